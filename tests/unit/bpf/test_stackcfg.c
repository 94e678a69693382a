// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_stackcfg.c - which unwinder a captured event gets (include/stackcfg.h) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include "stackcfg.h"

/* the thread's rule wins over --stacks; without one, --stacks */
static void test_stackcfg_rule_over_command_line(void **state)
{
	struct rtsup_stack_cfg rc = { .kind = RTSUP_STACKS_OFF, .size = 0 }, c;

	(void)state;
	c = stack_rule(RTSUP_STACKS_DWARF, 8192, NULL);
	assert_int_equal(c.kind, RTSUP_STACKS_DWARF);
	assert_int_equal(c.size, 8192);
	c = stack_rule(RTSUP_STACKS_DWARF, 8192, &rc);
	assert_int_equal(c.kind, RTSUP_STACKS_OFF);
	rc = (struct rtsup_stack_cfg){ .kind = RTSUP_STACKS_DWARF, .size = 16384 };
	c = stack_rule(RTSUP_STACKS_OFF, 8192, &rc);
	assert_int_equal(c.kind, RTSUP_STACKS_DWARF);
	assert_int_equal(c.size, 16384);
}

/* auto: the process's verdict; DWARF until userspace has one */
static void test_stackcfg_auto(void **state)
{
	__u32 fp = RTSUP_STACKS_FP, dwarf = RTSUP_STACKS_DWARF, junk = 77;

	(void)state;
	assert_int_equal(stack_auto_kind(NULL), RTSUP_STACKS_DWARF);
	assert_int_equal(stack_auto_kind(&fp), RTSUP_STACKS_FP);
	assert_int_equal(stack_auto_kind(&dwarf), RTSUP_STACKS_DWARF);
	assert_int_equal(stack_auto_kind(&junk), RTSUP_STACKS_DWARF);
}

/* the copy stays inside the record's room, 8-aligned */
static void test_stackcfg_dump_size(void **state)
{
	(void)state;
	assert_int_equal(stack_dump_size(8192, 16384), 8192);
	assert_int_equal(stack_dump_size(16384, 8192), 8192);
	assert_int_equal(stack_dump_size(4100, 8192), 4096);
	assert_int_equal(stack_dump_size(0, 8192), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stackcfg_rule_over_command_line),
		cmocka_unit_test(test_stackcfg_auto),
		cmocka_unit_test(test_stackcfg_dump_size),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
