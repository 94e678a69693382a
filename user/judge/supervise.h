/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * supervise.h - model -> checks -> verdicts: once per interval it gives every
 * thread its rule and its status, judges the supervisor itself, logs level
 * changes and keeps the list of violations for the final summary.
 */
#ifndef RTSUP_SUPERVISE_H
#define RTSUP_SUPERVISE_H

#include <stdbool.h>
#include "model/canmodel.h"
#include "judge/checks.h"
#include "judge/health.h"
#include "config/config.h"
#include "model/model.h"
#include "judge/status.h"

/* One WARN or ERROR verdict: when, who, what. */
struct violation {
	__u64 mono_ns;
	char component[48];
	enum level level;
	char what[400];
	int nfact;
	struct status_fact fact[STATUS_MAX_MSGS];	/* per message: check, level, counts */
	char text[STATUS_MAX_MSGS][STATUS_MSG_LEN];
};

#define SUPERVISE_MAX_VIOLATIONS 1000

/* One level change, for a sink that reacts to it (actions.c). */
struct level_change {
	const char *component;
	enum level from, to;
	__u64 mono_ns;
	const char *when;		/* wall-clock time, ISO 8601 UTC */
	const struct status *st;	/* the new verdict and its messages */
	__u32 tid, pid;			/* of a thread; 0 for other components */
};

struct supervisor {
	struct config cfg;
	__u32 gen;			/* bumped on every (re)load */
	bool cmd_mode;			/* -- CMD: a thread's normal exit is expected */
	bool json;			/* level changes as JSON lines on stdout too */
	struct status self;		/* the supervisor's own component */
	enum level self_worst;
	struct violation *v;
	int nv;
	__u64 v_dropped;
	__s64 real_off;			/* CLOCK_REALTIME - CLOCK_MONOTONIC, for messages */
	struct can_model *can;		/* the CAN buses, NULL without --can */
	__u64 now;			/* time of the verdicts being made */
	double overhead_pct;		/* last sampled BPF overhead, % of a CPU; <0 unknown */
	struct stats_window stats;	/* the window it was measured in (overhead.h) */
	struct self_span loop;		/* the main loop's own time, this interval */
	struct self_span loop_run;	/* the same since the start */
	struct health health;		/* rtsup-trace's own, for the reports (health.h) */
	/* where level changes go; stderr by default, the journal under systemd */
	void (*log)(const char *component, enum level from, enum level to, const char *line);
	/* every level change, after it is logged; NULL = none */
	void (*on_change)(void *ctx, const struct level_change *c);
	void *on_change_ctx;
};

/* supervise_init - take ownership of a loaded configuration */
void supervise_init(struct supervisor *s, struct config *cfg);
/* supervise_reload - swap in a new configuration; threads are matched again */
void supervise_reload(struct supervisor *s, struct config *cfg);
/* supervise_rule - the effective rule of a thread (after supervise_interval) */
const struct rule *supervise_rule(const struct supervisor *s, const struct thread_model *tm);
/* supervise_interval - judge every thread and the supervisor at 'now' */
void supervise_interval(struct supervisor *s, struct model *m, __u32 bank,
			const struct self_in *self, __u64 now);
/* supervise_can - judge the CAN components at 'now', interval_s long */
void supervise_can(struct supervisor *s, __u64 now, double interval_s);
/* supervise_worst - the worst level any component reached */
enum level supervise_worst(const struct supervisor *s, const struct model *m);
/* component_name - "comm[tid]" */
void component_name(const struct thread_model *tm, char *buf, size_t len);
void supervise_free(struct supervisor *s);

#endif
