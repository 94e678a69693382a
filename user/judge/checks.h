/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * checks.h - the checks of the seed's OroMonitor, for threads and for the
 * supervisor itself. Each check reads the numbers of one component and adds
 * its messages to a status; none of them prints. Pure functions: the unit
 * tests feed them numbers.
 */
#ifndef RTSUP_CHECKS_H
#define RTSUP_CHECKS_H

#include <stdbool.h>
#include "config/config.h"
#include "model/model.h"
#include "judge/status.h"
#include "collect/selfsched.h"
#include "judge/overhead.h"

/* Check names: what each message of a verdict says it came from (docs/json.md). */
#define CHECK_EXCEPTION		"exception"
#define CHECK_SCHED		"scheduling"
#define CHECK_ABI		"abi"
#define CHECK_INIT		"initialization"
#define CHECK_STARVATION	"starvation"
#define CHECK_MISS		"deadline_miss"
#define CHECK_EXEC_NEAR		"exec_near_period"
#define CHECK_UNSAFE		"rt_unsafe"
#define CHECK_LATENCY		"latency"
#define CHECK_JITTER		"jitter"
#define CHECK_OVERHEAD		"overhead"
#define CHECK_LOSS		"loss"

/* Everything the checks know about one thread at the end of an interval. */
struct check_in {
	const struct span_view *win;	/* the last interval, NULL before the first */
	const struct span_view *life;
	const struct rule *rule;	/* effective rule (defaults + first match) */
	bool judged;			/* a program's RT thread or named by a rule */
	bool expect_run;		/* a rule names it: no cycle at all is a fault */
	bool kthread;			/* a kernel thread: judged only when a rule names it */
	bool alive;
	bool left_rt;			/* --rt let it go: it left RT (rtfollow.h) */
	int policy;
	int prio;
	__u64 now_ns;			/* CLOCK_MONOTONIC */
	__u64 first_seen_ns;
	__u64 last_cycle_ns;		/* start of the last finished cycle, 0 = none */
	__u64 nominal_ns;		/* period derived from absolute sleeps, 0 = none */
	bool exit_expected;		/* a normal end (the supervised command ended) */
	int exit_code;			/* task exit code: signal in bits 0-6, status in 8-15 */
	bool exit_mid_cycle;
	bool process_ended;		/* its process ended with it (exit_group, a fatal signal) */
	__u64 compat_sys;		/* 32-bit syscalls seen: not classified */
	__u32 restarted_from;		/* tid of the dead instance it replaces, 0 = none */
	const char *unsafe_names;	/* unsafe syscalls of the window, e.g. "mmap 1, munmap 1" */
	/* the top cause of the misses (model/causes.h), NULL = none known */
	const char *why_win, *why_life;
};

/* check_period - the period the checks use: configured, derived, or measured */
__u64 check_period(const struct check_in *in);
/* check_thread - run every check of a thread into 'out' (reset first) */
void check_thread(const struct check_in *in, struct status *out);
/*
 * check_shown_key - all check_thread reads of a thread it does not judge
 * (judged false): two such inputs of the same key give the same status, so
 * the supervisor keeps the last one (900 parked threads of a robot's
 * programs, checked again every interval). 0 for a judged thread: every
 * check runs.
 */
unsigned check_shown_key(bool judged, bool kthread, bool alive);

/* What the supervisor knows about itself. */
struct self_in {
	double overhead_pct;		/* our BPF programs' own run time, % of one CPU; <0 unknown */
	struct stats_window stats;	/* the window it was measured in (wall_ns 0: none) */
	__u64 lost_events;		/* ring buffer drops in the interval */
	__u64 untracked_threads;	/* threads the map could not hold, in total */
	struct self_span loop;		/* the main loop's CPU and run-queue wait, this interval */
	struct self_span loop_run;	/* the same since the start */
	const struct thresholds *th;
};

/* check_self - the supervisor's own status (overhead, losses) */
void check_self(const struct self_in *in, struct status *out);

#endif
