// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_overhead.c - user/judge/overhead.h: the overhead check's measure is
 * our programs' own run time, the statistics' floor taken off each run.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "judge/overhead.h"

/* numbers of a getppid flood on the development VM: 4.2 M runs a second */
static void test_floor_taken_off_each_run(void **state)
{
	struct stats_window w = { .wall_ns = 100000000, .runs = 421728,
				  .run_ns = 421728ULL * 61, .floor_ns = 52 };

	/* 9 ns a run of our own, 3.8 % of a CPU; raw, it read 25.7 % */
	assert_float_equal(stats_own_ns(&w), 421728.0 * 9, 1);
	assert_float_equal(stats_overhead_pct(&w), 3.795552, 1e-6);
}

/* a floor measured above what the runs took (a colder calibration) is 0, not less */
static void test_never_below_zero(void **state)
{
	struct stats_window w = { .wall_ns = 100000000, .runs = 1000, .run_ns = 40000,
				  .floor_ns = 52 };

	assert_float_equal(stats_overhead_pct(&w), 0, 0);
}

/* no floor (the kernel refused the empty program): the raw time stands */
static void test_unknown_floor_keeps_raw(void **state)
{
	struct stats_window w = { .wall_ns = 100000000, .runs = 1000, .run_ns = 1000000,
				  .floor_ns = -1 };

	assert_float_equal(stats_overhead_pct(&w), 1.0, 1e-9);
}

/* no window closed yet: unknown */
static void test_no_window_unknown(void **state)
{
	struct stats_window w = { .floor_ns = -1 };

	assert_true(stats_overhead_pct(&w) < 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_floor_taken_off_each_run),
		cmocka_unit_test(test_never_below_zero),
		cmocka_unit_test(test_unknown_floor_keeps_raw),
		cmocka_unit_test(test_no_window_unknown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
