// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_health.c - user/judge/health.c: the kernel counters land in their
 * fields, a map's fill and when it is near full, and that any loss, skip or
 * near-full map makes the health not ok.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "judge/health.h"

static void test_health_counters_each_field(void **state)
{
	__u64 c[RTSUP_C_NR] = { 0 };
	struct health h;

	(void)state;
	memset(&h, 0, sizeof(h));
	c[RTSUP_C_RB_DROPS] = 1;
	c[RTSUP_C_CYC_DROPS] = 2;
	c[RTSUP_C_MAP_FULL] = 3;
	c[RTSUP_C_SYS_FULL] = 4;
	c[RTSUP_C_CAN_FULL] = 5;
	c[RTSUP_C_NEW] = 99;	/* not a problem: threads added */
	health_counters(&h, c);
	assert_int_equal(h.lost_events, 1);
	assert_int_equal(h.lost_cycle_records, 2);
	assert_int_equal(h.untracked_threads, 3);
	assert_int_equal(h.untracked_syscall_counts, 4);
	assert_int_equal(h.can_frames_not_counted, 5);
	assert_int_equal(h.parse_errors, 0);
}

static void test_health_fill_unknown(void **state)
{
	struct health_map m = { .entries = 5, .capacity = 0 };

	(void)state;
	assert_true(health_fill_pct(&m) < 0);
	assert_false(health_near_full(&m));
}

/* 90 % exactly is near full; one entry less is not */
static void test_health_near_full_edge(void **state)
{
	struct health_map m = { .entries = 90, .capacity = 100 };

	(void)state;
	assert_true(health_near_full(&m));
	assert_float_equal(health_fill_pct(&m), 90.0, 1e-9);
	m.entries = 89;
	assert_false(health_near_full(&m));
	m.capacity = 4096;
	m.entries = 3687;	/* 90.01 % */
	assert_true(health_near_full(&m));
	m.entries = 3686;	/* 89.99 % */
	assert_false(health_near_full(&m));
	/* no overflow near the top of the range */
	m.capacity = 0xffffffffu;
	m.entries = 0xffffffffu;
	assert_true(health_near_full(&m));
}

static void test_health_problems_each(void **state)
{
	struct health h;
	int i;

	(void)state;
	for (i = 0; i < 11; i++) {
		memset(&h, 0, sizeof(h));
		h.thread_map.capacity = 100;
		h.can_id_map.capacity = 100;
		assert_false(health_problems(&h));
		switch (i) {
		case 0: h.lost_events = 1; break;
		case 1: h.lost_cycle_records = 1; break;
		case 2: h.untracked_threads = 1; break;
		case 3: h.untracked_syscall_counts = 1; break;
		case 4: h.can_frames_not_counted = 1; break;
		case 5: h.events_not_kept = 1; break;
		case 6: h.parse_errors = 1; break;
		case 7: h.actions_dropped = 1; break;
		case 8: h.thread_map.entries = 95; break;
		case 9: h.can_id_map.entries = 100; break;
		case 10: h.hook_runs_missed = 1; break;
		}
		assert_true(health_problems(&h));
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_health_counters_each_field),
		cmocka_unit_test(test_health_fill_unknown),
		cmocka_unit_test(test_health_near_full_edge),
		cmocka_unit_test(test_health_problems_each),
	};

	return cmocka_run_group_tests_name("health", tests, NULL, NULL);
}
