// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_pidns.c - user/collect/pidns.c: the levels of NSpid in /proc/<pid>/status */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include "collect/pidns.h"

static void test_nspid_levels(void **state)
{
	assert_int_equal(nspid_levels("Name:\tx\nNSpid:\t1234\nNSpgid:\t1234\n"), 1);
	/* seen from the host's /proc: the host's pid, then the container's */
	assert_int_equal(nspid_levels("Tgid:\t9\nNSpid:\t24358\t2\nNSsid:\t1\n"), 2);
	assert_int_equal(nspid_levels("NSpid:\t5\t4\t1"), 3);
	/* kernels before 4.1 have no NSpid line */
	assert_int_equal(nspid_levels("Name:\tx\nPid:\t3\n"), 0);
	/* only the line's own start counts */
	assert_int_equal(nspid_levels("Name:\txNSpid: 1 2\nNSpid:\t7\n"), 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_nspid_levels),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
