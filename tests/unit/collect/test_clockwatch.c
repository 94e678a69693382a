// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_clockwatch.c - user/collect/clockwatch.c: the timer arms and reads
 * "no step" while the clock is left alone. A real step (date -s) is
 * test_faults.py's, inside the RT guest: a unit test must not set the
 * machine's clock.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <unistd.h>
#include <cmocka.h>

#include "collect/clockwatch.h"

static void test_clockwatch_no_step(void **state)
{
	int fd = clockwatch_open();

	assert_true(fd >= 0);
	assert_int_equal(clockwatch_stepped(fd), 0);
	assert_int_equal(clockwatch_stepped(fd), 0);
	close(fd);
	/* a closed descriptor is an error, never a step */
	assert_true(clockwatch_stepped(fd) < 0);
	(void)state;
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_clockwatch_no_step),
	};

	return cmocka_run_group_tests_name("clockwatch", tests, NULL, NULL);
}
