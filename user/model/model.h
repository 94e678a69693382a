/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * model.h - what userspace knows about each thread: the last snapshot
 * of its kernel entry and the numbers derived from it, per interval and
 * over its lifetime. Plain C, no kernel, so the unit tests cover it.
 */
#ifndef RTSUP_MODEL_H
#define RTSUP_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"
#include "judge/status.h"

/*
 * What the model adds to the kernel's buckets of a thread's metrics:
 * - the lifetime's counts are the kernel's of the last snapshot (cur: since
 *   the kernel last restarted the statistics, as the lifetime) plus 2^32
 *   each time a __u32 bucket wrapped (wraps: NULL until a first wrap, 49
 *   days at 1 kHz in one bucket), so they never wrap;
 * - the last interval's counts, for its percentiles and --hist-interval,
 *   kept for [wlo, whi] only (win[i][0] is bucket wlo[i]).
 * Every count outside [lo, hi] (lifetime) and [wlo, whi] (interval) is 0:
 * an interval touches a few of the 280 buckets, and the model's work per
 * thread is kept to those (empty: lo > hi). Read them with
 * model_life_counts and model_win_counts.
 */
struct life_hist {
	__u32 (*wraps)[HIST_BUCKETS];	/* [RTSUP_M_NR] */
	__u32 *win[RTSUP_M_NR];
	__u16 wcap[RTSUP_M_NR];
	__s16 lo[RTSUP_M_NR], hi[RTSUP_M_NR];
	__s16 wlo[RTSUP_M_NR], whi[RTSUP_M_NR];
};

/* One metric, in ns, over a window or a lifetime. */
struct metric_view {
	__u64 count;
	__u64 min;
	__u64 max;
	double mean;
	double ewma;
	__u64 p50;
	__u64 p99;
	__u64 p999;
};

/* Counters and metrics over one span (an interval or the lifetime). */
struct span_view {
	__u64 cycles;
	__u64 misses;
	__u64 overruns;
	__u64 vol_cs;
	__u64 invol_cs;
	__u64 unseen_in;	/* activations whose switch-in no hook saw */
	__u64 compat_sys;	/* 32-bit syscalls, not classified */
	__u64 migrations;
	__u64 syscalls;
	__u64 signals;
	__u64 minflt;
	__u64 majflt;
	__u64 unsafe[RTSUP_U_NR];
	__u64 unsafe_total;
	struct metric_view m[RTSUP_M_NR];
};

/* Unsafe syscalls of one thread, by number. */
struct sys_count {
	int nr;
	__u64 total;
	__u64 prev;	/* total at the end of the previous interval */
};

#define MODEL_MAX_SYS 32

struct thread_model {
	__u32 tid;
	__u32 tgid;
	char comm[RTSUP_COMM_LEN];
	int policy;		/* -1 when the thread is gone */
	int prio;
	char cpus[64];		/* allowed CPUs as a list, e.g. "0-3" */
	bool alive;
	bool reported_exit;
	__u64 seen_seq;		/* the sample whose read of the thread map found it last */
	/*
	 * Every interval reads or writes these of every thread, a parked one
	 * too: together in the first cache lines, not one line each across
	 * the model's 10 KiB
	 */
	bool judged;			/* supervised in an earlier interval */
	/* thread_copy_due's reader fields, for the reads the iterator has no say in */
	__u32 read_seen, read_again;
	struct life_hist *life_hist;	/* lifetime bucket counts, NULL until a snapshot */
	int nsys;
	char pcomm[RTSUP_COMM_LEN];	/* the process's name */
	__u64 cgroup_id;		/* the id it was read for (task iterator), 0 = none */
	__u64 attrs_seq;		/* the sample that read attrs, 0 = none yet */
	bool attrs_applied;		/* policy, cpus and cgroup are from attrs */
	bool task_gone;			/* its last read found no task */
	bool attrs_stale;		/* the policy hook saw a change since attrs was read */
	int rule;			/* index of the matching rule, -1 = defaults */
	__u32 rule_gen;			/* config generation 'rule' belongs to, 0 = none */
	__u32 cfg_gen;			/* config generation written to the kernel */
	bool cfg_in_kernel;		/* thread_cfg or stack_cfg may hold its tid */
	__u32 restarted_from;		/* tid of the dead instance it replaces */
	bool replaced;			/* a restarted instance took its place */
	bool was_rt;			/* it ran with an RT policy at some point */
	bool kthread;			/* a kernel thread (PF_KTHREAD) */
	bool level_changed;		/* st's level is not the interval before's */
	unsigned shown_key;		/* check_shown_key of st, 0: none (supervise.c) */
	enum level worst;		/* worst level ever reached */
	__u64 dead_seq;			/* order of death, set by model_prune_dead */
	bool win_idle;		/* win is empty (model_idle), as is life_hist's interval */
	bool cur_torn;		/* cur's buckets do not sum to its counts (snapshot_torn) */
	__u8 life_due;		/* metrics whose life percentiles wait (model_life_settle) */
	/*
	 * verdict of the last interval: its level and count of messages are
	 * read of every thread at every interval (the table, the service's
	 * status line), so on the head's page, not 8 KiB away on a third one
	 */
	struct status st;
	struct rtsup_thread cur;	/* the last snapshot of the kernel entry */
	/*
	 * Computed once per snapshot (model_set) for every check and sink:
	 * the interval (this snapshot minus the one before) and the lifetime.
	 * The lifetime's percentiles only when asked (model_life_settle).
	 */
	struct span_view win;
	struct span_view life;
	/* the top cause of its deadline misses (causes.h): interval, lifetime; "" = none */
	char why_win[160], why_life[160];
	struct rtsup_thread *snap;	/* replay only: cur at the last interval */
	struct sys_count sys[MODEL_MAX_SYS];
	char cgroup[256];		/* cgroup v2 path, "" if unknown */
	/* its task's attributes as the thread map's iterator last read them (threadread.h) */
	struct rtsup_task_attrs attrs;
};

struct model {
	struct thread_model **t;	/* by tid after model_sort (model_sorted) */
	/*
	 * t[i]->tid for i < nsorted: a search reads this array, not a cache
	 * line of ten models (a thousand lookups an interval)
	 */
	__u32 *tids;
	int n;
	int cap;
	int nsorted;			/* t[0..nsorted) by tid, then arrivals in their order */
	__u64 dead_seq;			/* last order of death handed out */
	__u64 forgotten;		/* exited threads dropped by model_prune_dead */
};

/*
 * New threads wait unsorted after the sorted ones, at most this many: an
 * insert in the middle moved half the array, and a storm of threads
 * arriving in hash-map order moved gigabytes (a 0.5 s interval took 10 s at
 * 10 000 threads a second). The array holds pointers, so a thread's model
 * (~10 KiB) never moves and a sort moves 8 bytes a thread: with the models
 * in the array, the sorts of a storm moved ~1 GB an interval.
 */
#define MODEL_TAIL_MAX 256

/* Exited threads kept for the summary; older ones are forgotten (weeks of churn). */
#define MODEL_KEEP_DEAD 1024

/* hist_percentile - q-quantile (0 < q <= 1) of cur - prev (prev may be NULL) */
__u64 hist_percentile(const __u32 *cur, const __u32 *prev, double q, __u64 min,
		      __u64 max);
/* hist_percentile64 - q-quantile of bucket counts h, values within [min, max] */
__u64 hist_percentile64(const __u64 *h, double q, __u64 min, __u64 max);
/* hist_delta - bucket counts cur - prev (prev may be NULL), modulo 2^32 */
void hist_delta(const __u32 *cur, const __u32 *prev, __u64 *out);

/*
 * metric_view_counts - a lifetime view whose percentiles come from the
 * bucket counts h (NULL: the kernel's own buckets)
 */
void metric_view_counts(const struct rtsup_metric_stats *s, const __u64 *h,
			struct metric_view *v);
/* metric_view_life - a metric over the thread's lifetime */
void metric_view_life(const struct rtsup_metric_stats *s, struct metric_view *v);
/*
 * metric_view_window - a metric over the last interval: the difference of
 * two snapshots; min/max come from the interval bank 'bank'.
 */
void metric_view_window(const struct rtsup_metric_stats *cur,
			const struct rtsup_metric_stats *prev, __u32 bank,
			struct metric_view *v);

/* span_life / span_window - counters and metrics of a thread */
void span_life(const struct rtsup_thread *t, struct span_view *s);
void span_window(const struct rtsup_thread *cur, const struct rtsup_thread *prev,
		 __u32 bank, struct span_view *s);

/*
 * model_set - a new snapshot of the thread's kernel entry; its interval
 * view is the change since the previous one (none yet: since the start).
 * False when it is the same bytes as the previous one (but the kernel's
 * attribution state, which the model does not keep: snapshot_bytes).
 */
bool model_set(struct thread_model *tm, const struct rtsup_thread *t, __u32 bank);
/*
 * model_takes_short - can tm take a short copy of its entry: one that
 * holds its fields but of its buckets only those between the lowest and
 * highest values of each metric's interval banks (metric_banks_range)?
 * Only after a whole snapshot that was not torn, with a lifetime of counts.
 */
bool model_takes_short(const struct thread_model *tm);
/*
 * model_set_sent - model_set from t, a short copy when sent: 1 moved, 0
 * the same, -1 when the model cannot take it and wants the entry whole,
 * nothing taken (statistics restarted since, buckets moved outside the
 * ones it holds: a copy taken while a hook wrote, a bank reset before it)
 */
int model_set_sent(struct thread_model *tm, const struct rtsup_thread *t, __u32 bank, bool sent);
/*
 * model_life_counts - metric m's lifetime bucket counts into h[*lo..*hi]
 * (every other count is 0, and h is not written there); false when the
 * model keeps none (no cycle yet, out of memory): the kernel's are it
 */
bool model_life_counts(const struct thread_model *tm, int m, __u64 *h, int *lo, int *hi);
/* model_win_counts - the same for the last interval's counts */
bool model_win_counts(const struct thread_model *tm, int m, __u64 *h, int *lo, int *hi);
/*
 * model_views - the interval (t minus prev, NULL: since the start) and
 * lifetime views; prev must be the t of the call before. A t equal to
 * prev (a parked thread) costs a compare, and returns false.
 */
bool model_views(struct thread_model *tm, const struct rtsup_thread *t,
		 const struct rtsup_thread *prev, __u32 bank);
/*
 * model_life_settle - tm's lifetime percentiles (life.m[].p50, p99, p999)
 * made right: model_set leaves them due, as most intervals nobody reads
 * them (the table and the checks read the interval's; walking each moved
 * metric's lifetime buckets was a tenth of the loop with 1000 threads
 * running). Their readers settle first: the lifetime checks, the JSON
 * "total", the summary, --hist. model_settle_all: every thread's.
 */
void model_life_settle(struct thread_model *tm);
void model_settle_all(struct model *m);
/* model_idle - no snapshot this interval: an empty interval view */
void model_idle(struct thread_model *tm);

/*
 * MODEL_HEAD_BYTES - the lines of a model every interval reads, a parked
 * thread's too: the fields before st, and st's level and count of messages
 * (its messages follow, read only when there are some)
 */
#define MODEL_HEAD_BYTES (offsetof(struct thread_model, st) + offsetof(struct status, msg))

/*
 * model_win_empty - tm's interval view is all zero (model_idle): a reader
 * of a parked thread's win need not fetch its lines, two pages past the
 * head. Only model.c writes win, and it clears win_idle first.
 */
static inline bool model_win_empty(const struct thread_model *tm)
{
	return tm->win_idle;
}

/* model_get - the thread's model, created (zeroed) when 'create' */
struct thread_model *model_get(struct model *m, __u32 tid, bool create);
/*
 * model_prefetch - ask the CPU for the lines of tm a snapshot reads and
 * writes (model_set), while the thread before it is taken: 1000 models of
 * 10 KiB each are out of the cache by the next interval, and each waited
 * for its misses one after the other
 */
void model_prefetch(const struct thread_model *tm);
/*
 * model_prefetch_kept - the same for a thread kept as it was (its entry
 * did not move): the few lines take_kept's pass reads, not the 32 a
 * snapshot reads (900 parked threads an interval)
 */
void model_prefetch_kept(const struct thread_model *tm);
/*
 * model_prefetch_spans - the same, one step later, for the lines only the
 * new entry t says: of each metric, the buckets between its interval
 * banks' lowest and highest values in tm's snapshot and in t
 * (metric_banks_range: what the comparison of model_set reads, ~50
 * buckets a running thread), and its lifetime's spans (life_hist). t's
 * first lines, which name them, asked for the step before (tm may be NULL)
 */
void model_prefetch_spans(const struct thread_model *tm, const struct rtsup_thread *t);
/* model_sort - every thread in tid order, for the outputs (pointers into t change) */
void model_sort(struct model *m);
/*
 * model_sorted - the invariant of the sorted part, which model_sort
 * restores: t[0..nsorted) strictly by tid, and tids[i] their tids
 */
bool model_sorted(const struct model *m);
/* model_remove - forget a thread */
void model_remove(struct model *m, __u32 tid);
/*
 * model_prune_dead - keep at most 'keep' threads that exited and were
 * reported (reported_exit), the most recent ones; count the others in
 * m->forgotten. Memory stays bounded however many threads come and go.
 */
void model_prune_dead(struct model *m, int keep);
/* model_sys_add - set the lifetime count of one unsafe syscall */
void model_sys_set(struct thread_model *tm, int nr, __u64 total);
void model_free(struct model *m);

/* unsafe_reason_name - JSON/table name of an unsafe reason */
const char *unsafe_reason_name(int reason);
/* metric_name - JSON name of a metric */
const char *metric_name(int metric);
/* policy_name - "SCHED_FIFO"... */
const char *policy_name(int policy);

#endif
