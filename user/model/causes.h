/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * causes.h - deadline misses grouped by cause: per target thread, by kind
 * (include/cause.h) and culprit, with the count and the time of the
 * winning part. Fed with every miss before the event log folds floods, so
 * the groups count every miss; one table per interval, one for the run.
 */
#ifndef RTSUP_CAUSES_H
#define RTSUP_CAUSES_H

#include <stddef.h>
#include "rtsup.h"

struct model;

struct cause_group {
	__u32 tid;		/* the target thread */
	__u32 kind;		/* enum rtsup_cause_kind */
	struct rtsup_who who;	/* the culprit; tid 0 and no name: none */
	__u32 flags;		/* RTSUP_CAUSE_F_* of any of its misses */
	__u32 after;		/* a backlog: the kind of the late cycle before (rtsup_cause) */
	__u64 count;
	__u64 total_ns;		/* the winning parts, summed */
	__u64 max_ns;
};

/*
 * The run's table holds a group per thread and culprit: thousands on a
 * noisy robot with many threads. A miss finds its group through 'index'
 * (open addressing on the thread, kind and culprit; positions in g, + 1),
 * not a walk of them all; causes_of searches the sorted table.
 */
struct causes {
	struct cause_group *g;
	size_t n, cap;
	__u32 *index;		/* 0: empty; else a position in g + 1 */
	size_t index_cap;	/* a power of 2, at least twice n (causes.c, index_due) */
	__u64 dropped;		/* misses not grouped for want of memory */
};

/* cause_kind_name - "timer", "wait", ... as in JSON */
const char *cause_kind_name(__u32 kind);
/* cause_who_text - "noise-hog[812] FIFO/99", "the idle task"; self: our own tgid */
void cause_who_text(char *buf, size_t len, const struct rtsup_who *w, __u32 self);
/* causes_group_text - a group as causes_text says one of its misses, with max_ns */
void causes_group_text(char *buf, size_t len, const struct cause_group *g, __u32 self);
/* mig_why_name - why a thread migrated (enum rtsup_mig_why): "affinity"... */
const char *mig_why_name(__u32 why);
/*
 * unsafe_event_syscall - the syscall an RT-unsafe event names: the one made
 * (reason syscall) or the one a block waits in (block: its number + 1 in
 * arg2, 0 outside any or unknown); NULL when none
 */
const char *unsafe_event_syscall(const struct rtsup_event *e);
/* causes_add - one miss of thread tid with its cause */
void causes_add(struct causes *cs, __u32 tid, const struct rtsup_cause *c);
/* causes_sort - by thread, then longest total first */
void causes_sort(struct causes *cs);
/*
 * causes_of - the first group of thread tid after causes_sort (a binary
 * search), NULL if none; *n of them
 */
const struct cause_group *causes_of(const struct causes *cs, __u32 tid, size_t *n);
/* causes_text - one readable cause: "waited 3.1 ms behind noise-hog[812] FIFO/99" */
void causes_text(char *buf, size_t len, __u32 kind, __u32 flags, __u64 ns,
		 const struct rtsup_who *who, const struct rtsup_cause *detail, __u32 self);
/*
 * causes_to_model - each thread's top cause (longest total) as a short text
 * for the checks: "28 caused by why-hog[667] FIFO/60 (wait, 3.1 ms max)";
 * after causes_sort. Walks the groups and finds their threads, not the
 * other way round (a thousand threads times the run's groups, each interval).
 */
void causes_to_model(const struct causes *win, const struct causes *life, struct model *m);
void causes_clear(struct causes *cs);
void causes_free(struct causes *cs);

#endif
