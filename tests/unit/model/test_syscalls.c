// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_syscalls.c - syscall names and the RT-safety class table */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "model/syscalls.h"
#include "rtsup.h"

static const char *const default_delims[] = { "clock_nanosleep", "nanosleep" };

/* Fixture: a class table as big as the kernel's. */
struct sfx {
	__u32 table[RTSUP_MAX_SYSCALLS];
	char err[128];
};

static int sfx_setup(void **state)
{
	struct sfx *s = calloc(1, sizeof(*s));

	if (!s)
		return -1;
	*state = s;
	return 0;
}

static int sfx_teardown(void **state)
{
	free(*state);
	return 0;
}

/* cls - the class bits of a syscall name in the built table */
static __u32 cls(const struct sfx *s, const char *name)
{
	int nr = syscall_nr(name);

	assert_true(nr >= 0 && nr < RTSUP_MAX_SYSCALLS);
	return s->table[nr];
}

/* name -> number -> name for a few syscalls every architecture has */
static void test_syscalls_round_trip(void **state)
{
	static const char *const names[] = { "clock_nanosleep", "mmap", "openat",
					     "write", "epoll_pwait" };
	unsigned int i;

	for (i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
		int nr = syscall_nr(names[i]);

		assert_true(nr >= 0);
		assert_non_null(syscall_name(nr));
		assert_string_equal(syscall_name(nr), names[i]);
	}
	/* different syscalls, different numbers */
	assert_int_not_equal(syscall_nr("mmap"), syscall_nr("openat"));
}

/* unknown names and numbers */
static void test_syscalls_unknown(void **state)
{
	assert_int_equal(syscall_nr("no_such_syscall"), -1);
	assert_int_equal(syscall_nr(""), -1);
	assert_int_equal(syscall_nr("mmap "), -1);	/* exact match only */
	assert_null(syscall_name(-1));
	assert_null(syscall_name(100000));
}

/* the unsafe categories */
static void test_syscalls_category(void **state)
{
	assert_string_equal(syscall_category("mmap"), "memory");
	assert_string_equal(syscall_category("openat"), "file");
	assert_string_equal(syscall_category("write"), "file");
	assert_string_equal(syscall_category("clone"), "process");
	assert_string_equal(syscall_category("clock_nanosleep"), "sleep");
	assert_string_equal(syscall_category("sched_yield"), "yield");
	assert_null(syscall_category("getpid"));
	assert_null(syscall_category("no_such_syscall"));
}

/* default delimiters: memory and files unsafe, the sleeps are delimiters */
static void test_syscalls_sysclass_default(void **state)
{
	struct sfx *s = *state;

	memset(s->table, 0xff, sizeof(s->table));	/* must be cleared */
	assert_int_equal(sysclass_build(s->table, RTSUP_MAX_SYSCALLS, default_delims,
					2, s->err, sizeof(s->err)), 0);
	assert_int_equal(cls(s, "mmap"), RTSUP_SC_UNSAFE);
	assert_int_equal(cls(s, "openat"), RTSUP_SC_UNSAFE);
	assert_int_equal(cls(s, "write"), RTSUP_SC_UNSAFE | RTSUP_SC_FDCHECK);
	/* the class stays: a rule may choose another delimiter for a thread */
	assert_int_equal(cls(s, "clock_nanosleep"),
			 RTSUP_SC_DELIM | RTSUP_SC_ABSSLEEP | RTSUP_SC_UNSAFE);
	assert_int_equal(cls(s, "nanosleep"),
			 RTSUP_SC_DELIM | RTSUP_SC_RELSLEEP | RTSUP_SC_UNSAFE);
	assert_int_equal(cls(s, "getpid"), 0);
	/* waits are keyed by what they wait on; restart resumes a sleep */
	assert_int_equal(cls(s, "epoll_pwait"), RTSUP_SC_KEYED);
	assert_int_equal(cls(s, "futex"), RTSUP_SC_KEYED | RTSUP_SC_OPKEY);
	assert_int_equal(cls(s, "restart_syscall"), RTSUP_SC_RESTART);
}

/* delimiter epoll_wait: it is the delimiter, the sleeps become unsafe */
static void test_syscalls_sysclass_epoll(void **state)
{
	static const char *const delims[] = { "epoll_wait" };
	struct sfx *s = *state;

	if (syscall_nr("epoll_wait") < 0)
		skip();		/* arm64 and riscv have only epoll_pwait */
	assert_int_equal(sysclass_build(s->table, RTSUP_MAX_SYSCALLS, delims, 1,
					s->err, sizeof(s->err)), 0);
	assert_int_equal(cls(s, "epoll_wait"), RTSUP_SC_DELIM | RTSUP_SC_KEYED);
	assert_true(cls(s, "clock_nanosleep") & RTSUP_SC_UNSAFE);
	assert_false(cls(s, "clock_nanosleep") & RTSUP_SC_DELIM);
	assert_true(cls(s, "nanosleep") & RTSUP_SC_UNSAFE);
	assert_int_equal(cls(s, "mmap"), RTSUP_SC_UNSAFE);
}

/* a delimiter keeps its class bits; DELIM wins in the kernel */
static void test_syscalls_sysclass_unsafe_delim(void **state)
{
	static const char *const delims[] = { "write" };
	struct sfx *s = *state;

	assert_int_equal(sysclass_build(s->table, RTSUP_MAX_SYSCALLS, delims, 1,
					s->err, sizeof(s->err)), 0);
	assert_int_equal(cls(s, "write"), RTSUP_SC_DELIM | RTSUP_SC_UNSAFE | RTSUP_SC_FDCHECK);
}

/* an unknown delimiter is an error naming it */
static void test_syscalls_sysclass_unknown_delim(void **state)
{
	static const char *const delims[] = { "nanosleep", "bogus_wait" };
	struct sfx *s = *state;

	assert_int_equal(sysclass_build(s->table, RTSUP_MAX_SYSCALLS, delims, 2,
					s->err, sizeof(s->err)), -1);
	assert_non_null(strstr(s->err, "bogus_wait"));
}

#define S(fn) cmocka_unit_test_setup_teardown(fn, sfx_setup, sfx_teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_syscalls_round_trip),
		cmocka_unit_test(test_syscalls_unknown),
		cmocka_unit_test(test_syscalls_category),
		S(test_syscalls_sysclass_default),
		S(test_syscalls_sysclass_epoll),
		S(test_syscalls_sysclass_unsafe_delim),
		S(test_syscalls_sysclass_unknown_delim),
	};

	return cmocka_run_group_tests_name("syscalls", tests, NULL, NULL);
}
