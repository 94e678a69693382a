// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_clockoff.c - user/collect/clockoff.c: the offset comes from the
 * narrowest bracket, at its midpoint, with half its width as the error;
 * a held offset changes only by more than the readings' errors; a real
 * read of CLOCK_MONOTONIC against itself is within the error it gives.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "collect/clockoff.h"

/* the preempted read (1 ms between its monotonic reads) is not the one taken */
static void test_pick_narrowest_midpoint(void **state)
{
	const struct clock_bracket b[] = {
		{ 1000, 5001000, 1001000 },	/* preempted after the clock read: off by 0.5 ms */
		{ 2000000, 7000100, 2000200 },	/* 200 ns wide: 7000100 - 2000100 */
		{ 3000000, 8000300, 3000400 },	/* 400 ns wide */
	};
	const struct clock_bracket odd = { 0, 10, 3 };
	struct clock_offset o;

	o = clockoff_pick(b, 3);
	assert_int_equal(o.off, 5000000);
	assert_int_equal(o.err, 100);
	/* one bracket: its own midpoint, whatever its width */
	o = clockoff_pick(b, 1);
	assert_int_equal(o.off, 5001000 - 501000);
	assert_int_equal(o.err, 500000);
	/* an odd width: the error rounds up, the truth (7..10) within 9 +- 2 */
	o = clockoff_pick(&odd, 1);
	assert_int_equal(o.off, 9);
	assert_int_equal(o.err, 2);
	(void)state;
}

/* readings within their errors are one offset: the narrower is held; a step replaces it */
static void test_keep_until_stepped(void **state)
{
	const struct clock_offset none = { 0, -1 }, a = { 1000, 100 }, b = { 1150, 50 },
				  wide = { 1500, 5000 }, step = { 5000001000, 80 };
	struct clock_offset o;

	o = clockoff_keep((struct clock_offset){ 0, 0 }, a, true);	/* the first reading */
	assert_int_equal(o.off, 1000);
	o = clockoff_keep(a, b, false);	/* 150 apart, errors 150: the same, b narrower */
	assert_int_equal(o.off, 1150);
	assert_int_equal(o.err, 50);
	o = clockoff_keep(b, wide, false);	/* a preempted reading does not move it */
	assert_int_equal(o.off, 1150);
	o = clockoff_keep(b, a, false);	/* nor does a wider one within the errors */
	assert_int_equal(o.off, 1150);
	o = clockoff_keep(b, step, false);	/* +5 s: taken, whatever its width */
	assert_int_equal(o.off, 5000001000);
	o = clockoff_keep(b, (struct clock_offset){ 1351, 150 }, false);	/* 201 > 200: moved */
	assert_int_equal(o.off, 1351);
	o = clockoff_keep(b, a, true);	/* a step the clock watch saw: taken, however small */
	assert_int_equal(o.off, 1000);
	o = clockoff_keep(b, none, false);	/* an unreadable clock: the held offset stays */
	assert_int_equal(o.off, 1150);
	o = clockoff_keep(b, none, true);	/* stepped or not */
	assert_int_equal(o.off, 1150);
	(void)state;
}

/* CLOCK_MONOTONIC against itself: offset 0 within the bound it gives */
static void test_read_monotonic_is_zero(void **state)
{
	struct clock_offset o = clockoff_read(CLOCK_MONOTONIC);

	assert_true(o.err >= 0);
	assert_true(o.off <= o.err && o.off >= -o.err);
	(void)state;
}

/* a clock that cannot be read: no offset claimed */
static void test_read_bad_clock(void **state)
{
	struct clock_offset o = clockoff_read((clockid_t)-1000);

	assert_true(o.err < 0);
	(void)state;
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pick_narrowest_midpoint),
		cmocka_unit_test(test_keep_until_stepped),
		cmocka_unit_test(test_read_monotonic_is_zero),
		cmocka_unit_test(test_read_bad_clock),
	};

	return cmocka_run_group_tests_name("clockoff", tests, NULL, NULL);
}
