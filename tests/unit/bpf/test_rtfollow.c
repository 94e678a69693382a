// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_rtfollow.c - --rt's decision at a policy change (include/rtfollow.h) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "rtfollow.h"

#define SCHED_OTHER_	0
#define SCHED_BATCH_	3
#define SCHED_IDLE_	5

/* the policies --rt follows, and only those */
static void test_rtfollow_policies(void **state)
{
	assert_true(rt_policy(RTF_SCHED_FIFO));
	assert_true(rt_policy(RTF_SCHED_RR));
	assert_true(rt_policy(RTF_SCHED_DEADLINE));
	assert_false(rt_policy(SCHED_OTHER_));
	assert_false(rt_policy(SCHED_BATCH_));
	assert_false(rt_policy(SCHED_IDLE_));
	assert_false(rt_policy(4));
}

/* SCHED_OTHER to FIFO, or an RT child: a thread without an entry is adopted */
static void test_rtfollow_becomes_rt(void **state)
{
	assert_int_equal(rt_on_policy(RTF_SCHED_FIFO, NULL), RT_ADOPT);
	assert_int_equal(rt_on_policy(RTF_SCHED_DEADLINE, NULL), RT_ADOPT);
	/* not RT and no entry: nothing */
	assert_int_equal(rt_on_policy(SCHED_OTHER_, NULL), RT_KEEP);
}

/* a followed thread that changes between RT policies or priorities stays as it is */
static void test_rtfollow_stays_rt(void **state)
{
	struct rtsup_thread t;

	memset(&t, 0, sizeof(t));
	t.rt = RTSUP_RT_ONLY;
	assert_int_equal(rt_on_policy(RTF_SCHED_RR, &t), RT_KEEP);
	t.rt = 0;	/* a -p target that is RT */
	assert_int_equal(rt_on_policy(RTF_SCHED_FIFO, &t), RT_KEEP);
}

/* FIFO to SCHED_OTHER: let go when --rt alone followed it; -p's targets stay */
static void test_rtfollow_leaves_rt(void **state)
{
	struct rtsup_thread t;

	memset(&t, 0, sizeof(t));
	t.rt = RTSUP_RT_ONLY;
	assert_int_equal(rt_on_policy(SCHED_OTHER_, &t), RT_LET_GO);
	assert_int_equal(rt_on_policy(SCHED_BATCH_, &t), RT_LET_GO);
	t.rt = 0;
	assert_int_equal(rt_on_policy(SCHED_OTHER_, &t), RT_KEEP);
	/* let go already: once */
	t.rt = RTSUP_RT_ONLY | RTSUP_RT_LEFT;
	assert_int_equal(rt_on_policy(SCHED_OTHER_, &t), RT_KEEP);
	/* an exited thread's entry is no one to let go */
	t.rt = RTSUP_RT_ONLY;
	t.exited = 1;
	assert_int_equal(rt_on_policy(SCHED_OTHER_, &t), RT_KEEP);
}

/*
 * back to RT before userspace let it go, or a reused tid of an exited
 * thread: the entry is stale and the thread is adopted anew
 */
static void test_rtfollow_back_to_rt(void **state)
{
	struct rtsup_thread t;

	memset(&t, 0, sizeof(t));
	t.rt = RTSUP_RT_ONLY | RTSUP_RT_LEFT;
	assert_true(rt_entry_stale(&t));
	assert_int_equal(rt_on_policy(RTF_SCHED_FIFO, &t), RT_ADOPT);
	t.rt = RTSUP_RT_ONLY;
	assert_false(rt_entry_stale(&t));
	t.exited = 5;
	assert_true(rt_entry_stale(&t));
	assert_int_equal(rt_on_policy(RTF_SCHED_FIFO, &t), RT_ADOPT);
}

/*
 * the switch-in's read, without the policy hook: a task in do_exit is no
 * new thread, whether its exited entry is still there or reaped already
 */
static void test_rtfollow_switch_in_exiting(void **state)
{
	struct rtsup_thread t;

	memset(&t, 0, sizeof(t));
	assert_int_equal(rt_on_switch_in(RTF_SCHED_FIFO, 0, NULL), RT_ADOPT);
	/* reaped after its exit event, switched in while it still frees its memory */
	assert_int_equal(rt_on_switch_in(RTF_SCHED_FIFO, RTF_PF_EXITING, NULL), RT_KEEP);
	assert_int_equal(rt_on_switch_in(RTF_SCHED_FIFO, RTF_PF_EXITING | 0x40, NULL), RT_KEEP);
	/* its exited entry still there */
	t.rt = RTSUP_RT_ONLY;
	t.exited = 1;
	assert_int_equal(rt_on_switch_in(RTF_SCHED_FIFO, 0, &t), RT_KEEP);
	assert_int_equal(rt_on_switch_in(RTF_SCHED_FIFO, RTF_PF_EXITING, &t), RT_KEEP);
	/* one let go for leaving RT, back in RT: adopted anew, unless it is exiting */
	t.exited = 0;
	t.rt = RTSUP_RT_ONLY | RTSUP_RT_LEFT;
	assert_int_equal(rt_on_switch_in(RTF_SCHED_RR, 0, &t), RT_ADOPT);
	assert_int_equal(rt_on_switch_in(RTF_SCHED_RR, RTF_PF_EXITING, &t), RT_KEEP);
	/* a live target that leaves RT is let go as at a policy change */
	t.rt = RTSUP_RT_ONLY;
	assert_int_equal(rt_on_switch_in(SCHED_OTHER_, 0, &t), RT_LET_GO);
}

/* a let-go marks the entry, unless the thread's process became a target */
static void test_rtfollow_mark_left(void **state)
{
	struct rtsup_thread t;

	memset(&t, 0, sizeof(t));
	t.rt = RTSUP_RT_ONLY;
	assert_int_equal(rt_mark_left(&t, 1), 0);
	assert_int_equal(t.rt, RTSUP_RT_ONLY);
	assert_false(rt_entry_stale(&t));
	assert_int_equal(rt_mark_left(&t, 0), 1);
	assert_int_equal(t.rt, RTSUP_RT_ONLY | RTSUP_RT_LEFT);
	assert_true(rt_entry_stale(&t));
	assert_int_equal(rt_mark_left(NULL, 0), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_rtfollow_policies),
		cmocka_unit_test(test_rtfollow_becomes_rt),
		cmocka_unit_test(test_rtfollow_stays_rt),
		cmocka_unit_test(test_rtfollow_leaves_rt),
		cmocka_unit_test(test_rtfollow_back_to_rt),
		cmocka_unit_test(test_rtfollow_switch_in_exiting),
		cmocka_unit_test(test_rtfollow_mark_left),
	};

	return cmocka_run_group_tests_name("rtfollow", tests, NULL, NULL);
}
