// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_selfsched.c - user/collect/selfsched.c: the loop's CPU and run-queue time */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>
#include <setjmp.h>
#include <cmocka.h>
#include "collect/selfsched.h"

static void test_parse(void **state)
{
	struct self_sched s;

	assert_int_equal(self_sched_parse("2500000000 750000 1234\n", &s), 0);
	assert_int_equal(s.cpu_ns, 2500000000ULL);
	assert_int_equal(s.wait_ns, 750000);
	/* past 2^32 ns (4.3 s): the counters are 64-bit */
	assert_int_equal(self_sched_parse("18446744073709551615 5000000000 1", &s), 0);
	assert_true(s.cpu_ns == UINT64_MAX && s.wait_ns == 5000000000ULL);
	assert_int_equal(self_sched_parse("", &s), -EINVAL);
	assert_int_equal(self_sched_parse("12\n", &s), -EINVAL);
	assert_int_equal(self_sched_parse("x y z", &s), -EINVAL);
}

static void test_span(void **state)
{
	struct self_sched a = { 1000000000, 200000000 }, b = { 1250000000, 1200000000 };
	struct self_span sp = self_span_since(&a, &b, true);

	assert_float_equal(sp.cpu_s, 0.25, 1e-12);
	assert_float_equal(sp.wait_s, 1.0, 1e-12);
	/* not read, or going back (not the same thread's): unknown, never negative */
	sp = self_span_since(&a, &b, false);
	assert_true(sp.cpu_s < 0 && sp.wait_s < 0);
	sp = self_span_since(&b, &a, true);
	assert_true(sp.cpu_s < 0 && sp.wait_s < 0);
}

static void test_read_own_thread(void **state)
{
	struct self_sched s;
	struct timespec t0, t;
	int err;

	/* 2 ms of CPU: the thread's clock has seen it, however young the thread */
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
	do
		clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	while ((t.tv_sec - t0.tv_sec) * 1000000000L + t.tv_nsec - t0.tv_nsec < 2000000);
	err = self_sched_read(&s);

	/* a kernel without CONFIG_SCHED_INFO has no schedstat file */
	if (err == -ENOENT)
		skip();
	assert_int_equal(err, 0);
	assert_true(s.cpu_ns >= 2000000);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_parse),
		cmocka_unit_test(test_span),
		cmocka_unit_test(test_read_own_thread),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
