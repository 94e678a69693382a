// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_taskattrs.c - user/collect/taskattrs.c: the task iterator's records */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>
#include "collect/taskattrs.h"
#include "collect/targets.h"

static struct rtsup_task_attrs rec(__u32 tid, __s32 policy, __u32 prio, __u64 cpus0)
{
	struct rtsup_task_attrs a = { .tid = tid, .policy = policy, .rt_priority = prio,
				      .cpu_words = 2, .cgroup_id = 1000 + tid };

	a.cpus[0] = cpus0;
	a.cpus[1] = ~0ULL;	/* past the online CPUs: any bits (the kernel's masks) */
	return a;
}

/* records in any order are found by tid; a tid not written is none */
static void test_parse_and_find(void **state)
{
	struct rtsup_task_attrs in[3] = { rec(300, 1, 80, 1), rec(7, 0, 0, 3), rec(42, 2, 10, 2) };
	struct task_attrs ta = { 0 };
	const struct rtsup_task_attrs *a;

	(void)state;
	assert_int_equal(task_attrs_parse(&ta, in, sizeof(in)), 0);
	assert_int_equal(ta.n, 3);
	assert_int_equal(ta.torn, 0);
	assert_true(ta.a[0].tid == 7 && ta.a[1].tid == 42 && ta.a[2].tid == 300);
	a = task_attrs_of(&ta, 300);
	assert_non_null(a);
	assert_int_equal(a->policy, 1);
	assert_int_equal(a->rt_priority, 80);
	assert_int_equal(a->cgroup_id, 1300);
	assert_null(task_attrs_of(&ta, 8));
	/* a read cut inside a record keeps the whole ones and says so */
	assert_int_equal(task_attrs_parse(&ta, in, sizeof(in) - 5), 0);
	assert_int_equal(ta.n, 2);
	assert_int_equal(ta.torn, sizeof(in[0]) - 5);
	assert_null(task_attrs_of(&ta, 42));
	/* nothing read: nothing found */
	assert_int_equal(task_attrs_parse(&ta, NULL, 0), 0);
	assert_null(task_attrs_of(&ta, 7));
	task_attrs_free(&ta);
}

/* the CPUs shown are the mask and'ed with the online ones, as sched_getaffinity */
static void test_cpus_online_only(void **state)
{
	struct rtsup_task_attrs a = rec(1, 1, 1, 0x5);
	struct task_attrs ta = { 0 };
	char buf[64];

	(void)state;
	assert_false(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));	/* online unknown */
	ta.online[0] = 0x7;	/* "0-2" */
	ta.online_ok = true;
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2");
	ta.online[1] = 0x1;	/* CPU 64 online too: the mask's word 1 has it */
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2,64");
	a.cpu_words = 1;	/* a kernel mask of 64 CPUs: word 1 is not its */
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2");
}

/* the last list is kept: the same mask again, another one, and a buffer too short */
static void test_cpus_kept_list(void **state)
{
	struct rtsup_task_attrs a = rec(1, 1, 1, 0x5), b = rec(2, 1, 1, 0xf);
	struct task_attrs ta = { 0 };
	char buf[64], small[3];

	(void)state;
	ta.online[0] = ~0UL;
	ta.online_ok = true;
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2");
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2");
	assert_true(task_attrs_cpus(&ta, &b, buf, sizeof(buf)));
	assert_string_equal(buf, "0-3");
	assert_true(task_attrs_cpus(&ta, &a, buf, sizeof(buf)));
	assert_string_equal(buf, "0,2");
	/* cut as cpu_list_mask cuts, not overrun */
	cpu_list_mask((unsigned long[RTSUP_ATTR_CPU_WORDS]){ 0x5 }, RTSUP_ATTR_CPU_WORDS * 64,
		      buf, sizeof(small));
	assert_true(task_attrs_cpus(&ta, &a, small, sizeof(small)));
	assert_string_equal(small, buf);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_parse_and_find),
		cmocka_unit_test(test_cpus_online_only),
		cmocka_unit_test(test_cpus_kept_list),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
