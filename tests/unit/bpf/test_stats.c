// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_stats.c - EWMA, metric_add and thread_account_cycle (include/stats.h) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "stats.h"

#define FIX_ONE	(1 << RTSUP_EWMA_SHIFT)

static double ewma_value(__s64 ewma)
{
	return (double)ewma / FIX_ONE;
}

/*
 * run_ewma - feed a value sequence to ewma_update and to a double-precision
 * reference with the same weight w/1024; compare after every step. Each
 * fixed-point step truncates by less than 1/256, and older errors decay by
 * (1 - w/1024), so the error stays below (1/256) * 1024 / w.
 */
static void run_ewma(__u32 w, const __u64 *v, int n)
{
	double ref = 0, tol = (1.0 / FIX_ONE) * RTSUP_EWMA_ONE / w + 1e-9;
	double a = (double)w / RTSUP_EWMA_ONE;
	__s64 e = 0;
	int i;

	for (i = 0; i < n; i++) {
		e = ewma_update(e, (__u64)i, v[i], w);
		ref = i == 0 ? (double)v[i] : ref + a * ((double)v[i] - ref);
		if (fabs(ewma_value(e) - ref) > tol)
			fail_msg("w=%u step %d: ewma %f ref %f", w, i,
				 ewma_value(e), ref);
	}
}

/* a sequence with steps up and down, spikes and a long steady tail */
static int make_sequence(__u64 *v, int max)
{
	static const __u64 head[] = {
		1000000, 1000000, 1000003, 999990, 2500000, 12, 0, 750000,
		1000000, 1, 7, 123456789, 1000000, 1000001,
	};
	unsigned int seed = 42;
	int n = 0, i;

	for (i = 0; i < (int)(sizeof(head) / sizeof(head[0])) && n < max; i++)
		v[n++] = head[i];
	while (n < max) {
		seed = seed * 1103515245 + 12345;
		v[n++] = 900000 + (seed >> 8) % 200000;
	}
	return n;
}

/*
 * test_stats_ewma_huge - a value near 2^55 ns (a damaged recorded trace,
 * found by fuzz_record) wraps like the CPU instead of overflowing a signed
 * product: make sanitize runs this under UBSan; ordinary values are unchanged
 */
static void test_stats_ewma_huge(void **state)
{
	__s64 e = ewma_update(0, 0, 1000000, 102);

	e = ewma_update(e, 1, 1ULL << 55, 102);
	e = ewma_update(e, 2, 1000000, 1024);
	assert_true(ewma_value(e) == 1000000.0);
	e = ewma_update(ewma_update(0, 0, 1000, 512), 1, 3000, 512);
	assert_true(ewma_value(e) == 2000.0);
}

/* weight 102/1024 (about 0.1) tracks the double reference */
static void test_stats_ewma_weight_01(void **state)
{
	__u64 v[500];
	int n = make_sequence(v, 500);

	run_ewma(102, v, n);
}

/* weight 512/1024 tracks the double reference */
static void test_stats_ewma_weight_05(void **state)
{
	__u64 v[500];
	int n = make_sequence(v, 500);

	run_ewma(512, v, n);
}

/* weight 1024/1024: the EWMA is exactly the last value */
static void test_stats_ewma_weight_1(void **state)
{
	__u64 v[100];
	__s64 e = 0;
	int n = make_sequence(v, 100), i;

	run_ewma(RTSUP_EWMA_ONE, v, n);
	for (i = 0; i < n; i++) {
		e = ewma_update(e, (__u64)i, v[i], RTSUP_EWMA_ONE);
		assert_int_equal(e, (__s64)(v[i] << RTSUP_EWMA_SHIFT));
	}
}

/* the first value (count 0) sets the EWMA, whatever the old value */
static void test_stats_ewma_first_value(void **state)
{
	assert_int_equal(ewma_update(0, 0, 1234, 102), 1234 << RTSUP_EWMA_SHIFT);
	assert_int_equal(ewma_update(999999, 0, 5, 102), 5 << RTSUP_EWMA_SHIFT);
	/* count 1: moves by w/1024 of the difference, here exactly 1/2 */
	assert_int_equal(ewma_update(100 << RTSUP_EWMA_SHIFT, 1, 300, 512),
			 200 << RTSUP_EWMA_SHIFT);
	/* and downwards */
	assert_int_equal(ewma_update(300 << RTSUP_EWMA_SHIFT, 1, 100, 512),
			 200 << RTSUP_EWMA_SHIFT);
}

static int stats_setup(void **state)
{
	struct rtsup_metric_stats *s = calloc(1, sizeof(*s));

	if (!s)
		return -1;
	metric_init(s);
	*state = s;
	return 0;
}

static int stats_teardown(void **state)
{
	free(*state);
	return 0;
}

static __u32 hist_total(const struct rtsup_metric_stats *s)
{
	__u32 n = 0;
	int b;

	for (b = 0; b < HIST_BUCKETS; b++)
		n += s->hist[b];
	return n;
}

/* metric_add: count, sum, min, max, EWMA and one histogram entry per value */
static void test_stats_metric_add_basic(void **state)
{
	struct rtsup_metric_stats *s = *state;
	static const __u64 v[] = { 500, 200, 900, 200, 1000000 };
	unsigned int i;

	assert_int_equal(s->count, 0);
	assert_true(s->min == ~0ULL);
	for (i = 0; i < 5; i++)
		metric_add(s, v[i], 102, 0);
	assert_int_equal(s->count, 5);
	assert_int_equal(s->sum, 500 + 200 + 900 + 200 + 1000000);
	assert_int_equal(s->min, 200);
	assert_int_equal(s->max, 1000000);
	assert_int_equal(hist_total(s), 5);
	assert_int_equal(s->hist[hist_bucket(200)], 2);
	assert_int_equal(s->hist[hist_bucket(1000000)], 1);
	/* first value set the EWMA: 500, then moved towards the others */
	assert_true(s->ewma != 0);
}

/* metric_add writes min/max only into the bank of its epoch (epoch & 1) */
static void test_stats_metric_add_banks(void **state)
{
	struct rtsup_metric_stats *s = *state;

	metric_add(s, 100, 102, 0);
	metric_add(s, 300, 102, 0);
	assert_int_equal(s->win[0].min, 100);
	assert_int_equal(s->win[0].max, 300);
	assert_true(s->win[1].min == ~0ULL);
	assert_int_equal(s->win[1].max, 0);

	metric_add(s, 50, 102, 1);
	metric_add(s, 70, 102, 3);	/* odd epoch: bank 1 too */
	assert_int_equal(s->win[1].min, 50);
	assert_int_equal(s->win[1].max, 70);
	assert_int_equal(s->win[0].min, 100);
	assert_int_equal(s->win[0].max, 300);

	/* a bank reset only touches that bank; lifetime stays */
	minmax_reset(&s->win[0]);
	metric_add(s, 2000, 102, 2);
	assert_int_equal(s->win[0].min, 2000);
	assert_int_equal(s->win[0].max, 2000);
	assert_int_equal(s->win[1].min, 50);
	assert_int_equal(s->min, 50);
	assert_int_equal(s->max, 2000);
	assert_int_equal(s->count, 5);
}

/* metric_init empties the statistics, histogram included */
static void test_stats_metric_init_empties(void **state)
{
	struct rtsup_metric_stats *s = *state;

	metric_add(s, 100, 102, 0);
	metric_add(s, 5000, 102, 1);
	metric_init(s);
	assert_int_equal(s->count, 0);
	assert_int_equal(s->sum, 0);
	assert_true(s->min == ~0ULL);
	assert_int_equal(s->max, 0);
	assert_true(s->win[0].min == ~0ULL);
	assert_true(s->win[1].min == ~0ULL);
	assert_int_equal(hist_total(s), 0);
}

/* zeroed memory (a new map entry, no metric_init): the first value is min */
static void test_stats_metric_add_zeroed_min(void **state)
{
	struct rtsup_metric_stats *s = *state;

	memset(s, 0, sizeof(*s));
	metric_add(s, 700, 102, 0);
	metric_add(s, 900, 102, 0);
	metric_add(s, 800, 102, 0);
	assert_int_equal(s->min, 700);
	assert_int_equal(s->max, 900);
	assert_int_equal(s->count, 3);
}

static int thread_setup(void **state)
{
	struct rtsup_thread *t = calloc(1, sizeof(*t));
	int i;

	if (!t)
		return -1;
	for (i = 0; i < RTSUP_M_NR; i++)
		metric_init(&t->m[i]);
	*state = t;
	return 0;
}

/* cycle - a finished cycle with the given flags */
static struct rtsup_cycle cycle(__u32 flags, __u64 period, __u64 exec,
				__u64 cpu, __u64 latency)
{
	struct rtsup_cycle c;

	memset(&c, 0, sizeof(c));
	c.start = 5000000;
	c.period = period;
	c.exec = exec;
	c.cpu = cpu;
	c.latency = latency;
	c.flags = flags;
	return c;
}

/* first cycle: no period, and no latency without an expected release */
static void test_stats_account_first_cycle(void **state)
{
	struct rtsup_thread *t = *state;
	struct rtsup_cycle c = cycle(0, 0, 300, 250, 0);

	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->cycles, 1);
	assert_int_equal(t->last_cycle, 5000000);
	assert_int_equal(t->misses, 0);
	assert_int_equal(t->overruns, 0);
	assert_int_equal(t->m[RTSUP_M_PERIOD].count, 0);
	assert_int_equal(t->m[RTSUP_M_LATENCY].count, 0);
	assert_int_equal(t->m[RTSUP_M_EXEC].count, 1);
	assert_int_equal(t->m[RTSUP_M_EXEC].sum, 300);
	assert_int_equal(t->m[RTSUP_M_CPU].count, 1);
	assert_int_equal(t->m[RTSUP_M_CPU].sum, 250);
}

/* period and latency are added only with their flags */
static void test_stats_account_period_latency(void **state)
{
	struct rtsup_thread *t = *state;
	struct rtsup_cycle c;

	c = cycle(RTSUP_CF_HAS_PERIOD, 1000000, 300, 250, 77);
	thread_account_cycle(t, &c, 102, 0);
	c = cycle(RTSUP_CF_HAS_PERIOD | RTSUP_CF_HAS_LATENCY, 1000010, 310, 260, 12);
	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->cycles, 2);
	assert_int_equal(t->m[RTSUP_M_PERIOD].count, 2);
	assert_int_equal(t->m[RTSUP_M_PERIOD].sum, 2000010);
	assert_int_equal(t->m[RTSUP_M_LATENCY].count, 1);
	assert_int_equal(t->m[RTSUP_M_LATENCY].sum, 12);	/* not 77 */
	assert_int_equal(t->m[RTSUP_M_LATENCY].min, 12);
}

/* a missed deadline and an overrun are counted apart */
static void test_stats_account_miss_overrun(void **state)
{
	struct rtsup_thread *t = *state;
	struct rtsup_cycle c;

	c = cycle(RTSUP_CF_MISS, 0, 300, 250, 0);
	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->misses, 1);
	assert_int_equal(t->overruns, 0);
	c = cycle(RTSUP_CF_MISS | RTSUP_CF_OVERRUN, 0, 3000000, 2900000, 0);
	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->misses, 2);
	assert_int_equal(t->overruns, 1);
	c = cycle(RTSUP_CF_OVERRUN, 0, 3000000, 2900000, 0);
	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->misses, 2);
	assert_int_equal(t->overruns, 2);
	assert_int_equal(t->cycles, 3);
}

/* page faults of a cycle go to the thread and to its unsafe reasons */
static void test_stats_account_faults(void **state)
{
	struct rtsup_thread *t = *state;
	struct rtsup_cycle c = cycle(0, 0, 300, 250, 0);

	c.minflt = 3;
	c.majflt = 1;
	thread_account_cycle(t, &c, 102, 0);
	thread_account_cycle(t, &c, 102, 0);
	assert_int_equal(t->minflt, 6);
	assert_int_equal(t->majflt, 2);
	assert_int_equal(t->unsafe[RTSUP_U_MINFLT], 6);
	assert_int_equal(t->unsafe[RTSUP_U_MAJFLT], 2);
	assert_int_equal(t->unsafe[RTSUP_U_SYSCALL], 0);
}

/* the epoch selects the bank of every metric of the cycle */
static void test_stats_account_epoch_bank(void **state)
{
	struct rtsup_thread *t = *state;
	struct rtsup_cycle c;

	c = cycle(RTSUP_CF_HAS_PERIOD | RTSUP_CF_HAS_LATENCY, 1000000, 300, 250, 9);
	thread_account_cycle(t, &c, 102, 1);
	assert_int_equal(t->m[RTSUP_M_EXEC].win[1].min, 300);
	assert_int_equal(t->m[RTSUP_M_CPU].win[1].max, 250);
	assert_int_equal(t->m[RTSUP_M_PERIOD].win[1].min, 1000000);
	assert_int_equal(t->m[RTSUP_M_LATENCY].win[1].max, 9);
	assert_true(t->m[RTSUP_M_EXEC].win[0].min == ~0ULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stats_ewma_huge),
		cmocka_unit_test(test_stats_ewma_weight_01),
		cmocka_unit_test(test_stats_ewma_weight_05),
		cmocka_unit_test(test_stats_ewma_weight_1),
		cmocka_unit_test(test_stats_ewma_first_value),
		cmocka_unit_test_setup_teardown(test_stats_metric_add_basic,
						stats_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_metric_add_banks,
						stats_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_metric_init_empties,
						stats_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_metric_add_zeroed_min,
						stats_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_account_first_cycle,
						thread_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_account_period_latency,
						thread_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_account_miss_overrun,
						thread_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_account_faults,
						thread_setup, stats_teardown),
		cmocka_unit_test_setup_teardown(test_stats_account_epoch_bank,
						thread_setup, stats_teardown),
	};

	return cmocka_run_group_tests_name("stats", tests, NULL, NULL);
}
