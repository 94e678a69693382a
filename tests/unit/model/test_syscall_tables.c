// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_syscall_tables.c - scripts/gen-syscalls on each architecture: the
 * numbers the kernel uses, aliases (__NR3264_*) resolved.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "syscall_table_x86_64.h"
#include "syscall_table_i386.h"
#include "syscall_table_arm64.h"
#include "syscall_table.h"

#define NR_OF(table, name) nr_of(table, sizeof(table) / sizeof(table[0]), name)

static int nr_of(const void *table, size_t n, const char *name)
{
	const struct { const char *name; int nr; } *t = table;
	size_t i;

	for (i = 0; i < n; i++)
		if (!strcmp(t[i].name, name))
			return t[i].nr;
	return -1;
}

/* arm64 takes mmap, fstat and newfstatat from __NR3264_* aliases */
static void test_syscall_tables_arm64_aliases(void **state)
{
	assert_int_equal(NR_OF(syscall_table_arm64, "mmap"), 222);
	assert_int_equal(NR_OF(syscall_table_arm64, "fstat"), 80);
	assert_int_equal(NR_OF(syscall_table_arm64, "newfstatat"), 79);
	assert_int_equal(NR_OF(syscall_table_arm64, "openat"), 56);
	assert_int_equal(NR_OF(syscall_table_arm64, "clock_nanosleep"), 115);
	assert_int_equal(NR_OF(syscall_table_arm64, "restart_syscall"), 128);
	/* arm64 has no open, no 32-bit time calls */
	assert_int_equal(NR_OF(syscall_table_arm64, "open"), -1);
	assert_int_equal(NR_OF(syscall_table_arm64, "clock_nanosleep_time64"), -1);
}

static void test_syscall_tables_x86_64(void **state)
{
	assert_int_equal(NR_OF(syscall_table_x86_64, "mmap"), 9);
	assert_int_equal(NR_OF(syscall_table_x86_64, "openat"), 257);
	assert_int_equal(NR_OF(syscall_table_x86_64, "clock_nanosleep"), 230);
	assert_int_equal(NR_OF(syscall_table_x86_64, "newfstatat"), 262);
}

/* ia32 programs on x86_64 use other numbers, and a 64-bit time variant */
static void test_syscall_tables_i386(void **state)
{
	assert_int_equal(NR_OF(syscall_table_i386, "mmap"), 90);
	assert_int_equal(NR_OF(syscall_table_i386, "clock_nanosleep"), 267);
	assert_int_equal(NR_OF(syscall_table_i386, "clock_nanosleep_time64"), 407);
}

/*
 * The build's own table (syscall_table.h, what rtsup-trace classifies
 * with) is the target's: a cross build (make ARCH=arm64) must not take
 * the build host's numbers. Compared entry by entry, both ways.
 */
static void test_syscall_tables_build_is_target(void **state)
{
#if defined(__aarch64__)
#define TARGET syscall_table_arm64
#elif defined(__x86_64__)
#define TARGET syscall_table_x86_64
#endif
#ifdef TARGET
	size_t i, n = sizeof(syscall_table) / sizeof(syscall_table[0]);

	for (i = 0; i < n; i++)
		assert_int_equal(NR_OF(TARGET, syscall_table[i].name), syscall_table[i].nr);
	for (i = 0; i < sizeof(TARGET) / sizeof(TARGET[0]); i++)
		assert_int_equal(NR_OF(syscall_table, TARGET[i].name), TARGET[i].nr);
	assert_int_equal(NR_OF(syscall_table, "mmap"), NR_OF(TARGET, "mmap"));
#else
	skip();
#endif
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_syscall_tables_arm64_aliases),
		cmocka_unit_test(test_syscall_tables_x86_64),
		cmocka_unit_test(test_syscall_tables_i386),
		cmocka_unit_test(test_syscall_tables_build_is_target),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
