// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_syshooks.c - which syscalls the per-syscall hooks attach to */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "model/syscalls.h"
#include "model/syshooks.h"
#include "rtsup.h"

static const char *const default_delims[] = { "clock_nanosleep", "nanosleep" };

struct hfx {
	__u32 table[RTSUP_MAX_SYSCALLS];
	struct sys_hookset h;
	char err[128];
};

static int hfx_setup(void **state)
{
	struct hfx *f = calloc(1, sizeof(*f));

	if (!f || sysclass_build(f->table, RTSUP_MAX_SYSCALLS, default_delims, 2, f->err,
				 sizeof(f->err)))
		return -1;
	*state = f;
	return 0;
}

static int hfx_teardown(void **state)
{
	free(*state);
	return 0;
}

static bool hooked(const struct hfx *f, const char *name, bool out)
{
	return syshooks_has(&f->h, syscall_nr(name), out);
}

/* every classified syscall on entry; what may end a cycle on exit too; nothing else */
static void test_plan_follows_the_class_table(void **state)
{
	struct hfx *f = *state;
	int nr, nclassified = 0;

	assert_int_equal(syshooks_plan(&f->h, f->table, RTSUP_MAX_SYSCALLS, NULL, f->err,
				       sizeof(f->err)), 0);
	for (nr = 0; nr < RTSUP_MAX_SYSCALLS; nr++) {
		nclassified += f->table[nr] != 0;
		assert_int_equal(syshooks_has(&f->h, nr, false), f->table[nr] != 0);
		assert_int_equal(syshooks_has(&f->h, nr, true),
				 (f->table[nr] & (RTSUP_SC_DELIM | RTSUP_SC_RESTART)) != 0);
	}
	assert_int_equal(f->h.nin, nclassified);
	assert_true(hooked(f, "clock_nanosleep", true) && hooked(f, "restart_syscall", true));
	assert_true(hooked(f, "mmap", false) && !hooked(f, "mmap", true));
	/* a keyed wait is no delimiter until a rule or --cycle-syscall names it */
	assert_true(hooked(f, "read", false) && !hooked(f, "read", true));
	assert_false(hooked(f, "getppid", false));
}

/* a rule's delimiter is hooked at both ends, a rule's forbidden name at entry */
static void test_plan_adds_the_rules_names(void **state)
{
	struct hfx *f = *state;
	struct sys_rule_names r = { .ndelims = 1, .nforbid = 1 };

	r.delims[0] = syscall_nr("read");
	r.forbid[0] = syscall_nr("getppid");
	assert_int_equal(syshooks_plan(&f->h, f->table, RTSUP_MAX_SYSCALLS, &r, f->err,
				       sizeof(f->err)), 0);
	assert_true(hooked(f, "read", true));
	assert_true(hooked(f, "getppid", false) && !hooked(f, "getppid", true));
	assert_int_equal(syshooks_missing(&f->h, &r), -1);
	/* a reload that names one more is found */
	r.forbid[r.nforbid++] = syscall_nr("getpid");
	assert_int_equal(syshooks_missing(&f->h, &r), syscall_nr("getpid"));
	r.nforbid--;
	r.delims[r.ndelims++] = syscall_nr("mmap");	/* hooked on entry only */
	assert_int_equal(syshooks_missing(&f->h, &r), syscall_nr("mmap"));
}

/* more names than stubs: an error that says so, not a silent cut */
static void test_plan_refuses_more_than_the_stubs(void **state)
{
	struct hfx *f = *state;
	struct sys_rule_names r = { 0 };
	int nr;

	for (nr = 0; nr < RTSUP_MAX_SYSCALLS && r.nforbid < SYS_RULE_NAMES; nr++)
		if (!f->table[nr] && syscall_name(nr))
			r.forbid[r.nforbid++] = nr;
	assert_int_equal(syshooks_plan(&f->h, f->table, RTSUP_MAX_SYSCALLS, &r, f->err,
				       sizeof(f->err)), -1);
	assert_non_null(strstr(f->err, "syscalls to hook on entry"));
	assert_int_equal(f->h.nin, RTSUP_SYS_IN_SLOTS);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_plan_follows_the_class_table, hfx_setup,
						hfx_teardown),
		cmocka_unit_test_setup_teardown(test_plan_adds_the_rules_names, hfx_setup,
						hfx_teardown),
		cmocka_unit_test_setup_teardown(test_plan_refuses_more_than_the_stubs, hfx_setup,
						hfx_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
