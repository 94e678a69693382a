// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_model.c - user/model/model.c: percentiles from the histogram, interval
 * views from two snapshots, and the tid-sorted thread registry.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "model/model.h"
#include "stats.h"
#include "hist.h"
#include "threadread.h"

#define US	1000ULL
#define MS	1000000ULL
#define NMAX	20000

/* xorshift64: deterministic pseudo-random values */
static __u64 rnd_state;

static __u64 rnd(void)
{
	rnd_state ^= rnd_state << 13;
	rnd_state ^= rnd_state >> 7;
	rnd_state ^= rnd_state << 17;
	return rnd_state;
}

static double rnd_unit(void)
{
	return (double)(rnd() >> 11) / (double)(1ULL << 53);
}

enum dist { UNIFORM, EXPO, BIMODAL, NARROW, P5333, P5333_JITTER };

/* draw - one value in ns between 1 us and 10 ms from a distribution */
static __u64 draw(enum dist d)
{
	__u64 v;

	switch (d) {
	case UNIFORM:
		return 1 * US + rnd() % (10 * MS - 1 * US + 1);
	case EXPO:		/* mean 200 us above 1 us, long tail */
		v = 1 * US + (__u64)(-log(1.0 - rnd_unit()) * 200 * US);
		return v > 10 * MS ? 10 * MS : v;
	case BIMODAL:		/* 90% near 50 us, 10% near 5 ms */
		if (rnd() % 10)
			return 40 * US + rnd() % (20 * US);
		return 4500 * US + rnd() % (1 * MS);
	case P5333:		/* a steady period of 5333 us */
		return 5333 * US;
	case P5333_JITTER:	/* the same with +-40 us of triangular jitter */
		return 5333 * US - 40 * US + rnd() % (40 * US) + rnd() % (40 * US);
	case NARROW:		/* 1..2 ms */
	default:
		return 1 * MS + rnd() % (1 * MS);
	}
}

static int cmp_u64(const void *a, const void *b)
{
	__u64 x = *(const __u64 *)a, y = *(const __u64 *)b;

	return x < y ? -1 : x > y;
}

/* nearest_rank - the permille-quantile of a sorted array, nearest rank */
static __u64 nearest_rank(const __u64 *sorted, __u64 n, unsigned int permille)
{
	__u64 rank = (permille * n + 999) / 1000;

	return sorted[rank ? rank - 1 : 0];
}

/* near - the histogram value is within 2 % of the reference */
static void check_near(__u64 got, __u64 ref, const char *what)
{
	__u64 d = got > ref ? got - ref : ref - got;

	if (d * 50 > ref)
		fail_msg("%s: histogram %llu, sorted array %llu", what,
			 (unsigned long long)got, (unsigned long long)ref);
}

/* Fixture: a metric filled with values, and a copy of them to sort. */
struct pfx {
	struct rtsup_metric_stats cur;
	struct rtsup_metric_stats prev;
	__u64 v[NMAX];
	__u64 n;
};

static int pfx_setup(void **state)
{
	struct pfx *p = calloc(1, sizeof(*p));

	if (!p)
		return -1;
	metric_init(&p->cur);
	rnd_state = 0x2545F4914F6CDD1DULL;
	*state = p;
	return 0;
}

static int pfx_teardown(void **state)
{
	free(*state);
	return 0;
}

/* fill - add n values of a distribution to p->cur (bank of 'epoch') */
static void fill(struct pfx *p, enum dist d, __u64 n, __u32 epoch)
{
	__u64 i;

	for (i = 0; i < n; i++) {
		p->v[i] = draw(d);
		metric_add(&p->cur, p->v[i], 102, epoch);
	}
	p->n = n;
	qsort(p->v, n, sizeof(p->v[0]), cmp_u64);
}

/* check_lifetime - p50/p99/p99.9 of p->cur against the sorted array */
static void check_lifetime(struct pfx *p)
{
	const struct rtsup_metric_stats *s = &p->cur;
	struct metric_view v;

	/* the views: from the buckets and the sum */
	metric_view_life(s, &v);
	check_near(v.p50, nearest_rank(p->v, p->n, 500), "view p50");
	check_near(v.p99, nearest_rank(p->v, p->n, 990), "view p99");
	check_near(v.p999, nearest_rank(p->v, p->n, 999), "view p99.9");
	/* from the buckets alone */

	check_near(hist_percentile(s->hist, NULL, 0.50, s->min, s->max),
		   nearest_rank(p->v, p->n, 500), "p50");
	check_near(hist_percentile(s->hist, NULL, 0.99, s->min, s->max),
		   nearest_rank(p->v, p->n, 990), "p99");
	check_near(hist_percentile(s->hist, NULL, 0.999, s->min, s->max),
		   nearest_rank(p->v, p->n, 999), "p99.9");
}

/* uniform 1 us..10 ms: percentiles within 1/8 of the sorted array */
static void test_model_percentile_uniform(void **state)
{
	struct pfx *p = *state;

	fill(p, UNIFORM, 5000, 0);
	check_lifetime(p);
}

/* exponential-ish with a long tail */
static void test_model_percentile_expo(void **state)
{
	struct pfx *p = *state;

	fill(p, EXPO, NMAX, 0);
	check_lifetime(p);
}

/* bimodal: p50 in the low mode, p99 and p99.9 in the high one */
static void test_model_percentile_bimodal(void **state)
{
	struct pfx *p = *state;
	const struct rtsup_metric_stats *s = &p->cur;

	fill(p, BIMODAL, 3333, 0);
	check_lifetime(p);
	assert_true(hist_percentile(s->hist, NULL, 0.50, s->min, s->max) < 70 * US);
	assert_true(hist_percentile(s->hist, NULL, 0.99, s->min, s->max) > 4 * MS);
}

/* edge cases: empty, one value, small exact values, the last bucket */
static void test_model_percentile_edges(void **state)
{
	struct pfx *p = *state;
	struct rtsup_metric_stats *s = &p->cur;

	assert_int_equal(hist_percentile(s->hist, NULL, 0.5, 0, 0), 0);
	metric_add(s, 123457, 102, 0);
	/* one value: clamped to min == max, so exact */
	assert_int_equal(hist_percentile(s->hist, NULL, 0.5, s->min, s->max), 123457);
	assert_int_equal(hist_percentile(s->hist, NULL, 0.999, s->min, s->max), 123457);

	memset(s, 0, sizeof(*s));	/* metric_init keeps hist[] */
	metric_init(s);
	metric_add(s, 3, 102, 0);
	metric_add(s, 5, 102, 0);
	metric_add(s, 7, 102, 0);
	assert_int_equal(hist_percentile(s->hist, NULL, 0.34, s->min, s->max), 5);
	assert_int_equal(hist_percentile(s->hist, NULL, 0.33, s->min, s->max), 3);
	assert_int_equal(hist_percentile(s->hist, NULL, 1.0, s->min, s->max), 7);

	/* a value in the last bucket reports the max */
	metric_add(s, 500ULL * 1000 * MS, 102, 0);
	assert_int_equal(hist_percentile(s->hist, NULL, 1.0, s->min, s->max),
			 500ULL * 1000 * MS);
}

/* percentiles of an interval: difference of two snapshots */
static void test_model_percentile_window(void **state)
{
	struct pfx *p = *state;
	__u64 n1;

	fill(p, NARROW, 7000, 0);	/* the previous intervals: 1..2 ms */
	n1 = p->n;
	p->prev = p->cur;
	minmax_reset(&p->cur.win[1]);	/* what cycle_epoch does */
	fill(p, EXPO, 4000, 1);		/* this interval */
	assert_int_equal(p->cur.count - p->prev.count, 4000);
	assert_int_equal(p->prev.count, n1);
	check_near(hist_percentile(p->cur.hist, p->prev.hist, 0.50,
				   p->cur.win[1].min, p->cur.win[1].max),
		   nearest_rank(p->v, p->n, 500), "window p50");
	check_near(hist_percentile(p->cur.hist, p->prev.hist, 0.99,
				   p->cur.win[1].min, p->cur.win[1].max),
		   nearest_rank(p->v, p->n, 990), "window p99");
	check_near(hist_percentile(p->cur.hist, p->prev.hist, 0.999,
				   p->cur.win[1].min, p->cur.win[1].max),
		   nearest_rank(p->v, p->n, 999), "window p99.9");
}

/* a period of 5333 us: the bucket's midpoint read 5505 us; now within 2 % */
static void test_model_percentile_5333(void **state)
{
	struct pfx *p = *state;
	struct metric_view v;

	fill(p, P5333, 1000, 0);
	check_lifetime(p);
	metric_init(&p->cur);
	memset(p->cur.hist, 0, sizeof(p->cur.hist));
	fill(p, P5333_JITTER, NMAX - 1, 0);
	check_lifetime(p);
	/* one overrun of 8 ms: max is far, the jitter still sits in one bucket */
	metric_add(&p->cur, 8 * MS, 102, 0);
	p->v[p->n++] = 8 * MS;
	metric_view_life(&p->cur, &v);
	check_near(v.p50, nearest_rank(p->v, p->n, 500), "p50 with an overrun");
	check_near(v.p99, nearest_rank(p->v, p->n, 990), "p99 with an overrun");
}

/*
 * a range of values: narrow (+-1 %) and wide (x0.5..x2) distributions
 * centred from 3 us to 40 ms, each bucket position within its octave
 */
static void test_model_percentile_range(void **state)
{
	struct pfx *p = *state;
	double c;
	__u64 i, n = 4000;
	int wide;

	for (wide = 0; wide < 2; wide++) {
		for (c = 3 * US; c < 40 * MS; c *= 1.37) {
			metric_init(&p->cur);
			memset(p->cur.hist, 0, sizeof(p->cur.hist));
			for (i = 0; i < n; i++) {
				double f = wide ? 0.5 + 1.5 * rnd_unit() : 0.99 + 0.02 * rnd_unit();

				p->v[i] = (__u64)(c * f);
				metric_add(&p->cur, p->v[i], 102, 0);
			}
			p->n = n;
			qsort(p->v, n, sizeof(p->v[0]), cmp_u64);
			check_lifetime(p);
		}
	}
}

/* metric_view_window: count/mean from the snapshots, min/max from the bank */
static void test_model_view_window(void **state)
{
	struct pfx *p = *state;
	struct metric_view v;
	__u64 i, sum = 0;

	fill(p, NARROW, 1000, 0);
	p->prev = p->cur;
	minmax_reset(&p->cur.win[1]);
	fill(p, BIMODAL, 2000, 1);
	for (i = 0; i < p->n; i++)
		sum += p->v[i];

	metric_view_window(&p->cur, &p->prev, 1, &v);
	assert_int_equal(v.count, 2000);
	assert_int_equal(v.min, p->v[0]);
	assert_int_equal(v.max, p->v[p->n - 1]);
	assert_float_equal(v.mean, (double)sum / 2000, 1e-6);
	assert_float_equal(v.ewma, (double)p->cur.ewma / 256, 1e-9);
	check_near(v.p50, nearest_rank(p->v, p->n, 500), "view p50");
	check_near(v.p99, nearest_rank(p->v, p->n, 990), "view p99");
	check_near(v.p999, nearest_rank(p->v, p->n, 999), "view p99.9");
	/* the other bank holds the previous interval (1..2 ms) */
	metric_view_window(&p->cur, &p->prev, 0, &v);
	assert_true(v.min >= 1 * MS);

	/* nothing new: an empty view */
	metric_view_window(&p->cur, &p->cur, 1, &v);
	assert_int_equal(v.count, 0);
	assert_int_equal(v.min, 0);
	assert_int_equal(v.p99, 0);
}

/* metric_view_window without a previous snapshot is the lifetime view */
static void test_model_view_window_no_prev(void **state)
{
	struct pfx *p = *state;
	struct metric_view w, l;

	fill(p, UNIFORM, 500, 0);
	metric_view_window(&p->cur, NULL, 1, &w);
	metric_view_life(&p->cur, &l);
	assert_memory_equal(&w, &l, sizeof(w));
	assert_int_equal(l.count, 500);
	assert_int_equal(l.min, p->v[0]);
	assert_int_equal(l.max, p->v[499]);
}

/* Two snapshots of one thread. */
struct tfx {
	struct rtsup_thread cur;
	struct rtsup_thread prev;
};

static int tfx_setup(void **state)
{
	struct tfx *t = calloc(1, sizeof(*t));

	if (!t)
		return -1;
	*state = t;
	return 0;
}

/* add_cycles - n cycles of exec 'exec' into a thread, epoch bank 'epoch' */
static void add_cycles(struct rtsup_thread *t, int n, __u64 exec, __u32 epoch)
{
	struct rtsup_cycle c;
	int i;

	memset(&c, 0, sizeof(c));
	for (i = 0; i < n; i++) {
		c.exec = exec + (__u64)i;
		c.cpu = c.exec;
		thread_account_cycle(t, &c, 102, epoch);
	}
}

/* span_window: counters are differences; unsafe_total sums the reasons */
static void test_model_span_window(void **state)
{
	struct tfx *t = *state;
	struct span_view s;

	add_cycles(&t->cur, 30, 100 * US, 0);
	t->cur.unsafe[RTSUP_U_SYSCALL] = 4;
	t->cur.vol_cs = 31;
	t->prev = t->cur;
	minmax_reset(&t->cur.m[RTSUP_M_EXEC].win[1]);
	add_cycles(&t->cur, 12, 300 * US, 1);
	t->cur.unsafe[RTSUP_U_SYSCALL] = 6;
	t->cur.unsafe[RTSUP_U_BLOCK] = 1;
	t->cur.vol_cs = 44;
	t->cur.misses = 2;

	span_window(&t->cur, &t->prev, 1, &s);
	assert_int_equal(s.cycles, 12);
	assert_int_equal(s.vol_cs, 13);
	assert_int_equal(s.misses, 2);
	assert_int_equal(s.unsafe[RTSUP_U_SYSCALL], 2);
	assert_int_equal(s.unsafe[RTSUP_U_BLOCK], 1);
	assert_int_equal(s.unsafe_total, 3);
	assert_int_equal(s.m[RTSUP_M_EXEC].count, 12);
	assert_int_equal(s.m[RTSUP_M_EXEC].min, 300 * US);
	assert_int_equal(s.m[RTSUP_M_EXEC].max, 300 * US + 11);
	assert_int_equal(s.m[RTSUP_M_PERIOD].count, 0);

	span_life(&t->cur, &s);
	assert_int_equal(s.cycles, 42);
	assert_int_equal(s.unsafe_total, 7);
	assert_int_equal(s.m[RTSUP_M_EXEC].min, 100 * US);
}

/* stats restarted (the reset generation changed): the window starts from zero */
static void test_model_span_window_restart(void **state)
{
	struct tfx *t = *state;
	struct span_view s;

	add_cycles(&t->prev, 50, 100 * US, 0);	/* start-up, then dropped */
	t->prev.unsafe[RTSUP_U_SYSCALL] = 7;
	t->prev.syscalls = 9;
	add_cycles(&t->cur, 10, 500 * US, 1);
	t->cur.resets = t->prev.resets + 1;
	t->cur.unsafe[RTSUP_U_SYSCALL] = 1;
	t->cur.syscalls = 1;

	span_window(&t->cur, &t->prev, 1, &s);
	assert_int_equal(s.cycles, 10);
	assert_int_equal(s.syscalls, 1);
	assert_int_equal(s.unsafe[RTSUP_U_SYSCALL], 1);
	assert_int_equal(s.unsafe_total, 1);
	assert_int_equal(s.m[RTSUP_M_EXEC].count, 10);
	assert_int_equal(s.m[RTSUP_M_EXEC].min, 500 * US);
	assert_int_equal(s.m[RTSUP_M_EXEC].max, 500 * US + 9);
}

/*
 * stats restarted, but more cycles since the restart than before it (a
 * short start-up, then the loop): the window must still start from zero,
 * not subtract the dropped start-up counters.
 */
static void test_model_span_window_restart_more_cycles(void **state)
{
	struct tfx *t = *state;
	struct span_view s;

	add_cycles(&t->prev, 20, 100 * US, 0);	/* start-up activations */
	t->prev.unsafe[RTSUP_U_SYSCALL] = 15;
	t->prev.syscalls = 15;
	add_cycles(&t->cur, 1000, 500 * US, 1);	/* after the reset */
	t->cur.resets = t->prev.resets + 1;

	span_window(&t->cur, &t->prev, 1, &s);
	assert_int_equal(s.cycles, 1000);
	assert_int_equal(s.syscalls, 0);
	assert_int_equal(s.unsafe[RTSUP_U_SYSCALL], 0);
	assert_int_equal(s.m[RTSUP_M_EXEC].count, 1000);
}

/*
 * model_set: the first snapshot's interval is everything so far, the next
 * one's is the change; model_idle empties the interval, not the lifetime
 */
static void test_model_set_snapshots(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);

	assert_non_null(tm);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 30, 100 * US, 0);
	t->cur.vol_cs = 31;
	model_set(tm, &t->cur, 0);
	assert_int_equal(tm->win.cycles, 30);
	assert_int_equal(tm->win.vol_cs, 31);
	assert_int_equal(tm->life.cycles, 30);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 30);

	minmax_reset(&t->cur.m[RTSUP_M_EXEC].win[1]);
	add_cycles(&t->cur, 12, 300 * US, 1);
	t->cur.vol_cs = 45;
	model_set(tm, &t->cur, 1);
	assert_int_equal(tm->win.cycles, 12);
	assert_int_equal(tm->win.vol_cs, 14);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 12);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].min, 300 * US);
	assert_int_equal(tm->life.cycles, 42);
	assert_int_equal(tm->life.m[RTSUP_M_EXEC].min, 100 * US);

	model_idle(tm);
	assert_int_equal(tm->win.cycles, 0);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 0);
	assert_int_equal(tm->life.cycles, 42);
	model_free(&m);
}

/* life_at - the model's lifetime count of bucket b of metric i */
static __u64 life_at(const struct thread_model *tm, int i, int b)
{
	__u64 h[HIST_BUCKETS];
	int lo, hi;

	assert_true(model_life_counts(tm, i, h, &lo, &hi));
	return b >= lo && b <= hi ? h[b] : 0;
}

/* win_at - the model's count of bucket b of metric i in the last interval */
static __u64 win_at(const struct thread_model *tm, int i, int b)
{
	__u64 h[HIST_BUCKETS];
	int lo, hi;

	assert_true(model_win_counts(tm, i, h, &lo, &hi));
	return b >= lo && b <= hi ? h[b] : 0;
}

/* check_views - tm against the snapshots: every bucket, and the public views */
static void check_views(struct thread_model *tm, const struct rtsup_thread *cur,
			const struct rtsup_thread *base, __u64 (*life)[HIST_BUCKETS],
			__u32 bank)
{
	struct metric_view v;
	int i, b;

	model_life_settle(tm);	/* the lifetime's percentiles, as their readers ask */
	for (i = 0; i < RTSUP_M_NR; i++) {
		for (b = 0; b < HIST_BUCKETS; b++) {
			__u32 d = cur->m[i].hist[b] - (base ? base->m[i].hist[b] : 0);

			assert_int_equal(win_at(tm, i, b), d);
			assert_int_equal(life_at(tm, i, b), life[i][b]);
			if (d)
				assert_true(tm->life_hist->wlo[i] <= b && b <= tm->life_hist->whi[i]);
			if (life[i][b])
				assert_true(tm->life_hist->lo[i] <= b && b <= tm->life_hist->hi[i]);
		}
		metric_view_window(&cur->m[i], base ? &base->m[i] : NULL, bank, &v);
		assert_memory_equal(&tm->win.m[i], &v, sizeof(v));
		metric_view_counts(&cur->m[i], life[i], &v);
		assert_memory_equal(&tm->life.m[i], &v, sizeof(v));
	}
}

/*
 * model_set works on the buckets an interval touched only: as the values
 * move (10 us, 5 ms, an idle interval, 50 us, a restart of the kernel's
 * statistics, 2 ms), every one of the 280 buckets of the interval and the
 * lifetime still holds what the snapshots say, and the views are those of
 * the full computation.
 */
static void test_model_views_follow_moving_buckets(void **state)
{
	static const __u64 exec[] = { 10 * US, 5 * MS, 0, 50 * US, 0, 2 * MS, 0, 3 * MS };
	static __u64 life[RTSUP_M_NR][HIST_BUCKETS];
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);
	struct rtsup_thread prev;
	bool have_prev = false;
	__u32 bank;
	int k, i, b;

	assert_non_null(tm);
	memset(life, 0, sizeof(life));
	t->cur.first_seen = 7;
	for (k = 0; k < (int)(sizeof(exec) / sizeof(exec[0])); k++) {
		bank = (__u32)k & 1;
		if (k == 2) {	/* an interval without a snapshot */
			model_idle(tm);
			for (i = 0; i < RTSUP_M_NR; i++)
				for (b = 0; b < HIST_BUCKETS; b++)
					assert_int_equal(win_at(tm, i, b), 0);
			assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 0);
			continue;
		}
		if (k == 6) {	/* a snapshot without a cycle: the lifetime views are kept */
			t->cur.vol_cs++;
		} else if (k == 4) {	/* the kernel restarted the statistics */
			for (i = 0; i < RTSUP_M_NR; i++)
				metric_init(&t->cur.m[i]);
			t->cur.resets++;
			memset(life, 0, sizeof(life));
			have_prev = false;
			add_cycles(&t->cur, 7, 900 * US, bank);
		} else {
			minmax_reset(&t->cur.m[RTSUP_M_EXEC].win[bank]);
			add_cycles(&t->cur, 10 + k, exec[k], bank);
		}
		for (i = 0; i < RTSUP_M_NR; i++)
			for (b = 0; b < HIST_BUCKETS; b++)
				life[i][b] += (__u32)(t->cur.m[i].hist[b] -
						      (have_prev ? prev.m[i].hist[b] : 0));
		model_set(tm, &t->cur, bank);
		check_views(tm, &t->cur, have_prev ? &prev : NULL, life, bank);
		/* the snapshot kept is the one given, though only its moved buckets were copied */
		assert_memory_equal(&tm->cur, &t->cur, sizeof(t->cur));
		prev = t->cur;
		have_prev = true;
	}
	model_free(&m);
}

/*
 * The buckets between the banks' lowest and highest values are read only
 * when they moved by as many values as the count did. A bucket outside
 * them that moved with its count (a bank reset since the value went in)
 * is found by comparing every bucket; one whose count is not in the copy
 * yet (a copy taken while a hook wrote) is counted at the next snapshot,
 * with its count, and the snapshot kept holds it only then.
 */
static void test_model_buckets_outside_the_banks(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);
	struct rtsup_metric_stats *e = &t->cur.m[RTSUP_M_EXEC];
	__u32 far = hist_bucket(40 * MS);

	assert_non_null(tm);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 10, 100 * US, 0);
	model_set(tm, &t->cur, 0);

	/* moved with its count, the banks knowing nothing of it */
	minmax_reset(&e->win[0]);
	minmax_reset(&e->win[1]);
	add_cycles(&t->cur, 3, 100 * US, 1);
	e->hist[far]++;
	e->count++;
	e->sum += 40 * MS;
	model_set(tm, &t->cur, 1);
	assert_int_equal(win_at(tm, RTSUP_M_EXEC, far), 1);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 4);
	assert_memory_equal(&tm->cur, &t->cur, sizeof(t->cur));

	/* torn: the bucket is in the copy, its count and bank not yet */
	minmax_reset(&e->win[0]);
	add_cycles(&t->cur, 2, 100 * US, 0);
	e->hist[far]++;
	model_set(tm, &t->cur, 0);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 2);
	assert_int_equal(win_at(tm, RTSUP_M_EXEC, far), 0);
	assert_int_equal(tm->cur.m[RTSUP_M_EXEC].hist[far], 1);
	/* the hook's count and bank in the next copy: the value is counted there */
	minmax_reset(&e->win[1]);
	e->count++;
	e->sum += 40 * MS;
	e->win[0].max = 40 * MS;
	add_cycles(&t->cur, 1, 100 * US, 1);
	model_set(tm, &t->cur, 1);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 2);
	assert_int_equal(win_at(tm, RTSUP_M_EXEC, far), 1);
	assert_memory_equal(&tm->cur, &t->cur, sizeof(t->cur));
	model_free(&m);
}

/*
 * An idle thread costs no percentile walk: a snapshot equal to the last
 * one computes nothing, one where a metric did not move keeps that
 * metric's lifetime view (the poisoned p99 stays), one
 * where it moved computes it again, as does a bucket read before its count
 * (a torn read); a restart of the kernel's statistics computes every view
 * again, whatever the counts.
 */
static void test_model_idle_snapshot_keeps_life_views(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);
	struct metric_view *life_exec;
	__u64 p99;

	assert_non_null(tm);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 20, 100 * US, 0);
	model_set(tm, &t->cur, 0);
	life_exec = &tm->life.m[RTSUP_M_EXEC];
	/* the lifetime's percentiles wait for a reader (model_life_settle) */
	assert_true(tm->life_due & (1u << RTSUP_M_EXEC));
	assert_int_equal(life_exec->p99, 0);
	model_life_settle(tm);
	assert_int_equal(tm->life_due, 0);
	p99 = life_exec->p99;
	assert_int_equal(p99 / US, 100);

	/* the same bytes again (a parked thread): nothing is computed, the interval empties */
	assert_int_equal(win_at(tm, RTSUP_M_EXEC, hist_bucket(100 * US)), 20);
	life_exec->p99 = 12345;		/* poison: kept only if not walked again */
	tm->life.cycles = 777;
	model_set(tm, &t->cur, 1);
	model_life_settle(tm);
	assert_int_equal(life_exec->p99, 12345);
	assert_int_equal(tm->life.cycles, 777);
	assert_int_equal(tm->win.cycles, 0);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 0);
	assert_int_equal(win_at(tm, RTSUP_M_EXEC, hist_bucket(100 * US)), 0);
	/* what a reader of a parked thread skips is zero: the whole view */
	assert_true(model_win_empty(tm));
	assert_memory_equal(&tm->win, &(struct span_view){ 0 }, sizeof(tm->win));
	tm->life.cycles = 20;

	t->cur.vol_cs++;	/* a switch, no cycle: the counters again, not the percentiles */
	model_set(tm, &t->cur, 1);
	model_life_settle(tm);
	assert_false(model_win_empty(tm));
	assert_int_equal(tm->win.vol_cs, 1);
	assert_int_equal(life_exec->p99, 12345);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 0);
	assert_int_equal(tm->life.cycles, 20);

	add_cycles(&t->cur, 1, 100 * US, 0);	/* moved: computed again */
	model_set(tm, &t->cur, 0);
	model_life_settle(tm);
	assert_int_equal(life_exec->p99, p99);

	life_exec->p99 = 12345;	/* a torn read: a bucket moved, its count not yet */
	t->cur.m[RTSUP_M_EXEC].hist[hist_bucket(100 * US)]++;
	model_set(tm, &t->cur, 1);
	model_life_settle(tm);
	assert_int_not_equal(life_exec->p99, 12345);

	life_exec->p99 = 12345;
	t->cur.resets++;	/* the same counts, but since a restart */
	model_set(tm, &t->cur, 1);
	model_life_settle(tm);
	assert_int_equal(life_exec->p99, p99);
	model_free(&m);
}

/*
 * The kernel's cause attribution state (why) is no part of the thread the
 * model reads (snapshot_bytes): a snapshot that moved there only is the
 * same snapshot, a parked thread's, and a cycle after it is counted as
 * from the last snapshot's counts
 */
static void test_model_why_alone_is_no_change(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);

	assert_non_null(tm);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 5, 100 * US, 0);
	assert_true(model_set(tm, &t->cur, 0));
	t->cur.why.out_ts = 123;	/* a hook's attribution state only */
	t->cur.why.cur.wait_ns = 9;
	assert_false(model_set(tm, &t->cur, 1));
	assert_int_equal(tm->win.cycles, 0);
	add_cycles(&t->cur, 2, 100 * US, 0);
	assert_true(model_set(tm, &t->cur, 0));
	assert_int_equal(tm->win.cycles, 2);
	assert_int_equal(tm->win.m[RTSUP_M_EXEC].count, 2);
	assert_int_equal(tm->life.cycles, 7);
	model_free(&m);
}

/* flip - interval e begins: its bank of every metric reset, as cycle_epoch does */
static void flip(struct rtsup_thread *t, __u32 e)
{
	int i;

	for (i = 0; i < RTSUP_M_NR; i++)
		minmax_reset(&t->m[i].win[RTSUP_BANK(e)]);
}

/* short_of - a short copy of t (thread_copy_short) over a buffer of other bytes */
static void short_of(struct rtsup_thread *out, const struct rtsup_thread *t)
{
	memset(out, 0xab, sizeof(*out));
	thread_copy_short(out, t);
}

/* views_equal - the interval and lifetime views of two models, percentiles and all */
static void views_equal(struct thread_model *a, struct thread_model *b)
{
	model_life_settle(a);
	model_life_settle(b);
	assert_memory_equal(&a->win, &b->win, sizeof(a->win));
	assert_memory_equal(&a->life, &b->life, sizeof(a->life));
	assert_memory_equal(&a->cur, &b->cur, offsetof(struct rtsup_thread, why));
}

/*
 * A short copy (the collector's in place: threadmem.h) is taken as the
 * whole entry would be: interval after interval, in both banks, values
 * in new buckets, the same views and snapshot, and an interval without
 * a value is no change.
 */
static void test_model_short_copy_as_whole(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *whole = model_get(&m, 1, true), *part = model_get(&m, 2, true);
	static const __u64 exec[] = { 100 * US, 3 * MS, 40 * US, 900 * US, 100 * US };
	__u32 e;

	assert_non_null(whole);
	assert_non_null(part);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 5, 100 * US, 0);
	assert_false(model_takes_short(part));	/* nothing to take the other buckets from */
	assert_true(model_set(whole, &t->cur, 0));
	assert_true(model_set(part, &t->cur, 0));
	for (e = 1; e < 1 + sizeof(exec) / sizeof(exec[0]); e++) {
		flip(&t->cur, e);
		add_cycles(&t->cur, (int)e, exec[e - 1], e);
		assert_true(model_takes_short(part));
		short_of(&t->prev, &t->cur);
		assert_int_equal(model_set_sent(part, &t->prev, e, true), 1);
		assert_true(model_set(whole, &t->cur, e));
		views_equal(whole, part);
	}
	short_of(&t->prev, &t->cur);
	assert_int_equal(model_set_sent(part, &t->prev, e, true), 0);
	assert_int_equal(part->win.cycles, 0);
	model_free(&m);
}

/*
 * A short copy whose buckets do not account for its counts (a value
 * outside the banks' buckets: a bank reset before the copy, a hook
 * writing during it) is refused, and nothing of the model moves: the
 * whole entry taken next gives what a whole entry always gave.
 */
static void test_model_short_copy_refused(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *whole = model_get(&m, 1, true), *part = model_get(&m, 2, true);
	struct rtsup_metric_stats *s = &t->cur.m[RTSUP_M_EXEC];

	assert_non_null(whole);
	assert_non_null(part);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 5, 100 * US, 0);
	model_set(whole, &t->cur, 0);
	model_set(part, &t->cur, 0);
	flip(&t->cur, 1);
	add_cycles(&t->cur, 3, 200 * US, 1);
	/* a value of 5 ms the banks do not hold (its bank reset since) */
	s->hist[hist_bucket(5 * MS)]++;
	s->count++;
	s->sum += 5 * MS;
	short_of(&t->prev, &t->cur);
	assert_int_equal(model_set_sent(part, &t->prev, 1, true), -1);
	assert_true(model_set(part, &t->cur, 1));
	assert_true(model_set(whole, &t->cur, 1));
	views_equal(whole, part);
	assert_int_equal(part->win.m[RTSUP_M_EXEC].count, 4);
	model_free(&m);
}

/*
 * A whole copy taken while a hook wrote (a count without its bucket yet)
 * is torn: the next copy is whole too, or that bucket would stay out of
 * the snapshot for good. Once a whole copy is not torn, short ones again.
 */
static void test_model_torn_copy_takes_no_short(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 1, true);
	struct rtsup_metric_stats *s = &t->cur.m[RTSUP_M_EXEC];
	__u32 b = hist_bucket(100 * US);

	assert_non_null(tm);
	t->cur.first_seen = 7;
	add_cycles(&t->cur, 5, 100 * US, 0);
	s->hist[b]--;	/* the hook had yet to write it */
	model_set(tm, &t->cur, 0);
	assert_false(model_takes_short(tm));
	s->hist[b]++;
	model_set(tm, &t->cur, 0);
	assert_true(model_takes_short(tm));
	assert_int_equal(tm->life.m[RTSUP_M_EXEC].count, 5);
	model_free(&m);
}

/*
 * What the kernel counted before the thread's first cycle (a snapshot
 * without cycles keeps no lifetime of its own) is in the lifetime once one
 * is kept: every view as the kernel's buckets give it.
 */
static void test_model_life_holds_counts_before_the_first_cycle(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);
	struct rtsup_metric_stats *s = &t->cur.m[RTSUP_M_LATENCY];
	__u32 b = hist_bucket(2 * MS);
	struct metric_view v;
	int i;

	assert_non_null(tm);
	t->cur.first_seen = 7;
	s->hist[b] = 3;
	s->count = 3;
	s->sum = 6 * MS;
	s->min = s->max = 2 * MS;
	model_set(tm, &t->cur, 0);
	assert_null(tm->life_hist);
	add_cycles(&t->cur, 10, 100 * US, 1);
	model_set(tm, &t->cur, 1);
	assert_int_equal(life_at(tm, RTSUP_M_LATENCY, b), 3);
	model_life_settle(tm);
	for (i = 0; i < RTSUP_M_NR; i++) {
		metric_view_life(&t->cur.m[i], &v);
		assert_memory_equal(&tm->life.m[i], &v, sizeof(v));
	}
	model_free(&m);
}

/*
 * A bucket that wraps between two snapshots (0xFFFFFFF0 -> 0x10) adds 0x20
 * to the lifetime count; a year at 1 kHz keeps its percentiles.
 */
static void test_model_life_hist_wrap(void **state)
{
	struct tfx *t = *state;
	struct model m = { 0 };
	struct thread_model *tm = model_get(&m, 42, true);
	__u32 b = hist_bucket(1 * MS), b2 = hist_bucket(3 * MS);
	struct rtsup_metric_stats *s = &t->cur.m[RTSUP_M_PERIOD];
	__u64 want;
	int i;

	assert_non_null(tm);
	t->cur.first_seen = 7;
	metric_init(s);
	s->hist[b] = 0xFFFFFFF0;
	s->count = 0xFFFFFFF0;
	t->cur.cycles = s->count;
	s->min = 1 * MS;
	s->max = 1 * MS;
	model_set(tm, &t->cur, 0);
	assert_int_equal(life_at(tm, RTSUP_M_PERIOD, b), 0xFFFFFFF0ULL);

	s->hist[b] = 0x10;	/* 0x20 more: the __u32 wrapped */
	s->count += 0x20;
	model_set(tm, &t->cur, 1);
	assert_int_equal(life_at(tm, RTSUP_M_PERIOD, b), 0x100000010ULL);
	assert_int_equal(tm->win.m[RTSUP_M_PERIOD].count, 0x20);

	/*
	 * A year at 1 kHz, one snapshot a day: 1 % of the cycles at 3 ms. The
	 * 1 ms bucket wraps seven times; p50 and p99 stay where they are.
	 */
	for (i = 0; i < 365; i++) {
		__u64 day = 86400ULL * 1000;

		s->hist[b] += (__u32)(day - day / 100);
		s->hist[b2] += (__u32)(day / 100);
		s->count += day;
		s->max = 3 * MS;
		model_set(tm, &t->cur, i & 1);
	}
	want = 0x100000010ULL + 365 * (86400ULL * 1000 - 864000);
	assert_int_equal(life_at(tm, RTSUP_M_PERIOD, b), want);
	assert_int_equal(life_at(tm, RTSUP_M_PERIOD, b2), 365 * 864000ULL);
	/*
	 * 1 % at 3 ms: p50 and p99 in the 1 ms bucket, p99.9 at 3 ms. Wrapped
	 * __u32 counts would put p50 anywhere. (Every value sits at the bucket's
	 * low end here, the case interpolation cannot see: within the bucket.)
	 */
	model_life_settle(tm);
	assert_int_equal(hist_bucket(tm->life.m[RTSUP_M_PERIOD].p50), b);
	assert_int_equal(hist_bucket(tm->life.m[RTSUP_M_PERIOD].p99), b);
	assert_int_equal(hist_bucket(tm->life.m[RTSUP_M_PERIOD].p999), b2);
	model_free(&m);
}

static int model_setup(void **state)
{
	struct model *m = calloc(1, sizeof(*m));

	if (!m)
		return -1;
	*state = m;
	return 0;
}

static int model_teardown(void **state)
{
	model_free(*state);
	free(*state);
	return 0;
}

/* check_sorted - the sorted part holds its invariant; after model_sort, all */
static void check_sorted(struct model *m)
{
	int i;

	assert_true(model_sorted(m));
	assert_true(m->n - m->nsorted <= MODEL_TAIL_MAX);
	model_sort(m);
	for (i = 1; i < m->n; i++)
		if (m->t[i - 1]->tid >= m->t[i]->tid)
			fail_msg("not sorted at %d: %u, %u", i, m->t[i - 1]->tid,
				 m->t[i]->tid);
}

/* model_get creates zeroed entries in tid order and finds them again */
static void test_model_get_sorted(void **state)
{
	struct model *m = *state;
	struct thread_model *tm;
	int i;

	assert_null(model_get(m, 42, false));
	for (i = 0; i < 300; i++) {	/* a permutation of 0..299, beyond cap 64 */
		__u32 tid = 1000 + (__u32)(i * 7) % 300;

		tm = model_get(m, tid, true);
		assert_non_null(tm);
		assert_int_equal(tm->tid, tid);
		assert_int_equal(tm->policy, -1);
		assert_false(tm->alive);
		assert_int_equal(tm->nsys, 0);
		tm->tgid = tid + 1;	/* mark it */
		check_sorted(m);
	}
	assert_int_equal(m->n, 300);
	for (i = 0; i < 300; i++) {
		tm = model_get(m, 1000 + (__u32)i, false);
		assert_non_null(tm);
		assert_int_equal(tm->tgid, 1000 + (__u32)i + 1);
	}
	/* getting an existing one with create adds nothing */
	tm = model_get(m, 1150, true);
	assert_int_equal(tm->tgid, 1151);
	assert_int_equal(m->n, 300);
	assert_null(model_get(m, 999, false));
	assert_null(model_get(m, 1300, false));
}

/* a thread's model stays where it is while others come, sort and go */
static void test_model_entries_do_not_move(void **state)
{
	struct model *m = *state;
	struct thread_model *first = model_get(m, 5000, true), *tm;
	int i;

	for (i = 0; i < 1000; i++)	/* grows, sorts the tail, keeps 5000 in the middle */
		model_get(m, (__u32)(i * 7919) % 10000, true);
	for (i = 0; i < 5000; i += 2)
		model_remove(m, (__u32)i);
	model_sort(m);
	tm = model_get(m, 5000, false);
	assert_ptr_equal(tm, first);
	assert_int_equal(tm->tid, 5000);
}

/* model_remove keeps the order; unknown tids are ignored */
static void test_model_remove(void **state)
{
	struct model *m = *state;
	int i;

	for (i = 0; i < 100; i++)
		model_get(m, (__u32)(i * 37) % 100 + 1, true);
	for (i = 1; i <= 100; i += 3)
		model_remove(m, (__u32)i);
	model_remove(m, 5000);
	model_remove(m, 1);		/* already gone */
	check_sorted(m);
	assert_int_equal(m->n, 100 - 34);
	for (i = 1; i <= 100; i++) {
		struct thread_model *tm = model_get(m, (__u32)i, false);

		if ((i - 1) % 3 == 0) {
			assert_null(tm);
		} else {
			assert_non_null(tm);
			assert_int_equal(tm->tid, i);
		}
	}
	/* the first and last can go too */
	model_remove(m, 2);
	model_remove(m, 99);
	check_sorted(m);
	assert_int_equal(m->t[0]->tid, 3);
	assert_int_equal(m->t[m->n - 1]->tid, 98);
	/* re-adding a removed tid lands in place */
	assert_non_null(model_get(m, 4, true));
	check_sorted(m);
	assert_int_equal(m->t[1]->tid, 4);
}

/*
 * A storm of threads arriving in hash order: each is found at once (sorted
 * part or tail), the tail never passes MODEL_TAIL_MAX, removal and pruning
 * from both parts keep the invariant, and model_sort orders them all.
 */
static void test_model_tail_storm(void **state)
{
	struct model *m = *state;
	struct thread_model *tm;
	int i, j;

	for (i = 0; i < 5000; i++) {
		__u32 tid = 10 + (__u32)(i * 7919 % 5000);	/* a permutation: 7919 is prime */

		tm = model_get(m, tid, true);
		assert_non_null(tm);
		assert_int_equal(tm->tid, tid);
		tm->tgid = tid + 1;
		assert_true(model_sorted(m));
		assert_true(m->n - m->nsorted <= MODEL_TAIL_MAX);
		if (i % 97 == 0)	/* every one so far is still found */
			for (j = 0; j <= i; j++)
				assert_non_null(model_get(m, 10 + (__u32)(j * 7919 % 5000),
							  false));
	}
	assert_int_equal(m->n, 5000);
	assert_true(m->nsorted < m->n);	/* a tail is left to sort */
	/* remove from the tail and from the sorted part */
	model_remove(m, m->t[m->n - 1]->tid);
	model_remove(m, m->t[0]->tid);
	assert_true(model_sorted(m));
	/* prune half of them dead, oldest first */
	for (i = 0; i < m->n; i += 2)
		m->t[i]->reported_exit = true;
	model_prune_dead(m, 100);
	assert_true(model_sorted(m));
	assert_int_equal(m->n, 4998 - 2499 + 100);
	for (i = 0; i < m->n; i++)
		assert_int_equal(m->t[i]->tgid, m->t[i]->tid + 1);
	check_sorted(m);
	assert_int_equal(m->nsorted, m->n);
}

/* model_sys_set: adds, updates in place (prev kept), bounded table */
static void test_model_sys_set(void **state)
{
	struct model *m = *state;
	struct thread_model *tm = model_get(m, 7, true);
	int i;

	model_sys_set(tm, 9, 3);
	model_sys_set(tm, 257, 1);
	assert_int_equal(tm->nsys, 2);
	tm->sys[0].prev = 3;		/* end of an interval */
	model_sys_set(tm, 9, 5);
	assert_int_equal(tm->nsys, 2);
	assert_int_equal(tm->sys[0].nr, 9);
	assert_int_equal(tm->sys[0].total, 5);
	assert_int_equal(tm->sys[0].prev, 3);
	assert_int_equal(tm->sys[1].nr, 257);
	assert_int_equal(tm->sys[1].total, 1);
	assert_int_equal(tm->sys[1].prev, 0);

	for (i = 0; i < MODEL_MAX_SYS + 5; i++)
		model_sys_set(tm, 1000 + i, (__u64)i);
	assert_int_equal(tm->nsys, MODEL_MAX_SYS);
	assert_int_equal(tm->sys[MODEL_MAX_SYS - 1].nr, 1000 + MODEL_MAX_SYS - 3);
	/* a full table still updates known entries */
	model_sys_set(tm, 257, 8);
	assert_int_equal(tm->sys[1].total, 8);
}

/* names used in JSON and tables */
static void test_model_names(void **state)
{
	assert_string_equal(unsafe_reason_name(RTSUP_U_SYSCALL), "syscall");
	assert_string_equal(unsafe_reason_name(RTSUP_U_MIGRATE), "migration");
	assert_string_equal(unsafe_reason_name(RTSUP_U_NR), "unknown");
	assert_string_equal(unsafe_reason_name(-1), "unknown");
	assert_string_equal(metric_name(RTSUP_M_LATENCY), "latency_ns");
	assert_string_equal(metric_name(RTSUP_M_NR), "unknown");
	assert_string_equal(policy_name(1), "SCHED_FIFO");
	assert_string_equal(policy_name(6), "SCHED_DEADLINE");
	assert_string_equal(policy_name(-1), "-");
}

#define P(fn) cmocka_unit_test_setup_teardown(fn, pfx_setup, pfx_teardown)
#define TS(fn) cmocka_unit_test_setup_teardown(fn, tfx_setup, pfx_teardown)
#define M(fn) cmocka_unit_test_setup_teardown(fn, model_setup, model_teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		P(test_model_percentile_uniform),
		P(test_model_percentile_expo),
		P(test_model_percentile_bimodal),
		P(test_model_percentile_edges),
		P(test_model_percentile_window),
		P(test_model_percentile_5333),
		P(test_model_percentile_range),
		P(test_model_view_window),
		P(test_model_view_window_no_prev),
		TS(test_model_span_window),
		TS(test_model_span_window_restart),
		TS(test_model_span_window_restart_more_cycles),
		TS(test_model_set_snapshots),
		TS(test_model_life_hist_wrap),
		TS(test_model_views_follow_moving_buckets),
		TS(test_model_buckets_outside_the_banks),
		TS(test_model_why_alone_is_no_change),
		TS(test_model_short_copy_as_whole),
		TS(test_model_short_copy_refused),
		TS(test_model_torn_copy_takes_no_short),
		TS(test_model_idle_snapshot_keeps_life_views),
		TS(test_model_life_holds_counts_before_the_first_cycle),
		M(test_model_get_sorted),
		M(test_model_entries_do_not_move),
		M(test_model_remove),
		M(test_model_tail_storm),
		M(test_model_sys_set),
		cmocka_unit_test(test_model_names),
	};

	return cmocka_run_group_tests_name("model", tests, NULL, NULL);
}
