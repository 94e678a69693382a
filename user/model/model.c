// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* model.c - per-thread model: snapshots, interval deltas, percentiles */
#include <math.h>
#include <malloc.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include "model/model.h"
#include "hist.h"
#include "stats.h"

/* clamp_bucket - the part [*lo, *hi] of bucket b inside [min, max]; false if none */
static bool clamp_bucket(int b, __u64 min, __u64 max, __u64 *lo, __u64 *hi)
{
	*lo = hist_bucket_low(b);
	*hi = hist_bucket_high(b);
	if (*lo < min)
		*lo = min;
	if (*hi > max)
		*hi = max;
	return *lo <= *hi;
}

/*
 * Where the values of a bucket lie, for percentiles. A bucket is 1/8 to
 * 1/16 of its power of two wide, so its midpoint can be 6 % off (a steady
 * 5333 us period read 5505 us). We interpolate instead: the c values of the
 * bucket are taken as spread evenly over [lo, hi], the part of the bucket
 * inside [min, max]; exact for a bucket of one value, within 2 % for
 * distributions smooth at a bucket's scale. When the values pile up at one
 * end (a steady period with jitter far smaller than the bucket), the
 * metric's sum tells where: the bucket's own mean is the sum minus what the
 * other buckets hold, known within the sum of their half widths. When that
 * is sharp enough, [lo, hi] shrinks to the span centred on that mean.
 */
struct hist_pre {
	double sum;	/* the metric's sum, < 0: unknown */
	double mid;	/* sum over buckets of count * middle of [lo, hi] */
	double err;	/* sum over buckets of count * half of [lo, hi] */
};

/* hist_pre_scan - the pass over the buckets [b0, b1] that the sum needs */
static void hist_pre_scan(struct hist_pre *p, const __u64 *h, int b0, int b1, __u64 min,
			  __u64 max)
{
	__u64 lo, hi;
	int b;

	p->mid = p->err = 0;
	if (p->sum < 0)
		return;
	for (b = b0; b <= b1; b++) {
		if (!h[b] || !clamp_bucket(b, min, max, &lo, &hi))
			continue;
		p->mid += (double)h[b] * ((double)lo + (double)(hi - lo) / 2);
		p->err += (double)h[b] * (double)(hi - lo) / 2;
	}
}

/* bucket_rank_value - the k-th (1-based) of the c values in bucket b */
static __u64 bucket_rank_value(const struct hist_pre *p, int b, __u64 k, __u64 c,
			       __u64 min, __u64 max)
{
	double lo, hi, mean, err, hs;
	__u64 l, h;

	if (!clamp_bucket(b, min, max, &l, &h))
		return l > max ? max : min;	/* a torn read */
	lo = (double)l;
	hi = (double)h;
	if (p->sum >= 0 && hi > lo) {
		/* this bucket's mean, and how far off it may be */
		mean = (p->sum - (p->mid - (double)c * (lo + (hi - lo) / 2))) / (double)c;
		err = (p->err - (double)c * (hi - lo) / 2) / (double)c;
		if (err * 8 < hi - lo && mean >= lo && mean <= hi) {
			hs = mean - lo < hi - mean ? mean - lo : hi - mean;
			hs += err;
			if (mean - hs > lo)
				lo = mean - hs;
			if (mean + hs < hi)
				hi = mean + hs;
		}
	}
	return (__u64)(lo + (hi - lo) * ((double)k - 0.5) / (double)c + 0.5);
}

/*
 * hist_quantiles - n ascending quantiles of the counts h in one pass over
 * the buckets (and one more when the sum is known, sum < 0: unknown);
 * 'total' is their sum (the metric's count). Only [b0, b1] is read: every
 * count outside it is 0 (h may be unset there).
 */
static void hist_quantiles(const __u64 *h, int b0, int b1, __u64 total, double sum,
			   const double *q, __u64 *out, int n, __u64 min, __u64 max)
{
	struct hist_pre pre = { .sum = sum };
	__u64 acc = 0, rank;
	int b = b0, i;

	hist_pre_scan(&pre, h, b0, b1, min, max);
	for (i = 0; i < n; i++) {
		/* nearest rank, as a sorted array would give it */
		rank = (__u64)ceil(q[i] * (double)total);
		if (rank < 1)
			rank = 1;
		if (rank >= total) {	/* the last value is the max, exactly */
			out[i] = max;
			continue;
		}
		for (; b <= b1; b++) {
			if (acc + h[b] >= rank)
				break;
			acc += h[b];
		}
		if (b > b1) {	/* counts short of total: a torn read */
			out[i] = max;
			continue;
		}
		out[i] = rank == 1 ? min : bucket_rank_value(&pre, b, rank - acc, h[b], min, max);
	}
}

/* delta_in - hist_delta over [lo, hi] only */
static void delta_in(const __u32 *cur, const __u32 *prev, int lo, int hi, __u64 *out)
{
	int b;

	/* u32 arithmetic: right modulo 2^32 when a bucket wrapped in between */
	for (b = lo; b <= hi; b++)
		out[b] = (__u32)(cur[b] - (prev ? prev[b] : 0));
}

void hist_delta(const __u32 *cur, const __u32 *prev, __u64 *out)
{
	delta_in(cur, prev, 0, HIST_BUCKETS - 1, out);
}

#define DELTA_BLOCK 8

/* same_block - DELTA_BLOCK counts of a equal those of b; no branch inside */
static bool same_block(const __u32 *a, const __u32 *b)
{
	__u32 x = 0;
	int k;

	for (k = 0; k < DELTA_BLOCK; k++)
		x |= a[k] ^ b[k];
	return !x;
}

/*
 * delta_within - the buckets of [a, b] where cur and prev (NULL: zero)
 * differ lie in [*lo, *hi] (empty: *lo > *hi). Scanned from both ends: an
 * interval's values fill a few neighbouring buckets, so this is about one
 * compare a bucket, and what follows works on the few in between.
 */
static void delta_within(const __u32 *cur, const __u32 *prev, int a, int b, int *lo, int *hi)
{
	static const __u32 zero[HIST_BUCKETS];

	if (!prev)
		prev = zero;
	b++;	/* past the end, for the blocks */
	/* whole blocks first: a compare the compiler makes one vector op */
	while (a + DELTA_BLOCK <= b && same_block(cur + a, prev + a))
		a += DELTA_BLOCK;
	while (b - DELTA_BLOCK >= a && same_block(cur + b - DELTA_BLOCK, prev + b - DELTA_BLOCK))
		b -= DELTA_BLOCK;
	b--;
	while (a <= b && cur[a] == prev[a])
		a++;
	while (b > a && cur[b] == prev[b])
		b--;
	*lo = a;
	*hi = b;
}

/* delta_range - delta_within over every bucket */
static void delta_range(const __u32 *cur, const __u32 *prev, int *lo, int *hi)
{
	delta_within(cur, prev, 0, HIST_BUCKETS - 1, lo, hi);
}

/* moved_by - the values buckets [a, b] of cur gained since base (modulo 2^32, as delta_in) */
static __u64 moved_by(const struct rtsup_metric_stats *cur, const struct rtsup_metric_stats *base,
		      int a, int b)
{
	__u64 n = 0;
	int k;

	for (k = a; k <= b; k++)
		n += (__u32)(cur->hist[k] - base->hist[k]);
	return n;
}

/*
 * moved_range - delta_range of metric cur since base (NULL: since zero),
 * mostly without reading all of its buckets. Since the last snapshot,
 * values went into the bank of the interval that ended and the one that
 * began (rtsup.h, "Interval windows"): between their lowest and highest
 * buckets. That holds when the buckets there moved by as many values as
 * the count did; when not (a copy taken while a hook wrote, a bank reset
 * since), every bucket is compared as before. A short copy (sent: it holds
 * only those buckets) has no other bucket to compare: false then, the
 * caller wants the entry whole.
 */
static bool moved_range(const struct rtsup_metric_stats *cur,
			const struct rtsup_metric_stats *base, bool sent, int *lo, int *hi)
{
	int a, b;

	if (!base) {
		delta_range(cur->hist, NULL, lo, hi);
		return true;
	}
	metric_banks_range(cur, &a, &b);
	if (moved_by(cur, base, a, b) != cur->count - base->count) {
		if (sent)
			return false;
		delta_range(cur->hist, base->hist, lo, hi);
		return true;
	}
	delta_within(cur->hist, base->hist, a, b, lo, hi);
	return true;
}

/*
 * snapshot_torn - a copy of an entry taken while a hook wrote it: a
 * metric's buckets do not sum to its count (metric_add moves both, and
 * they wrap alike modulo 2^32). A short copy after it would keep the
 * bucket the hook had yet to write out of the snapshot for good: the
 * next copy is whole (model_takes_short).
 */
static bool snapshot_torn(const struct rtsup_thread *t)
{
	int i, b;

	for (i = 0; i < RTSUP_M_NR; i++) {
		__u32 n = 0;

		for (b = 0; b < HIST_BUCKETS; b++)
			n += t->m[i].hist[b];
		if (n != (__u32)t->m[i].count)
			return true;
	}
	return false;
}

/* nonzero_range - the buckets of h that are not 0 lie in [*lo, *hi] */
static void nonzero_range(const __u64 *h, int *lo, int *hi)
{
	int a = 0, b = HIST_BUCKETS - 1;

	while (a <= b && !h[a])
		a++;
	while (b > a && !h[b])
		b--;
	*lo = a;
	*hi = b;
}

__u64 hist_percentile(const __u32 *cur, const __u32 *prev, double q, __u64 min,
		      __u64 max)
{
	__u64 h[HIST_BUCKETS];

	hist_delta(cur, prev, h);
	return hist_percentile64(h, q, min, max);
}

__u64 hist_percentile64(const __u64 *h, double q, __u64 min, __u64 max)
{
	__u64 total = 0, out;
	int b;

	for (b = 0; b < HIST_BUCKETS; b++)
		total += h[b];
	if (!total)
		return 0;
	hist_quantiles(h, 0, HIST_BUCKETS - 1, total, -1, &q, &out, 1, min, max);
	return out;
}

/* view_quantiles - p50, p99 and p99.9 of a view; sum: of its values in [b0, b1] */
static void view_quantiles(const __u64 *h, int b0, int b1, __u64 sum, struct metric_view *v)
{
	static const double q[3] = { 0.50, 0.99, 0.999 };
	__u64 out[3];

	hist_quantiles(h, b0, b1, v->count, (double)sum, q, out, 3, v->min, v->max);
	v->p50 = out[0];
	v->p99 = out[1];
	v->p999 = out[2];
}

/* view_scalars - a view of s without its percentiles (0) */
static void view_scalars(const struct rtsup_metric_stats *s, struct metric_view *v)
{
	memset(v, 0, sizeof(*v));
	v->count = s->count;
	if (!s->count)
		return;
	v->min = s->min;
	v->max = s->max;
	v->mean = (double)s->sum / (double)s->count;
	v->ewma = (double)s->ewma / (1 << RTSUP_EWMA_SHIFT);
}

/* view_counts - metric_view_counts with h's non-zero buckets in [lo, hi] */
static void view_counts(const struct rtsup_metric_stats *s, const __u64 *h, int lo, int hi,
			struct metric_view *v)
{
	view_scalars(s, v);
	if (!s->count)
		return;
	view_quantiles(h, lo, hi, s->sum, v);
}

void metric_view_counts(const struct rtsup_metric_stats *s, const __u64 *h,
			     struct metric_view *v)
{
	__u64 tmp[HIST_BUCKETS];
	int lo, hi;

	if (h) {
		nonzero_range(h, &lo, &hi);
	} else {
		delta_range(s->hist, NULL, &lo, &hi);
		delta_in(s->hist, NULL, lo, hi, tmp);
		h = tmp;
	}
	view_counts(s, h, lo, hi, v);
}

void metric_view_life(const struct rtsup_metric_stats *s, struct metric_view *v)
{
	metric_view_counts(s, NULL, v);
}

/* window_counts - metric_view_window from the interval's counts h, non-zero in [lo, hi] */
static void window_counts(const struct rtsup_metric_stats *cur,
			  const struct rtsup_metric_stats *prev, __u32 bank, const __u64 *h,
			  int lo, int hi, struct metric_view *v)
{
	const struct rtsup_minmax *mm = &cur->win[RTSUP_BANK(bank)];

	if (!prev) {	/* since zero: the kernel's lifetime */
		view_counts(cur, h, lo, hi, v);
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
	view_quantiles(h, lo, hi, cur->sum - prev->sum, v);
}

void metric_view_window(const struct rtsup_metric_stats *cur,
			const struct rtsup_metric_stats *prev, __u32 bank,
			struct metric_view *v)
{
	__u64 h[HIST_BUCKETS];
	int lo, hi;

	delta_range(cur->hist, prev ? prev->hist : NULL, &lo, &hi);
	delta_in(cur->hist, prev ? prev->hist : NULL, lo, hi, h);
	window_counts(cur, prev, bank, h, lo, hi, v);
}

/*
 * snapshot_base - what an interval of cur is measured from: the previous
 * snapshot, or nothing (since zero) when the kernel restarted the thread's
 * statistics in between (first delimiter, settled period, exec: resets)
 */
static const struct rtsup_thread *snapshot_base(const struct rtsup_thread *cur,
						const struct rtsup_thread *prev)
{
	return prev && cur->resets == prev->resets ? prev : NULL;
}

/*
 * snapshot_bytes - the bytes of a snapshot the model reads: all but why,
 * the kernel's own state for cause attribution (cause.h), whose findings
 * come by the ring. 760 bytes a running thread an interval not copied, and
 * a change there alone is no change of the thread (model_views_spans).
 */
static size_t snapshot_bytes(void)
{
	return offsetof(struct rtsup_thread, why);
}

/* snapshot_bytes and snapshot_take_moved leave out why alone: it is the last field */
_Static_assert(offsetof(struct rtsup_thread, why) + sizeof(struct rtsup_why) ==
	       sizeof(struct rtsup_thread), "a field after why: snapshot_bytes misses it");

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
	s->compat_sys = c->compat_sys - p->compat_sys;
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

	prev = snapshot_base(cur, prev);
	span_counters(cur, prev, s);
	for (i = 0; i < RTSUP_M_NR; i++)
		metric_view_window(&cur->m[i], prev ? &prev->m[i] : NULL, bank, &s->m[i]);
}

/* win_clear - the last interval's counts gone: every span empty */
static void win_clear(struct life_hist *l)
{
	int i;

	for (i = 0; i < RTSUP_M_NR; i++) {
		l->wlo[i] = HIST_BUCKETS;
		l->whi[i] = -1;
	}
}

/* life_reset - every count 0: no wrap, empty spans (the interval buffers stay) */
static void life_reset(struct life_hist *l)
{
	int i;

	free(l->wraps);
	l->wraps = NULL;
	for (i = 0; i < RTSUP_M_NR; i++) {
		l->lo[i] = HIST_BUCKETS;
		l->hi[i] = -1;
	}
	win_clear(l);
}

static void life_free(struct life_hist *l)
{
	int i;

	if (!l)
		return;
	free(l->wraps);
	for (i = 0; i < RTSUP_M_NR; i++)
		free(l->win[i]);
	free(l);
}

/* win_room - room for n interval counts of metric i; -1 when out of memory */
static int win_room(struct life_hist *l, int i, int n)
{
	/* 8 at least: a thread's interval moves within a few buckets */
	int cap = n < 8 ? 8 : n;
	__u32 *w;

	if (n <= l->wcap[i])
		return 0;
	w = realloc(l->win[i], (size_t)cap * sizeof(*w));
	if (!w)
		return -1;
	l->win[i] = w;
	l->wcap[i] = (__u16)cap;
	return 0;
}

/* count_wrap - bucket b of metric i wrapped; lost when out of memory (said above) */
static void count_wrap(struct life_hist *l, int i, int b)
{
	if (!l->wraps)
		l->wraps = calloc(RTSUP_M_NR, sizeof(*l->wraps));
	if (l->wraps)
		l->wraps[i][b]++;
}

/* life_counts - the lifetime's counts of metric i over its span, kern: the snapshot's */
static void life_counts(const struct life_hist *l, int i, const __u32 *kern, __u64 *h)
{
	int b;

	for (b = l->lo[i]; b <= l->hi[i]; b++)
		h[b] = (l->wraps ? (__u64)l->wraps[i][b] << 32 : 0) | kern[b];
}

/*
 * life_add - the interval's counts (t minus prev), and the lifetime's span
 * and wraps. The kernel's __u32 buckets wrap after 2^32 values (49 days at
 * 1 kHz in one bucket); a difference of two snapshots is right modulo 2^32
 * as long as an interval holds fewer than 2^32 values per bucket, and a
 * count below the last one is a wrap (the kernel only adds, until a
 * restart, which has no prev). Returns -1 when there is none: a thread
 * without cycles has empty buckets and needs no memory, and when out of
 * memory the kernel's buckets are used (a wrap in that interval is lost).
 * A short copy t (sent: model_views_spans checked that prev is its base
 * and the lifetime is there) whose buckets moved outside the ones it
 * holds: -2, nothing counted.
 */
static int life_add(struct thread_model *tm, const struct rtsup_thread *t,
		    const struct rtsup_thread *prev, bool sent)
{
	struct life_hist *l = tm->life_hist;
	int lo[RTSUP_M_NR], hi[RTSUP_M_NR], i, b;
	bool fresh = !l;

	if (!l && !t->cycles)
		return -1;
	if (!l) {
		l = tm->life_hist = calloc(1, sizeof(*l));
		if (!l)
			return -1;
		life_reset(l);
	}
	/* the kernel dropped the start-up statistics: so does the lifetime */
	prev = snapshot_base(t, prev);
	if (!prev)
		life_reset(l);
	/* a new lifetime spans all the snapshot holds, counted before this one too */
	for (i = 0; fresh && prev && i < RTSUP_M_NR; i++) {
		delta_range(t->m[i].hist, NULL, &lo[i], &hi[i]);
		l->lo[i] = (__s16)lo[i];
		l->hi[i] = (__s16)hi[i];
	}
	/* no interval until it is written; then where each metric moved, and room */
	win_clear(l);
	for (i = 0; i < RTSUP_M_NR; i++) {
		if (!moved_range(&t->m[i], prev ? &prev->m[i] : NULL, sent, &lo[i], &hi[i]))
			return -2;
		if (lo[i] <= hi[i] && win_room(l, i, hi[i] - lo[i] + 1))
			return -1;
	}
	for (i = 0; i < RTSUP_M_NR; i++) {
		const __u32 *c = t->m[i].hist, *p = prev ? prev->m[i].hist : NULL;

		if (lo[i] > hi[i])
			continue;
		for (b = lo[i]; b <= hi[i]; b++) {
			l->win[i][b - lo[i]] = c[b] - (p ? p[b] : 0);	/* modulo 2^32 */
			if (p && c[b] < p[b])
				count_wrap(l, i, b);
		}
		l->wlo[i] = (__s16)lo[i];
		l->whi[i] = (__s16)hi[i];
		if (lo[i] < l->lo[i])
			l->lo[i] = (__s16)lo[i];
		if (hi[i] > l->hi[i])
			l->hi[i] = (__s16)hi[i];
	}
	return 0;
}

bool model_life_counts(const struct thread_model *tm, int m, __u64 *h, int *lo, int *hi)
{
	const struct life_hist *l = tm->life_hist;

	if (!l)
		return false;
	*lo = l->lo[m];
	*hi = l->hi[m];
	life_counts(l, m, tm->cur.m[m].hist, h);
	return true;
}

bool model_win_counts(const struct thread_model *tm, int m, __u64 *h, int *lo, int *hi)
{
	const struct life_hist *l = tm->life_hist;
	int b;

	if (!l)
		return false;
	*lo = l->wlo[m];
	*hi = l->whi[m];
	for (b = *lo; b <= *hi; b++)
		h[b] = l->win[m][b - *lo];
	return true;
}

/*
 * life_view_kept - the lifetime view of metric i is the one the last call
 * computed: its inputs did not move (the scalars the view reads, and no
 * bucket: life_add just wrote the interval's span). An idle thread's
 * lifetime percentiles are not walked again every interval.
 */
static bool life_view_kept(const struct life_hist *l, const struct rtsup_metric_stats *cur,
			   const struct rtsup_metric_stats *base, int i)
{
	return l->wlo[i] > l->whi[i] && cur->count == base->count && cur->sum == base->sum &&
	       cur->min == base->min && cur->max == base->max && cur->ewma == base->ewma;
}

/*
 * sent_same - short copy t holds the same bytes as prev where it holds any
 * (the buckets it does not hold are prev's, life_add checks that)
 */
static bool sent_same(const struct rtsup_thread *prev, const struct rtsup_thread *t)
{
	int i, a, b;

	if (memcmp(prev, t, offsetof(struct rtsup_thread, m)))
		return false;
	for (i = 0; i < RTSUP_M_NR; i++) {
		if (memcmp(&prev->m[i], &t->m[i], offsetof(struct rtsup_metric_stats, hist)))
			return false;
		metric_banks_range(&t->m[i], &a, &b);
		if (a <= b && memcmp(&prev->m[i].hist[a], &t->m[i].hist[a],
				     (size_t)(b - a + 1) * sizeof(t->m[i].hist[0])))
			return false;
	}
	return true;
}

bool model_takes_short(const struct thread_model *tm)
{
	return tm->cur.first_seen && tm->life_hist && !tm->cur_torn;
}

/*
 * model_views_spans - model_views; *spans says that the buckets of t
 * differ from prev's only within life_add's interval spans. A short copy
 * t (sent): -1 when it cannot be taken, before anything of the model but
 * the interval's spans moved.
 */
static int model_views_spans(struct thread_model *tm, const struct rtsup_thread *t,
			     const struct rtsup_thread *prev, __u32 bank, bool *spans, bool sent)
{
	/* the lifetime views were computed from life_hist by the last call */
	bool had_life = tm->life_hist != NULL;
	const struct rtsup_thread *base;
	struct life_hist *l;
	__u64 h[HIST_BUCKETS];
	int i, err;

	/* a short copy's other buckets are prev's: counted from prev, into a lifetime */
	if (sent && (!prev || !model_takes_short(tm) || snapshot_base(t, prev) != prev))
		return -1;
	/*
	 * the same bytes as the last snapshot (a parked thread): an empty
	 * interval, and the lifetime views the last call made from them
	 */
	if (prev && (sent ? sent_same(prev, t) : !memcmp(prev, t, snapshot_bytes()))) {
		model_idle(tm);
		return 0;
	}
	tm->win_idle = false;	/* written below */
	err = life_add(tm, t, prev, sent);
	if (err && sent)	/* no kernel's buckets to fall back on */
		return -1;
	if (err) {	/* no lifetime counts: the kernel's buckets */
		span_window(t, prev, bank, &tm->win);
		span_life(t, &tm->life);
		tm->life_due = 0;	/* percentiles and all, from them */
		return 1;
	}
	l = tm->life_hist;
	base = snapshot_base(t, prev);
	*spans = base && base == prev;
	span_counters(t, base, &tm->win);
	span_counters(t, NULL, &tm->life);
	for (i = 0; i < RTSUP_M_NR; i++) {
		/* the interval's counts, just written by life_add */
		for (int b = l->wlo[i]; b <= l->whi[i]; b++)
			h[b] = l->win[i][b - l->wlo[i]];
		window_counts(&t->m[i], base ? &base->m[i] : NULL, bank, h, l->wlo[i], l->whi[i],
			      &tm->win.m[i]);
		if (had_life && base && life_view_kept(l, &t->m[i], &base->m[i], i))
			continue;
		view_scalars(&t->m[i], &tm->life.m[i]);
		tm->life_due |= 1u << i;	/* from l and t, which model_set keeps as cur */
	}
	return 1;
}

void model_life_settle(struct thread_model *tm)
{
	const struct life_hist *l = tm->life_hist;
	__u64 h[HIST_BUCKETS];
	int i;

	for (i = 0; l && tm->life_due && i < RTSUP_M_NR; i++) {
		struct metric_view *v = &tm->life.m[i];

		if (!(tm->life_due & (1u << i)) || !v->count)
			continue;
		life_counts(l, i, tm->cur.m[i].hist, h);
		view_quantiles(h, l->lo[i], l->hi[i], tm->cur.m[i].sum, v);
	}
	tm->life_due = 0;
}

void model_settle_all(struct model *m)
{
	int i;

	for (i = 0; i < m->n; i++)
		model_life_settle(m->t[i]);
}

bool model_views(struct thread_model *tm, const struct rtsup_thread *t,
		 const struct rtsup_thread *prev, __u32 bank)
{
	bool spans;

	return model_views_spans(tm, t, prev, bank, &spans, false) > 0;
}

/*
 * snapshot_take_moved - cur becomes t, whose buckets differ from cur's only
 * within the interval's spans life_add found (l): a thread's 4 x 280
 * buckets are most of its 7 KiB, and an interval moves a few of them
 */
static void snapshot_take_moved(struct rtsup_thread *cur, const struct rtsup_thread *t,
				const struct life_hist *l)
{
	int i;

	memcpy(cur, t, offsetof(struct rtsup_thread, m));
	for (i = 0; i < RTSUP_M_NR; i++) {
		memcpy(&cur->m[i], &t->m[i], offsetof(struct rtsup_metric_stats, hist));
		if (l->wlo[i] <= l->whi[i])
			memcpy(&cur->m[i].hist[l->wlo[i]], &t->m[i].hist[l->wlo[i]],
			       (size_t)(l->whi[i] - l->wlo[i] + 1) * sizeof(t->m[i].hist[0]));
	}
}

int model_set_sent(struct thread_model *tm, const struct rtsup_thread *t, __u32 bank, bool sent)
{
	const struct rtsup_thread *prev = tm->cur.first_seen ? &tm->cur : NULL;
	bool spans = false;
	int moved = model_views_spans(tm, t, prev, bank, &spans, sent);

	/* not moved: the same bytes; spans: the buckets moved within them (always, sent) */
	if (spans)
		snapshot_take_moved(&tm->cur, t, tm->life_hist);
	else if (moved > 0)
		tm->cur = *t;
	/* a short copy moves buckets that sum as the counts moved: torn stays as it was */
	if (moved > 0 && !sent)
		tm->cur_torn = snapshot_torn(t);
	return moved;
}

bool model_set(struct thread_model *tm, const struct rtsup_thread *t, __u32 bank)
{
	return model_set_sent(tm, t, bank, false) > 0;
}

void model_idle(struct thread_model *tm)
{
	/* a parked thread's window is empty already: its lines stay out of the cache */
	if (tm->win_idle)
		return;
	tm->win_idle = true;
	memset(&tm->win, 0, sizeof(tm->win));
	if (tm->life_hist)
		win_clear(tm->life_hist);
}

void model_prefetch(const struct thread_model *tm)
{
	const char *p, *cur;
	size_t o;
	int i;

	if (!tm)
		return;
	p = (const char *)tm;
	cur = (const char *)&tm->cur;
	for (o = 0; o < MODEL_HEAD_BYTES; o += 64)
		__builtin_prefetch(p + o, 1);
	for (o = 0; o < offsetof(struct rtsup_thread, m); o += 64)
		__builtin_prefetch(cur + o, 1);
	for (i = 0; i < RTSUP_M_NR; i++) {
		__builtin_prefetch(&tm->cur.m[i], 1);
		__builtin_prefetch((const char *)&tm->cur.m[i] + 64, 1);
	}
	for (o = 0; o < sizeof(tm->win); o += 64)
		__builtin_prefetch((const char *)&tm->win + o, 1);
}

void model_prefetch_kept(const struct thread_model *tm)
{
	size_t o;

	if (!tm)
		return;
	for (o = 0; o < MODEL_HEAD_BYTES; o += 64)
		__builtin_prefetch((const char *)tm + o, 1);
	__builtin_prefetch(&tm->cur.tgid);
	__builtin_prefetch(&tm->cur.exited);
	__builtin_prefetch(&tm->cur.rt);
	/* not win: model_idle clears it once, and no one reads it after (model_win_empty) */
}

/* prefetch_line - one line, to be written (the model's) or only read (the kernel's) */
static inline void prefetch_line(const char *p, bool write)
{
	/* the builtin wants a constant: clang's front end checks before inlining */
	if (write)
		__builtin_prefetch(p, 1);
	else
		__builtin_prefetch(p, 0);
}

/* prefetch_buckets - the lines of buckets [a, b] of h */
static void prefetch_buckets(const __u32 *h, int a, int b, bool write)
{
	const char *p = (const char *)&h[a], *end = (const char *)&h[b];

	/* the line of each: [a, b] may start mid-line */
	for (; p <= end; p += 64)
		prefetch_line(p, write);
	prefetch_line(end, write);
}

void model_prefetch_spans(const struct thread_model *tm, const struct rtsup_thread *t)
{
	const struct life_hist *l = tm ? tm->life_hist : NULL;
	int i, a, b;

	if (!t)
		return;
	for (i = 0; i < RTSUP_M_NR; i++) {
		metric_banks_range(&t->m[i], &a, &b);
		if (a > b)
			continue;
		prefetch_buckets(t->m[i].hist, a, b, false);
		if (tm && tm->cur.first_seen)
			prefetch_buckets(tm->cur.m[i].hist, a, b, true);
	}
	/* its interval arrays' addresses are in it: read when taken */
	if (l)
		__builtin_prefetch(l, 1);
}

/* find - binary search in the tid-sorted array */
static int find(const struct model *m, __u32 tid, int *pos)
{
	int lo = 0, hi = m->nsorted, i;

	while (lo < hi) {
		int mid = (lo + hi) / 2;

		if (m->tids[mid] == tid) {
			*pos = mid;
			return 1;
		}
		if (m->tids[mid] < tid)
			lo = mid + 1;
		else
			hi = mid;
	}
	/* the arrivals since the last sort: at most MODEL_TAIL_MAX */
	for (i = m->nsorted; i < m->n; i++) {
		if (m->t[i]->tid == tid) {
			*pos = i;
			return 1;
		}
	}
	*pos = m->n;
	return 0;
}

static int by_tid(const void *a, const void *b)
{
	__u32 x = (*(struct thread_model *const *)a)->tid;
	__u32 y = (*(struct thread_model *const *)b)->tid;

	return x < y ? -1 : x > y;
}

void model_sort(struct model *m)
{
	int i;

	if (m->nsorted < m->n) {
		qsort(m->t, m->n, sizeof(*m->t), by_tid);
		for (i = 0; i < m->n; i++)
			m->tids[i] = m->t[i]->tid;
	}
	m->nsorted = m->n;
}

bool model_sorted(const struct model *m)
{
	int i;

	if (m->nsorted < 0 || m->nsorted > m->n)
		return false;
	for (i = 0; i < m->nsorted; i++)
		if (m->tids[i] != m->t[i]->tid || (i && m->t[i - 1]->tid >= m->t[i]->tid))
			return false;
	return true;
}

struct thread_model *model_get(struct model *m, __u32 tid, bool create)
{
	struct thread_model *tm;
	int pos;

	if (find(m, tid, &pos))
		return m->t[pos];
	if (!create)
		return NULL;
	if (m->n - m->nsorted >= MODEL_TAIL_MAX)
		model_sort(m);
	if (m->n == m->cap) {
		int cap = m->cap ? m->cap * 2 : 64;
		struct thread_model **t = realloc(m->t, cap * sizeof(*t));
		__u32 *tids;

		if (!t)
			return NULL;
		m->t = t;
		tids = realloc(m->tids, cap * sizeof(*tids));
		if (!tids)
			return NULL;
		m->tids = tids;
		m->cap = cap;
	}
	tm = calloc(1, sizeof(*tm));
	if (!tm)
		return NULL;
	tm->tid = tid;
	tm->policy = -1;
	pos = m->n++;
	m->t[pos] = tm;
	/* after every sorted one: it stays sorted (tids mostly grow) */
	if (m->nsorted == pos && (!pos || m->tids[pos - 1] < tid)) {
		m->tids[pos] = tid;
		m->nsorted++;
	}
	return tm;
}

static void thread_free(struct thread_model *tm)
{
	free(tm->snap);
	life_free(tm->life_hist);
	free(tm);
}

void model_remove(struct model *m, __u32 tid)
{
	int pos;

	if (!find(m, tid, &pos))
		return;
	thread_free(m->t[pos]);
	memmove(&m->t[pos], &m->t[pos + 1], (m->n - pos - 1) * sizeof(*m->t));
	m->n--;
	if (pos < m->nsorted) {
		m->nsorted--;
		memmove(&m->tids[pos], &m->tids[pos + 1], (m->nsorted - pos) * sizeof(*m->tids));
	}
}

static int cmp_u64(const void *a, const void *b)
{
	__u64 x = *(const __u64 *)a, y = *(const __u64 *)b;

	return x < y ? -1 : x > y;
}

void model_prune_dead(struct model *m, int keep)
{
	__u64 *seq, cut;
	int i, j, sorted, dead = 0;

	for (i = 0; i < m->n; i++) {
		struct thread_model *tm = m->t[i];

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
		if (m->t[i]->reported_exit)
			seq[j++] = m->t[i]->dead_seq;
	qsort(seq, dead, sizeof(*seq), cmp_u64);
	cut = seq[dead - keep - 1];	/* the newest of the ones to drop */
	free(seq);
	for (i = 0, j = 0, sorted = 0; i < m->n; i++) {
		if (m->t[i]->reported_exit && m->t[i]->dead_seq <= cut) {
			thread_free(m->t[i]);
			m->forgotten++;
			continue;
		}
		if (i != j) {
			m->t[j] = m->t[i];
			if (i < m->nsorted)
				m->tids[j] = m->tids[i];
		}
		/* the order is kept: the sorted part stays sorted, shorter */
		sorted += i < m->nsorted;
		j++;
	}
	m->n = j;
	m->nsorted = sorted;
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
		thread_free(m->t[i]);
	free(m->t);
	free(m->tids);
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
