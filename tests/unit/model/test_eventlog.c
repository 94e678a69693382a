// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_eventlog.c - life events are never crowded out; floods fold */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include "model/eventlog.h"

static struct rtsup_event ev(__u64 ts, __u32 type, __u32 tid, __u64 arg, __u64 arg2)
{
	struct rtsup_event e = { .ts = ts, .type = type, .tid = tid, .arg = arg, .arg2 = arg2 };

	return e;
}

static size_t count(const struct eventlog *l, __u32 type, __u32 tid)
{
	size_t i, n = 0;

	for (i = 0; i < l->n; i++)
		n += l->ev[i].type == type && l->ev[i].tid == tid;
	return n;
}

/* the failure seen on a noisy machine: an exit behind a flood of misses */
static void test_eventlog_exit_survives_10000_misses(void **state)
{
	struct eventlog l = { 0 };
	__u64 t = 1000;
	int i;

	for (i = 0; i < 5000; i++)
		eventlog_add(&l, &(struct rtsup_event){ .ts = t++, .type = RTSUP_EV_MISS, .tid = 7 });
	eventlog_add(&l, &(struct rtsup_event){ .ts = t++, .type = RTSUP_EV_EXIT, .tid = 8,
						.arg = 1 });
	for (i = 0; i < 5000; i++)
		eventlog_add(&l, &(struct rtsup_event){ .ts = t++, .type = RTSUP_EV_MISS, .tid = 7 });
	eventlog_finish(&l);
	assert_int_equal(l.total, 10001);
	assert_int_equal(count(&l, RTSUP_EV_EXIT, 8), 1);
	/* the first and the last three misses, the rest folded and said so */
	assert_int_equal(count(&l, RTSUP_EV_MISS, 7), 2 * EVENTLOG_KEEP);
	assert_int_equal(l.folded, 10000 - 2 * EVENTLOG_KEEP);
	assert_int_equal(l.nflood, 1);
	assert_int_equal(l.fold[0].tid, 7);
	assert_int_equal(l.fold[0].seen, 10000);
	assert_int_equal(l.fold[0].folded, 10000 - 2 * EVENTLOG_KEEP);
	assert_int_equal(l.fold[0].first_ts, 1000);
	assert_int_equal(l.fold[0].last_ts, 11000);
	/* in time order: first misses, the exit in the middle, the last misses */
	assert_int_equal(l.n, 7);
	assert_int_equal(l.ev[0].ts, 1000);
	assert_int_equal(l.ev[2].ts, 1002);
	assert_int_equal(l.ev[3].type, RTSUP_EV_EXIT);
	assert_int_equal(l.ev[4].ts, 10998);
	assert_int_equal(l.ev[6].ts, 11000);
	assert_int_equal(l.dropped, 0);
	eventlog_free(&l);
}

/* each thread and each kind is its own flood */
static void test_eventlog_floods_by_thread_and_kind(void **state)
{
	struct eventlog l = { 0 };
	__u64 t = 1;
	int i;

	for (i = 0; i < 10; i++) {
		struct rtsup_event a = ev(t++, RTSUP_EV_UNSAFE, 1, RTSUP_U_SYSCALL, 9);	/* mmap */
		struct rtsup_event b = ev(t++, RTSUP_EV_UNSAFE, 1, RTSUP_U_SYSCALL, 11);	/* munmap */
		struct rtsup_event c = ev(t++, RTSUP_EV_UNSAFE, 1, RTSUP_U_MINFLT, 3);
		struct rtsup_event d = ev(t++, RTSUP_EV_MISS, 2, 500, 0);
		struct rtsup_event s = ev(t++, RTSUP_EV_SIGNAL, 2, 14, 0);

		eventlog_add(&l, &a);
		eventlog_add(&l, &b);
		eventlog_add(&l, &c);
		eventlog_add(&l, &d);
		eventlog_add(&l, &s);
	}
	eventlog_finish(&l);
	assert_int_equal(l.nflood, 5);
	assert_int_equal(l.n, 5 * 2 * EVENTLOG_KEEP);
	assert_int_equal(l.folded, 5 * (10 - 2 * EVENTLOG_KEEP));
	for (i = 1; i < (int)l.n; i++)
		assert_true(l.ev[i - 1].ts <= l.ev[i].ts);
	eventlog_free(&l);
}

/*
 * the noise-injector failure: a block miss amid a flood of preemption
 * misses was folded away; each cause kind is its own flood
 */
static void test_eventlog_misses_fold_per_cause_kind(void **state)
{
	struct eventlog l = { 0 };
	__u64 t = 1;
	size_t i, blocks = 0;
	int k;

	for (k = 0; k < 1000; k++) {
		struct rtsup_event e = ev(t++, RTSUP_EV_MISS, 4, 500, 0);

		e.cause.kind = RTSUP_CAUSE_PREEMPT;
		eventlog_add(&l, &e);
		if (k == 500) {
			e = ev(t++, RTSUP_EV_MISS, 4, 900, 0);
			e.cause.kind = RTSUP_CAUSE_BLOCK;
			eventlog_add(&l, &e);
		}
	}
	eventlog_finish(&l);
	for (i = 0; i < l.n; i++)
		blocks += l.ev[i].cause.kind == RTSUP_CAUSE_BLOCK;
	assert_int_equal(blocks, 1);
	assert_int_equal(l.n, 2 * EVENTLOG_KEEP + 1);
	assert_int_equal(l.folded, 1000 - 2 * EVENTLOG_KEEP);
	assert_int_equal(l.nflood, 1);
	assert_int_equal(l.fold[0].kind, RTSUP_CAUSE_PREEMPT);
	eventlog_free(&l);
}

/* blocks fold per syscall they wait in: a flood of futex waits keeps the page fault's */
static void test_eventlog_blocks_fold_per_syscall(void **state)
{
	struct eventlog l = { 0 };
	size_t i, faults = 0;
	int k;

	(void)state;
	for (k = 0; k < 100; k++) {
		/* arg2: the syscall + 1 (202: futex), 0 none: a page fault */
		struct rtsup_event e = ev(k + 1, RTSUP_EV_UNSAFE, 4, RTSUP_U_BLOCK, k == 50 ? 0 : 203);

		eventlog_add(&l, &e);
	}
	eventlog_finish(&l);
	for (i = 0; i < l.n; i++)
		faults += l.ev[i].arg == RTSUP_U_BLOCK && l.ev[i].arg2 == 0;
	assert_int_equal(faults, 1);
	assert_int_equal(l.n, 2 * EVENTLOG_KEEP + 1);
	assert_int_equal(l.nflood, 1);
	assert_int_equal(l.fold[0].kind, ((__u64)RTSUP_U_BLOCK << 32) | 203);
	assert_int_equal(l.fold[0].folded, 99 - 2 * EVENTLOG_KEEP);
	eventlog_free(&l);
}

/* a few events of a kind are all kept; nothing folded, no flood listed */
static void test_eventlog_small_floods_kept_whole(void **state)
{
	struct eventlog l = { 0 };
	int i;

	for (i = 0; i < 2 * EVENTLOG_KEEP; i++) {
		struct rtsup_event e = ev(100 - i, RTSUP_EV_MISS, 3, 0, 0);

		eventlog_add(&l, &e);
	}
	eventlog_finish(&l);
	assert_int_equal(l.n, 2 * EVENTLOG_KEEP);
	assert_int_equal(l.folded, 0);
	assert_int_equal(l.nflood, 0);
	assert_int_equal(l.ev[0].ts, 100 - 2 * EVENTLOG_KEEP + 1);
	eventlog_free(&l);
}

/* a new interval starts empty, floods counted afresh; many threads grow the table */
static void test_eventlog_clear_and_grow(void **state)
{
	struct eventlog l = { 0 };
	__u32 tid;
	int k;

	for (tid = 1; tid <= 3000; tid++)
		for (k = 0; k < 8; k++) {
			struct rtsup_event e = ev(tid * 10 + k, RTSUP_EV_MISS, tid, 0, 0);

			eventlog_add(&l, &e);
		}
	eventlog_finish(&l);
	assert_int_equal(l.nflood, 3000);
	assert_int_equal(l.n, 3000 * 2 * EVENTLOG_KEEP);
	assert_int_equal(l.folded, 3000 * (8 - 2 * EVENTLOG_KEEP));
	eventlog_clear(&l);
	assert_int_equal(l.n, 0);
	assert_int_equal(l.total, 0);
	for (k = 0; k < 4; k++) {
		struct rtsup_event e = ev(k, RTSUP_EV_MISS, 5, 0, 0);

		eventlog_add(&l, &e);
	}
	eventlog_finish(&l);
	assert_int_equal(l.n, 4);
	assert_int_equal(l.folded, 0);
	eventlog_free(&l);
}

/* the table of life events */
static void test_eventlog_never_folded_table(void **state)
{
	assert_true(eventlog_never_folded(RTSUP_EV_EXIT));
	assert_true(eventlog_never_folded(RTSUP_EV_NEW));
	assert_false(eventlog_never_folded(RTSUP_EV_MISS));
	assert_false(eventlog_never_folded(RTSUP_EV_UNSAFE));
	assert_true(eventlog_never_folded(99));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_eventlog_exit_survives_10000_misses),
		cmocka_unit_test(test_eventlog_floods_by_thread_and_kind),
		cmocka_unit_test(test_eventlog_misses_fold_per_cause_kind),
		cmocka_unit_test(test_eventlog_blocks_fold_per_syscall),
		cmocka_unit_test(test_eventlog_small_floods_kept_whole),
		cmocka_unit_test(test_eventlog_clear_and_grow),
		cmocka_unit_test(test_eventlog_never_folded_table),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
