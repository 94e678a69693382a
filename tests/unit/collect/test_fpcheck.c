// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_fpcheck.c - --stacks auto: a module's verdict from its samples, a process's from its modules */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include "collect/fpcheck.h"
#include "rtsup.h"

/* a module: most of its code through the frame pointer, or little of it */
static void test_fpcheck_module_verdict(void **state)
{
	(void)state;
	/* numbers as sampled on Debian 12: a program built with frame pointers, glibc, ld.so */
	assert_int_equal(fp_verdict_of(205, 169), FP_KEPT);
	assert_int_equal(fp_verdict_of(252, 42), FP_OMITTED);
	assert_int_equal(fp_verdict_of(253, 89), FP_OMITTED);
	assert_int_equal(fp_verdict_of(197, 0), FP_OMITTED);
	/* the bound: half of the samples */
	assert_int_equal(fp_verdict_of(100, 50), FP_KEPT);
	assert_int_equal(fp_verdict_of(100, 49), FP_OMITTED);
	/* too little call frame information to tell */
	assert_int_equal(fp_verdict_of(FP_MIN_SAMPLES - 1, FP_MIN_SAMPLES - 1), FP_UNKNOWN);
	assert_int_equal(fp_verdict_of(0, 0), FP_UNKNOWN);
}

/* a process: fp only when every module keeps them; one without is DWARF */
static void test_fpcheck_process_kind(void **state)
{
	const enum fp_verdict all[] = { FP_KEPT, FP_KEPT, FP_KEPT };
	const enum fp_verdict libc[] = { FP_KEPT, FP_OMITTED, FP_KEPT };
	const enum fp_verdict unknown[] = { FP_KEPT, FP_UNKNOWN };
	const enum fp_verdict none[] = { FP_UNKNOWN, FP_UNKNOWN };

	(void)state;
	assert_int_equal(fp_process_kind(all, 3), RTSUP_STACKS_FP);
	assert_int_equal(fp_process_kind(libc, 3), RTSUP_STACKS_DWARF);
	/* a module without CFI decides nothing; but something must keep them */
	assert_int_equal(fp_process_kind(unknown, 2), RTSUP_STACKS_FP);
	assert_int_equal(fp_process_kind(none, 2), RTSUP_STACKS_DWARF);
	assert_int_equal(fp_process_kind(NULL, 0), RTSUP_STACKS_DWARF);
}

/* no ELF at all (a module libdwfl could not open): unknown, never a crash */
static void test_fpcheck_no_elf(void **state)
{
	(void)state;
	assert_int_equal(fp_elf_check(NULL), FP_UNKNOWN);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fpcheck_module_verdict),
		cmocka_unit_test(test_fpcheck_process_kind),
		cmocka_unit_test(test_fpcheck_no_elf),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
