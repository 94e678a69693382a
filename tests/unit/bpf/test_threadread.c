// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_threadread.c - which thread map entries the sample copies out (include/threadread.h) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "threadread.h"

/* one read by the iterator: is the entry copied whole? */
static int read_once(struct rtsup_thread *t)
{
	return thread_copy_due(t->gen, &t->read_seen, &t->read_again);
}

/* a new entry is copied whatever its generation, twice, then no more */
static void test_new_entry_copied_twice(void **state)
{
	struct rtsup_thread t;

	(void)state;
	memset(&t, 0, sizeof(t));	/* as the start-up scan adds it: generation 0 */
	assert_true(read_once(&t));
	assert_true(read_once(&t));
	assert_false(read_once(&t));
	assert_false(read_once(&t));
	t.gen = 41;			/* as the hooks' template left it */
	t.read_seen = 0;
	assert_true(read_once(&t));
	assert_true(read_once(&t));
	assert_false(read_once(&t));
}

/*
 * a hook between two reads: copied at the next read and once more after
 * (a copy taken while the hook ran may lack its last writes)
 */
static void test_touched_entry_copied_twice(void **state)
{
	struct rtsup_thread t;

	(void)state;
	memset(&t, 0, sizeof(t));
	read_once(&t);
	read_once(&t);
	thread_touch(&t);
	assert_true(read_once(&t));
	thread_touch(&t);	/* during the second copy's interval: two more */
	assert_true(read_once(&t));
	assert_true(read_once(&t));
	assert_false(read_once(&t));
	/* the generation wraps: still a change */
	t.gen = 0xffffffffU;
	assert_true(read_once(&t));
	thread_touch(&t);
	assert_true(read_once(&t));
	assert_true(read_once(&t));
	assert_false(read_once(&t));
}

/*
 * a reader that decides itself (thread_copied after each copy, the rule
 * asked of copies of its fields): a change is copied twice, then kept
 */
static void test_reader_copies_a_change_twice(void **state)
{
	__u32 seen = 0, again = 0, gen = 41, s, a;

	(void)state;
	thread_copied(gen, &seen, &again);	/* the first copy of a new entry */
	s = seen, a = again;
	assert_true(thread_copy_due(gen, &s, &a));	/* its second is due */
	thread_copied(gen, &seen, &again);
	s = seen, a = again;
	assert_false(thread_copy_due(gen, &s, &a));	/* then nothing, while no hook writes */
	gen++;	/* a hook looked it up */
	s = seen, a = again;
	assert_true(thread_copy_due(gen, &s, &a));
	thread_copied(gen, &seen, &again);
	s = seen, a = again;
	assert_true(thread_copy_due(gen, &s, &a));
	thread_copied(gen, &seen, &again);
	thread_copied(gen, &seen, &again);	/* a third copy changes nothing */
	s = seen, a = again;
	assert_false(thread_copy_due(gen, &s, &a));
}

/* the copies of an entry no hook wrote in between are the same bytes */
static void test_normalized_copies_equal(void **state)
{
	struct rtsup_thread t, a, b;

	(void)state;
	memset(&t, 0, sizeof(t));
	t.cycles = 7;
	thread_touch(&t);
	read_once(&t);
	a = t;
	read_once(&t);
	b = t;
	assert_memory_not_equal(&a, &b, sizeof(a));	/* the reader's fields moved */
	a.moved_seq = 3;	/* as a hook named it for the ring (thread_moved_due) */
	thread_rec_normalize(&a);
	thread_rec_normalize(&b);
	assert_memory_equal(&a, &b, sizeof(a));
}

/* is the entry's task read at read seq? (as the iterator decides, before its copy) */
static int task_due(const struct rtsup_thread *t, __u32 tid, __u32 seq)
{
	return thread_task_due(t->gen, t->read_seen, t->read_again, tid, seq, THREAD_TASKS_DUE);
}

/*
 * a parked entry's task is read once every THREAD_TASK_EVERY reads, one
 * that moved at every read until its second copy is done
 */
static void test_task_read_parked_rarely_moved_always(void **state)
{
	struct rtsup_thread t;
	__u32 seq, reads = 0, tid = 1234;

	(void)state;
	memset(&t, 0, sizeof(t));
	assert_true(task_due(&t, tid, 1));	/* new: never copied */
	read_once(&t);
	assert_true(task_due(&t, tid, 2));	/* its second copy is due */
	read_once(&t);
	for (seq = 3; seq < 3 + 10 * THREAD_TASK_EVERY; seq++) {
		reads += task_due(&t, tid, seq);
		read_once(&t);
	}
	assert_int_equal(reads, 10);
	/* moved: read at this read and the next, whatever seq */
	for (seq = 0; seq < THREAD_TASK_EVERY; seq++) {
		struct rtsup_thread u = t;

		thread_touch(&u);
		assert_true(task_due(&u, tid, seq));
		read_once(&u);
		assert_true(task_due(&u, tid, seq + 1));
	}
}

/* the parked ones' reads are spread: as many tids read at each seq */
static void test_task_read_spread_over_tids(void **state)
{
	struct rtsup_thread t;
	__u32 seq, tid, n;

	(void)state;
	memset(&t, 0, sizeof(t));
	read_once(&t);
	read_once(&t);
	for (seq = 100; seq < 100 + THREAD_TASK_EVERY; seq++) {
		for (n = 0, tid = 1000; tid < 1000 + 64 * THREAD_TASK_EVERY; tid++)
			n += task_due(&t, tid, seq);
		assert_int_equal(n, 64);
	}
}

/*
 * what the iterator writes of a parked entry: nothing, but at the reads of
 * its task; of a moved one, its record and copy (thread_rec_write's order:
 * the task's read decided first, then the copy)
 */
static void test_parked_entry_written_only_for_its_task(void **state)
{
	struct rtsup_thread t;
	__u32 seq, tid = 77, written = 0;
	__u16 task;
	int full;

	(void)state;
	memset(&t, 0, sizeof(t));
	read_once(&t);
	read_once(&t);
	for (seq = 1; seq <= 8 * THREAD_TASK_EVERY; seq++) {
		task = task_due(&t, tid, seq) ? THREAD_TASK_ATTRS : THREAD_TASK_UNREAD;
		full = read_once(&t);
		assert_false(full);
		written += !thread_rec_skipped(full, task);
	}
	assert_int_equal(written, 8);
	/* a task gone is said, read or not */
	assert_false(thread_rec_skipped(0, THREAD_TASK_GONE));
	/* moved: written, with its copy, at this read and the next */
	thread_touch(&t);
	assert_false(thread_rec_skipped(read_once(&t), THREAD_TASK_UNREAD));
	assert_false(thread_rec_skipped(read_once(&t), THREAD_TASK_UNREAD));
	assert_true(thread_rec_skipped(read_once(&t), THREAD_TASK_UNREAD));
}

/* a record's length: the attributes follow it when it says so; the entry never does */
static void test_rec_len(void **state)
{
	struct rtsup_thread_rec r = { .tid = 5, .slot = 3 };

	(void)state;
	assert_int_equal(sizeof(r) % 8, 0);	/* the attributes stay aligned */
	assert_int_equal(sizeof(struct rtsup_task_attrs) % 8, 0);
	assert_int_equal(thread_rec_len(&r), sizeof(r));
	r.task = THREAD_TASK_GONE;
	assert_int_equal(thread_rec_len(&r), sizeof(r));
	r.task = THREAD_TASK_ATTRS;
	assert_int_equal(thread_rec_len(&r), sizeof(r) + sizeof(struct rtsup_task_attrs));
	r.full = 1;	/* the collector copies it from thread_mem */
	assert_int_equal(thread_rec_len(&r), sizeof(r) + sizeof(struct rtsup_task_attrs));
	r.task = THREAD_TASK_UNREAD;
	assert_int_equal(thread_rec_len(&r), sizeof(r));
}

/* a slot of thread_mem is one of its n elements; THREAD_NO_SLOT never is */
static void test_slot_ok(void **state)
{
	(void)state;
	assert_true(thread_slot_ok(0, 4));
	assert_true(thread_slot_ok(3, 4));
	assert_false(thread_slot_ok(4, 4));
	assert_false(thread_slot_ok(THREAD_NO_SLOT, 4096));
	assert_false(thread_slot_ok(0, 0));
}

/* a hook's lookup names the entry in the ring once a read: as thread_entry does */
static int hook_names(struct rtsup_thread *t, __u32 read_seq, int send_ok)
{
	if (!thread_moved_due(t->moved_seq, read_seq))
		return 0;
	if (send_ok)
		t->moved_seq = read_seq;
	return 1;
}

static void test_moved_named_once_a_read(void **state)
{
	struct rtsup_thread t;

	(void)state;
	memset(&t, 0, sizeof(t));
	/* before the first read (seq 0): not named, the first two reads are whole */
	assert_false(hook_names(&t, 0, 1));
	assert_true(hook_names(&t, 1, 1));
	assert_false(hook_names(&t, 1, 1));
	assert_false(hook_names(&t, 1, 1));
	/* the next read began: named again, once */
	assert_true(hook_names(&t, 2, 1));
	assert_false(hook_names(&t, 2, 1));
	/* the ring was full: the next lookup tries again */
	assert_true(hook_names(&t, 3, 0));
	assert_true(hook_names(&t, 3, 1));
	assert_false(hook_names(&t, 3, 1));
}

/* which reads walk the whole map */
static void test_read_whole_when(void **state)
{
	__u64 seq;
	int whole = 0;

	(void)state;
	assert_true(thread_read_whole(0, 5, 0, 0, 1000));	/* no ring */
	assert_true(thread_read_whole(1, 1, 0, 0, 1000));	/* start-up's two */
	assert_true(thread_read_whole(1, 2, 0, 0, 1000));
	assert_true(thread_read_whole(1, 5, 1, 0, 1000));	/* lost, a cgroup move */
	for (seq = 3; seq < 3 + 10 * THREAD_TASK_EVERY; seq++)
		whole += thread_read_whole(1, seq, 0, 0, 1000);
	assert_int_equal(whole, 10);				/* the tasks, all of them */
	/* 100 running and 900 parked: 200 named (twice each), named read */
	assert_false(thread_read_whole(1, 5, 0, 200, 1000));
	/* all 1000 running: the walk is cheaper */
	assert_true(thread_read_whole(1, 5, 0, 2000, 1000));
	/* a few threads: the walk's fixed part makes their lookups cheaper */
	assert_false(thread_read_whole(1, 5, 0, 20, 11));
}

/*
 * with the ring: the reads that must see every task read all of them, a
 * walk only cheaper than the lookups none, whatever moved; without it the
 * iterator picks (thread_task_due)
 */
static void test_read_tasks_which(void **state)
{
	struct rtsup_thread t;
	__u64 seq;
	int all = 0;

	(void)state;
	memset(&t, 0, sizeof(t));
	assert_int_equal(thread_read_tasks(0, 5, 0), THREAD_TASKS_DUE);
	assert_int_equal(thread_read_tasks(1, 1, 0), THREAD_TASKS_ALL);
	assert_int_equal(thread_read_tasks(1, 2, 0), THREAD_TASKS_ALL);
	assert_int_equal(thread_read_tasks(1, 5, 1), THREAD_TASKS_ALL);	/* forced */
	for (seq = 3; seq < 3 + 10 * THREAD_TASK_EVERY; seq++) {
		__u32 which = thread_read_tasks(1, seq, 0);

		all += which == THREAD_TASKS_ALL;
		/* the mode decides, not the entry: this one is new (never copied) */
		assert_int_equal(thread_task_due(t.gen, t.read_seen, t.read_again, 7, (__u32)seq,
						 which), which == THREAD_TASKS_ALL);
		/* every all-read is a whole read */
		if (which == THREAD_TASKS_ALL)
			assert_true(thread_read_whole(1, seq, 0, 0, 1000));
	}
	assert_int_equal(all, 10);
	/* a parked entry read by the spread (tid + seq) is not read at a walk for cost */
	t.read_seen = t.gen + 1;
	assert_true(thread_task_due(t.gen, t.read_seen, 0, 0, 8, THREAD_TASKS_DUE));
	assert_false(thread_task_due(t.gen, t.read_seen, 0, 0, 8, THREAD_TASKS_NONE));
}

/*
 * the task iterator's walk of every task: at the reads that see every
 * entry, after a storm of threads asked one by one, and always without the ring
 */
static void test_walk_tasks_when(void **state)
{
	__u64 seq;
	int walks = 0;

	(void)state;
	assert_true(thread_walk_tasks(0, 5, 0, 0));	/* no ring: every sample */
	assert_true(thread_walk_tasks(1, 1, 0, 0));
	assert_true(thread_walk_tasks(1, 2, 0, 0));
	assert_true(thread_walk_tasks(1, 5, 1, 0));	/* forced: a cgroup move, a lost send */
	assert_false(thread_walk_tasks(1, 5, 0, THREAD_WALK_ASKS));
	assert_true(thread_walk_tasks(1, 5, 0, THREAD_WALK_ASKS + 1));
	for (seq = 3; seq < 3 + 10 * THREAD_TASK_EVERY; seq++) {
		int walk = thread_walk_tasks(1, seq, 0, 0);

		walks += walk;
		/* the same samples as the thread map's iterator reads every task */
		assert_int_equal(walk, thread_read_tasks(1, seq, 0) == THREAD_TASKS_ALL);
	}
	assert_int_equal(walks, 10);
}

/* attributes read of a task against what its last switch-out saw */
static void test_attrs_as_seen(void **state)
{
	struct rtsup_task_attrs a;
	struct rtsup_thread t;

	(void)state;
	memset(&a, 0, sizeof(a));
	memset(&t, 0, sizeof(t));
	a.policy = 1;
	a.rt_priority = 70;
	a.cpu_words = 2;
	a.cpus[0] = 0x3;	/* CPUs 0, 1 and 64 */
	a.cpus[1] = 0x1;
	assert_false(thread_attrs_as_seen(t.sched_seen, &a));	/* no switch-out yet */
	thread_sched_seen(&t, 1, 70, 3);	/* the first: a setsched that changed nothing */
	assert_true(thread_attrs_as_seen(t.sched_seen, &a));
	thread_sched_seen(&t, 1, 71, 3);	/* chrt -f 71 */
	assert_false(thread_attrs_as_seen(t.sched_seen, &a));
	thread_sched_seen(&t, 1, 70, 2);	/* taskset: one CPU less */
	assert_false(thread_attrs_as_seen(t.sched_seen, &a));
	a.cpus[1] = 0;
	assert_true(thread_attrs_as_seen(t.sched_seen, &a));
	a.cpu_words = 0;	/* a mask the read did not fill counts no CPU */
	assert_false(thread_attrs_as_seen(t.sched_seen, &a));
}

/* a target's switch-out: a change of what the collector reads of its task counts */
static void test_sched_seen_counts_changes(void **state)
{
	struct rtsup_thread t;

	(void)state;
	memset(&t, 0, sizeof(t));
	thread_sched_seen(&t, 0, 0, 2);	/* the first: unknown before */
	assert_int_equal(t.setsched, 1);
	thread_sched_seen(&t, 0, 0, 2);
	assert_int_equal(t.setsched, 1);
	thread_sched_seen(&t, 1, 70, 2);	/* chrt -f 70 */
	assert_int_equal(t.setsched, 2);
	thread_sched_seen(&t, 1, 71, 2);
	assert_int_equal(t.setsched, 3);
	thread_sched_seen(&t, 1, 71, 1);	/* taskset -c 0 */
	assert_int_equal(t.setsched, 4);
	thread_sched_seen(&t, 1, 71, 1);
	assert_int_equal(t.setsched, 4);
	thread_sched_seen(&t, 0, 0, 1);	/* back to SCHED_OTHER */
	assert_int_equal(t.setsched, 5);
}

/* the ring holds two sends of every entry, in whole pages */
static void test_moved_ring_bytes(void **state)
{
	(void)state;
	assert_int_equal(thread_moved_ring_bytes(4096, 4096), 128 * 1024);
	assert_int_equal(thread_moved_ring_bytes(1, 4096), 4096);
	assert_int_equal(thread_moved_ring_bytes(5000, 4096), 256 * 1024);
	assert_int_equal(thread_moved_ring_bytes(4096, 65536), 128 * 1024);
	assert_int_equal(thread_moved_ring_bytes(1, 65536), 65536);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_new_entry_copied_twice),
		cmocka_unit_test(test_touched_entry_copied_twice),
		cmocka_unit_test(test_normalized_copies_equal),
		cmocka_unit_test(test_task_read_parked_rarely_moved_always),
		cmocka_unit_test(test_task_read_spread_over_tids),
		cmocka_unit_test(test_parked_entry_written_only_for_its_task),
		cmocka_unit_test(test_rec_len),
		cmocka_unit_test(test_slot_ok),
		cmocka_unit_test(test_moved_named_once_a_read),
		cmocka_unit_test(test_read_whole_when),
		cmocka_unit_test(test_read_tasks_which),
		cmocka_unit_test(test_walk_tasks_when),
		cmocka_unit_test(test_reader_copies_a_change_twice),
		cmocka_unit_test(test_sched_seen_counts_changes),
		cmocka_unit_test(test_attrs_as_seen),
		cmocka_unit_test(test_moved_ring_bytes),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
