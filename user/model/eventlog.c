// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* eventlog.c - one interval's rare events: life events kept, floods folded */
#include <stdlib.h>
#include <string.h>
#include "model/eventlog.h"

/* The events of a thread's life: never folded, never crowded out. */
static const bool never_folded[] = {
	[RTSUP_EV_MISS] = false,
	[RTSUP_EV_UNSAFE] = false,
	[RTSUP_EV_EXIT] = true,
	[RTSUP_EV_NEW] = true,
	[RTSUP_EV_SIGNAL] = false,	/* a fatal one is among the flood's last */
};

bool eventlog_never_folded(__u32 type)
{
	/* an unknown type is kept: nothing is lost by showing it */
	return type >= sizeof(never_folded) / sizeof(never_folded[0]) || never_folded[type];
}

/* fold_kind - what tells two floods of one type apart */
static __u64 fold_kind(const struct rtsup_event *e)
{
	switch (e->type) {
	case RTSUP_EV_UNSAFE:
		/*
		 * one flood per reason, and per syscall for syscalls and for
		 * blocks (the one they wait in): a flood of futex waits must
		 * not hide the one block in a page fault
		 */
		return e->arg == RTSUP_U_SYSCALL || e->arg == RTSUP_U_BLOCK ?
			       (e->arg << 32) | (e->arg2 & 0xffffffff) : e->arg << 32;
	case RTSUP_EV_SIGNAL:
		return e->arg;
	case RTSUP_EV_MISS:
		/*
		 * one flood per cause kind: a flood of preemptions by noise
		 * must not hide the one miss that blocked on a mutex
		 */
		return e->cause.kind;
	}
	return 0;
}

static size_t fold_hash(__u32 tid, __u32 type, __u64 kind, size_t cap)
{
	__u64 h = ((__u64)tid * 0x9E3779B97F4A7C15ULL) ^ ((__u64)type << 56) ^
		  (kind * 0xC2B2AE3D27D4EB4FULL);

	return (h ^ (h >> 29)) & (cap - 1);
}

/* fold_slot - the flood of (tid, type, kind), a free slot if none; table not full */
static struct event_fold *fold_slot(struct event_fold *tab, size_t cap, __u32 tid,
				    __u32 type, __u64 kind)
{
	size_t i = fold_hash(tid, type, kind, cap);

	while (tab[i].seen && !(tab[i].tid == tid && tab[i].type == type && tab[i].kind == kind))
		i = (i + 1) & (cap - 1);
	return &tab[i];
}

/* fold_grow - double the table (at most half full); false without memory */
static bool fold_grow(struct eventlog *l)
{
	size_t cap = l->capfold ? l->capfold * 2 : 64, i;
	struct event_fold *tab = calloc(cap, sizeof(*tab));

	if (!tab)
		return false;
	for (i = 0; i < l->capfold; i++)
		if (l->fold[i].seen)
			*fold_slot(tab, cap, l->fold[i].tid, l->fold[i].type, l->fold[i].kind) =
				l->fold[i];
	free(l->fold);
	l->fold = tab;
	l->capfold = cap;
	return true;
}

/* keep - append to the kept events */
static bool keep(struct eventlog *l, const struct rtsup_event *e)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? l->cap * 2 : 256;
		struct rtsup_event *ev = realloc(l->ev, cap * sizeof(*ev));

		if (!ev)
			return false;
		l->ev = ev;
		l->cap = cap;
	}
	l->ev[l->n++] = *e;
	return true;
}

void eventlog_add(struct eventlog *l, const struct rtsup_event *e)
{
	struct event_fold *f;
	__u64 kind;

	l->total++;
	if (eventlog_never_folded(e->type)) {
		if (!keep(l, e))
			l->dropped++;
		return;
	}
	if ((l->nfold + 1) * 2 > l->capfold && !fold_grow(l)) {
		l->dropped++;
		return;
	}
	kind = fold_kind(e);
	f = fold_slot(l->fold, l->capfold, e->tid, e->type, kind);
	if (!f->seen) {
		l->nfold++;
		f->tid = e->tid;
		f->type = e->type;
		f->kind = kind;
		f->first_ts = e->ts;
		memcpy(f->comm, e->comm, sizeof(f->comm));
	}
	f->seen++;
	f->last_ts = e->ts;
	if (f->seen <= EVENTLOG_KEEP) {
		if (!keep(l, e))
			l->dropped++;
		return;
	}
	/* the ring holds the latest; the one it pushes out is folded */
	if (f->seen > 2 * EVENTLOG_KEEP) {
		f->folded++;
		l->folded++;
	}
	f->tail[(f->seen - EVENTLOG_KEEP - 1) % EVENTLOG_KEEP] = *e;
}

static int by_time(const void *a, const void *b)
{
	const struct rtsup_event *x = a, *y = b;

	return x->ts < y->ts ? -1 : x->ts > y->ts;
}

static int by_first(const void *a, const void *b)
{
	const struct event_fold *x = a, *y = b;

	return x->first_ts < y->first_ts ? -1 : x->first_ts > y->first_ts;
}

void eventlog_finish(struct eventlog *l)
{
	size_t i, j, ntail;

	l->nflood = 0;
	for (i = 0; i < l->capfold; i++) {
		struct event_fold *f = &l->fold[i];

		if (!f->seen)
			continue;
		ntail = f->seen > EVENTLOG_KEEP ? f->seen - EVENTLOG_KEEP : 0;
		if (ntail > EVENTLOG_KEEP)
			ntail = EVENTLOG_KEEP;
		for (j = 0; j < ntail; j++)
			if (!keep(l, &f->tail[j])) {
				l->dropped++;
			}
		if (f->folded)
			l->fold[l->nflood++] = *f;
	}
	/* the table is spent: what is left past nflood is forgotten */
	for (i = l->nflood; i < l->capfold; i++)
		memset(&l->fold[i], 0, sizeof(l->fold[i]));
	l->nfold = 0;
	/* qsort wants an array even for none (UBSan: nonnull), and ev is NULL until the first */
	if (l->n)
		qsort(l->ev, l->n, sizeof(*l->ev), by_time);
	if (l->nflood)
		qsort(l->fold, l->nflood, sizeof(*l->fold), by_first);
}

void eventlog_clear(struct eventlog *l)
{
	if (l->fold)
		memset(l->fold, 0, l->capfold * sizeof(*l->fold));
	l->n = 0;
	l->nfold = 0;
	l->nflood = 0;
	l->total = 0;
	l->folded = 0;
	l->dropped = 0;
}

void eventlog_free(struct eventlog *l)
{
	free(l->ev);
	free(l->fold);
	memset(l, 0, sizeof(*l));
}
