/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * eventlog.h - one interval's rare events, as the sinks show them. Every
 * event of a thread's life (new, exit) is kept, whatever else happens; a
 * flood of one kind for one thread (deadline misses, one unsafe reason, one
 * signal) keeps its first and last EVENTLOG_KEEP events and counts the rest
 * as folded. So ten thousand misses never push a thread's exit out.
 */
#ifndef RTSUP_EVENTLOG_H
#define RTSUP_EVENTLOG_H

#include <stdbool.h>
#include <stddef.h>
#include "rtsup.h"

#define EVENTLOG_KEEP 3		/* kept at each end of a flood */

/* A flood: the events of one kind for one thread in the interval. */
struct event_fold {
	__u32 tid;
	__u32 type;
	__u64 kind;		/* what else tells the kind apart: reason, signal */
	__u64 seen;		/* events of this kind in the interval */
	__u64 folded;		/* of which neither first nor last: not kept */
	__u64 first_ts, last_ts;
	struct rtsup_event tail[EVENTLOG_KEEP];	/* the latest, a ring */
	char comm[RTSUP_COMM_LEN];
};

struct eventlog {
	struct rtsup_event *ev;	/* kept events; in time order after eventlog_finish */
	size_t n, cap;
	struct event_fold *fold;	/* open-addressed by (tid, type, kind) */
	size_t nfold, capfold;
	size_t nflood;		/* after eventlog_finish: floods that folded, first in 'fold' */
	__u64 total;		/* every event of the interval */
	__u64 folded;		/* counted, not kept */
	__u64 dropped;		/* not kept for want of memory (counted, never silent) */
};

/* eventlog_never_folded - is this event type part of a thread's life? (the table) */
bool eventlog_never_folded(__u32 type);
/* eventlog_add - take one event (comm already sanitized) */
void eventlog_add(struct eventlog *l, const struct rtsup_event *e);
/*
 * eventlog_finish - the floods' last events in, everything in time order,
 * and the floods that folded anything first in 'fold' (nflood of them)
 */
void eventlog_finish(struct eventlog *l);
/* eventlog_clear - a new interval */
void eventlog_clear(struct eventlog *l);
void eventlog_free(struct eventlog *l);

#endif
