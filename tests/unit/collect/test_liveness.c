// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_liveness.c - user/collect/liveness.h: a failed or partial read of the thread
 * map never makes a live thread dead (issue 12, item 7).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "collect/liveness.h"

/* an entry that was read: dead only if the kernel recorded its exit */
static void test_liveness_present(void **state)
{
	assert_false(thread_dead(true, true, false));
	assert_true(thread_dead(true, true, true));
	/* entries read before the read failed count as read */
	assert_false(thread_dead(false, true, false));
	assert_true(thread_dead(false, true, true));
}

/* an entry missing from a whole read: the entry was freed, the thread is gone */
static void test_liveness_absent_complete_read(void **state)
{
	assert_true(thread_dead(true, false, false));
}

/* an entry the read never reached (it failed half-way): nothing is known */
static void test_liveness_absent_partial_read(void **state)
{
	assert_false(thread_dead(false, false, false));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_liveness_present),
		cmocka_unit_test(test_liveness_absent_complete_read),
		cmocka_unit_test(test_liveness_absent_partial_read),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
