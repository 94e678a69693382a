// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* model.c - per-thread model: snapshots, interval deltas, percentiles */
#include <math.h>
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include "model.h"
#include "hist.h"

/* bucket_value - the value a bucket stands for: its middle, within [min, max] */
static __u64 bucket_value(int b, __u64 min, __u64 max)
{
	/* at most half a bucket (1/16) from the true value */
	__u64 mid = hist_bucket_low(b) + (hist_bucket_high(b) - hist_bucket_low(b)) / 2;

	if (b == HIST_BUCKETS - 1)
		mid = max;
	if (mid < min)
		mid = min;
	if (mid > max)
		mid = max;
	return mid;
}

/*
 * hist_quantiles - n ascending quantiles of cur - prev in one pass over the
 * buckets; 'total' is their sum (the metric's count): the collector's hot
 * loop, so no second pass to find it
 */
static void hist_quantiles(const __u32 *cur, const __u32 *prev, __u64 total, const double *q,
			   __u64 *out, int n, __u64 min, __u64 max)
{
	__u64 acc = 0, rank;
	int b = 0, i;

	for (i = 0; i < n; i++) {
		/* nearest rank, as a sorted array would give it */
		rank = (__u64)ceil(q[i] * (double)total);
		if (rank < 1)
			rank = 1;
		for (; b < HIST_BUCKETS; b++) {
			__u64 c = cur[b] - (prev ? prev[b] : 0);

			if (acc + c >= rank)
				break;
			acc += c;
		}
		out[i] = bucket_value(b < HIST_BUCKETS ? b : HIST_BUCKETS - 1, min, max);
	}
}

__u64 hist_percentile(const __u32 *cur, const __u32 *prev, double q, __u64 min,
		      __u64 max)
{
	__u64 total = 0, out;
	int b;

	for (b = 0; b < HIST_BUCKETS; b++)
		total += cur[b] - (prev ? prev[b] : 0);
	if (!total)
		return 0;
	hist_quantiles(cur, prev, total, &q, &out, 1, min, max);
	return out;
}

/* view_quantiles - p50, p99 and p99.9 of a view */
static void view_quantiles(const __u32 *cur, const __u32 *prev, struct metric_view *v)
{
	static const double q[3] = { 0.50, 0.99, 0.999 };
	__u64 out[3];

	hist_quantiles(cur, prev, v->count, q, out, 3, v->min, v->max);
	v->p50 = out[0];
	v->p99 = out[1];
	v->p999 = out[2];
}

void metric_view_life(const struct rtsup_metric_stats *s, struct metric_view *v)
{
	memset(v, 0, sizeof(*v));
	v->count = s->count;
	if (!s->count)
		return;
	v->min = s->min;
	v->max = s->max;
	v->mean = (double)s->sum / (double)s->count;
	v->ewma = (double)s->ewma / (1 << RTSUP_EWMA_SHIFT);
	view_quantiles(s->hist, NULL, v);
}

void metric_view_window(const struct rtsup_metric_stats *cur,
			const struct rtsup_metric_stats *prev, __u32 bank,
			struct metric_view *v)
{
	const struct rtsup_minmax *mm = &cur->win[bank & 1];

	if (!prev) {
		metric_view_life(cur, v);
		return;
	}
	memset(v, 0, sizeof(*v));
	v->count = cur->count - prev->count;
	if (!v->count)
		return;
	v->min = mm->min;
	v->max = mm->max;
	v->mean = (double)(cur->sum - prev->sum) / (double)v->count;
	v->ewma = (double)cur->ewma / (1 << RTSUP_EWMA_SHIFT);
	view_quantiles(cur->hist, prev->hist, v);
}

/* span_counters - counters of cur minus prev (prev may be NULL) */
static void span_counters(const struct rtsup_thread *c, const struct rtsup_thread *p,
			  struct span_view *s)
{
	static const struct rtsup_thread zero;
	int i;

	if (!p)
		p = &zero;
	s->cycles = c->cycles - p->cycles;
	s->misses = c->misses - p->misses;
	s->overruns = c->overruns - p->overruns;
	s->vol_cs = c->vol_cs - p->vol_cs;
	s->invol_cs = c->invol_cs - p->invol_cs;
	s->unseen_in = c->unseen_in - p->unseen_in;
	s->migrations = c->migrations - p->migrations;
	s->syscalls = c->syscalls - p->syscalls;
	s->signals = c->signals - p->signals;
	s->minflt = c->minflt - p->minflt;
	s->majflt = c->majflt - p->majflt;
	s->unsafe_total = 0;
	for (i = 0; i < RTSUP_U_NR; i++) {
		s->unsafe[i] = c->unsafe[i] - p->unsafe[i];
		s->unsafe_total += s->unsafe[i];
	}
}

void span_life(const struct rtsup_thread *t, struct span_view *s)
{
	int i;

	span_counters(t, NULL, s);
	for (i = 0; i < RTSUP_M_NR; i++)
		metric_view_life(&t->m[i], &s->m[i]);
}

void span_window(const struct rtsup_thread *cur, const struct rtsup_thread *prev,
		 __u32 bank, struct span_view *s)
{
	int i;

	/* stats restarted (first delimiter): the window starts from zero */
	if (prev && cur->resets != prev->resets)
		prev = NULL;
	span_counters(cur, prev, s);
	for (i = 0; i < RTSUP_M_NR; i++)
		metric_view_window(&cur->m[i], prev ? &prev->m[i] : NULL, bank, &s->m[i]);
}

void model_views(struct thread_model *tm, const struct rtsup_thread *t,
		 const struct rtsup_thread *prev, __u32 bank)
{
	span_window(t, prev, bank, &tm->win);
	span_life(t, &tm->life);
}

void model_set(struct thread_model *tm, const struct rtsup_thread *t, __u32 bank)
{
	model_views(tm, t, tm->cur.first_seen ? &tm->cur : NULL, bank);
	tm->cur = *t;
}

void model_idle(struct thread_model *tm)
{
	memset(&tm->win, 0, sizeof(tm->win));
}

/* find - binary search in the tid-sorted array */
static int find(const struct model *m, __u32 tid, int *pos)
{
	int lo = 0, hi = m->n;

	while (lo < hi) {
		int mid = (lo + hi) / 2;

		if (m->t[mid].tid == tid) {
			*pos = mid;
			return 1;
		}
		if (m->t[mid].tid < tid)
			lo = mid + 1;
		else
			hi = mid;
	}
	*pos = lo;
	return 0;
}

struct thread_model *model_get(struct model *m, __u32 tid, bool create)
{
	int pos;

	if (find(m, tid, &pos))
		return &m->t[pos];
	if (!create)
		return NULL;
	if (m->n == m->cap) {
		int cap = m->cap ? m->cap * 2 : 64;
		struct thread_model *t = realloc(m->t, cap * sizeof(*t));

		if (!t)
			return NULL;
		m->t = t;
		m->cap = cap;
		/*
		 * glibc raises its mmap threshold when a big block is freed, so the
		 * arrays outgrown on the way stay in the heap, free but resident:
		 * 4.9 MiB at 1000 threads. Growing is rare; give them back.
		 */
		malloc_trim(0);
	}
	memmove(&m->t[pos + 1], &m->t[pos], (m->n - pos) * sizeof(*m->t));
	m->n++;
	memset(&m->t[pos], 0, sizeof(m->t[pos]));
	m->t[pos].tid = tid;
	m->t[pos].policy = -1;
	return &m->t[pos];
}

void model_remove(struct model *m, __u32 tid)
{
	int pos;

	if (!find(m, tid, &pos))
		return;
	free(m->t[pos].snap);
	memmove(&m->t[pos], &m->t[pos + 1], (m->n - pos - 1) * sizeof(*m->t));
	m->n--;
}

static int cmp_u64(const void *a, const void *b)
{
	__u64 x = *(const __u64 *)a, y = *(const __u64 *)b;

	return x < y ? -1 : x > y;
}

void model_prune_dead(struct model *m, int keep)
{
	__u64 *seq, cut;
	int i, j, dead = 0;

	for (i = 0; i < m->n; i++) {
		struct thread_model *tm = &m->t[i];

		if (!tm->reported_exit)
			continue;
		if (!tm->dead_seq)
			tm->dead_seq = ++m->dead_seq;
		dead++;
	}
	if (dead <= keep)
		return;
	seq = malloc(dead * sizeof(*seq));
	if (!seq)
		return;
	for (i = 0, j = 0; i < m->n; i++)
		if (m->t[i].reported_exit)
			seq[j++] = m->t[i].dead_seq;
	qsort(seq, dead, sizeof(*seq), cmp_u64);
	cut = seq[dead - keep - 1];	/* the newest of the ones to drop */
	free(seq);
	for (i = 0, j = 0; i < m->n; i++) {
		if (m->t[i].reported_exit && m->t[i].dead_seq <= cut) {
			free(m->t[i].snap);
			m->forgotten++;
			continue;
		}
		if (i != j)
			m->t[j] = m->t[i];
		j++;
	}
	m->n = j;
}

void model_sys_set(struct thread_model *tm, int nr, __u64 total)
{
	int i;

	for (i = 0; i < tm->nsys; i++) {
		if (tm->sys[i].nr == nr) {
			tm->sys[i].total = total;
			return;
		}
	}
	if (tm->nsys == MODEL_MAX_SYS)
		return;
	tm->sys[tm->nsys].nr = nr;
	tm->sys[tm->nsys].total = total;
	tm->sys[tm->nsys].prev = 0;
	tm->nsys++;
}

void model_free(struct model *m)
{
	int i;

	for (i = 0; i < m->n; i++)
		free(m->t[i].snap);
	free(m->t);
	memset(m, 0, sizeof(*m));
}

const char *unsafe_reason_name(int reason)
{
	static const char *const names[RTSUP_U_NR] = {
		[RTSUP_U_SYSCALL] = "syscall",
		[RTSUP_U_MINFLT] = "minor_fault",
		[RTSUP_U_MAJFLT] = "major_fault",
		[RTSUP_U_BLOCK] = "block",
		[RTSUP_U_MIGRATE] = "migration",
	};

	return reason >= 0 && reason < RTSUP_U_NR ? names[reason] : "unknown";
}

const char *metric_name(int metric)
{
	static const char *const names[RTSUP_M_NR] = {
		[RTSUP_M_PERIOD] = "period_ns",
		[RTSUP_M_EXEC] = "exec_ns",
		[RTSUP_M_CPU] = "cpu_ns",
		[RTSUP_M_LATENCY] = "latency_ns",
	};

	return metric >= 0 && metric < RTSUP_M_NR ? names[metric] : "unknown";
}

const char *policy_name(int policy)
{
	switch (policy) {
	case 0: return "SCHED_OTHER";
	case 1: return "SCHED_FIFO";
	case 2: return "SCHED_RR";
	case 3: return "SCHED_BATCH";
	case 5: return "SCHED_IDLE";
	case 6: return "SCHED_DEADLINE";
	case 7: return "SCHED_EXT";
	default: return "-";
	}
}
