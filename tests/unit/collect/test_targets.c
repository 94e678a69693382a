// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_targets.c - the CPU list shown for a thread's affinity; kernel threads from /proc */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "collect/targets.h"

#define W (8 * (int)sizeof(unsigned long))

static void set(unsigned long *bits, int c)
{
	bits[c / W] |= 1UL << (c % W);
}

static void test_cpu_list_ranges(void **state)
{
	unsigned long bits[1024 / W] = { 0 };
	char buf[64];

	(void)state;
	set(bits, 0);
	set(bits, 1);
	set(bits, 2);
	set(bits, 3);
	set(bits, 6);
	set(bits, 63);
	set(bits, 64);
	set(bits, 1023);
	cpu_list_mask(bits, 1024, buf, sizeof(buf));
	assert_string_equal(buf, "0-3,6,63-64,1023");
}

static void test_cpu_list_empty_and_single(void **state)
{
	unsigned long bits[128 / W] = { 0 };
	char buf[16];

	(void)state;
	cpu_list_mask(bits, 128, buf, sizeof(buf));
	assert_string_equal(buf, "");
	set(bits, 5);
	cpu_list_mask(bits, 64, buf, sizeof(buf));
	assert_string_equal(buf, "5");
}

/* the kernel's CPU lists read back: what cpu_list_mask writes, and bad text */
static void test_cpu_list_parse(void **state)
{
	unsigned long bits[1024 / W], back[1024 / W] = { 0 };
	char buf[64];

	(void)state;
	assert_int_equal(cpu_list_parse("0-3,6,63-64,1023\n", bits, 1024), 0);
	set(back, 0), set(back, 1), set(back, 2), set(back, 3), set(back, 6);
	set(back, 63), set(back, 64), set(back, 1023);
	assert_memory_equal(bits, back, sizeof(bits));
	cpu_list_mask(bits, 1024, buf, sizeof(buf));
	assert_string_equal(buf, "0-3,6,63-64,1023");
	/* CPUs past the mask are left out, not written past it */
	assert_int_equal(cpu_list_parse("1,100-200", bits, 128), 0);
	cpu_list_mask(bits, 128, buf, sizeof(buf));
	assert_string_equal(buf, "1,100-127");
	assert_int_equal(cpu_list_parse("", bits, 64), 0);
	assert_int_equal(bits[0], 0);
	assert_int_equal(cpu_list_parse("3-1", bits, 64), -EINVAL);
	assert_int_equal(cpu_list_parse("a", bits, 64), -EINVAL);
	assert_int_equal(cpu_list_parse("1;2", bits, 64), -EINVAL);
	assert_int_equal(cpu_list_parse("-1", bits, 64), -EINVAL);
}

/* a list longer than the buffer is cut, never overrun */
static void test_cpu_list_truncated(void **state)
{
	unsigned long bits[256 / W] = { 0 };
	char buf[8];
	int c;

	(void)state;
	for (c = 0; c < 256; c += 2)
		set(bits, c);
	cpu_list_mask(bits, 256, buf, sizeof(buf));
	assert_true(strlen(buf) < sizeof(buf));
	assert_memory_equal(buf, "0,2,4,6", 7);
}

/* the flags field of /proc/<pid>/stat, after a name with spaces and ')' */
static void test_stat_flags_kthread(void **state)
{
	const char *k = "42 (watchdogd) S 2 0 0 0 -1 2129984 0 0 0 0 0 0 0 0 -51 0 1 0 4 0 0";
	const char *u = "1234 (a) b) c) S 1 1234 1234 0 -1 4194560 99 0 0 0 1 2 0 0 -21 0 3 0";

	assert_true(stat_flags(k) & TARGETS_PF_KTHREAD);
	assert_int_equal(stat_flags(u), 4194560);
	assert_false(stat_flags(u) & TARGETS_PF_KTHREAD);
	assert_int_equal(stat_flags("garbage"), 0);
	assert_int_equal(stat_flags("1 (x) S"), 0);
}

/* this process is no kernel thread; kthreadd (pid 2) is one, where it is visible */
static void test_thread_is_kernel_here(void **state)
{
	char comm[RTSUP_COMM_LEN];

	assert_false(thread_is_kernel(getpid(), getpid()));
	if (!thread_comm(2, 2, comm, sizeof(comm)) && !strcmp(comm, "kthreadd"))
		assert_true(thread_is_kernel(2, 2));
}

static int count_tid(void *arg, pid_t tid)
{
	(void)tid;
	(*(int *)arg)++;
	return 0;
}

/* /proc text that was read but did not parse is counted; a file gone empty is not */
static void test_parse_errors_counted(void **state)
{
	static char status[] = "Name:\tx\nPid:\t12\n", good[] = "Name:\tx\nTgid:\t7\n", threads[] = "12\n13\nxyz\n14\n";
	__u64 n0 = targets_parse_errors();
	int n = 0;
	FILE *f;

	(void)state;
	f = fmemopen(good, strlen(good), "r");
	assert_int_equal(status_tgid(f), 7);
	fclose(f);
	assert_int_equal(targets_parse_errors(), n0);
	f = fopen("/dev/null", "r");	/* what a thread gone meanwhile reads */
	assert_int_equal(status_tgid(f), -1);
	fclose(f);
	assert_int_equal(targets_parse_errors(), n0);
	f = fmemopen(status, strlen(status), "r");
	assert_int_equal(status_tgid(f), -1);
	fclose(f);
	assert_int_equal(targets_parse_errors(), n0 + 1);
	assert_int_equal(stat_flags("12 (x) S 1 2 3"), 0);
	assert_int_equal(targets_parse_errors(), n0 + 2);
	f = fmemopen(threads, strlen(threads), "r");
	assert_int_equal(cgroup_threads(f, count_tid, &n), 0);
	fclose(f);
	assert_int_equal(n, 2);
	assert_int_equal(targets_parse_errors(), n0 + 3);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_cpu_list_ranges),
		cmocka_unit_test(test_cpu_list_empty_and_single),
		cmocka_unit_test(test_cpu_list_parse),
		cmocka_unit_test(test_cpu_list_truncated),
		cmocka_unit_test(test_stat_flags_kthread),
		cmocka_unit_test(test_thread_is_kernel_here),
		cmocka_unit_test(test_parse_errors_counted),
	};

	return cmocka_run_group_tests_name("targets", tests, NULL, NULL);
}
