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
	thread_rec_normalize(&a);
	thread_rec_normalize(&b);
	assert_memory_equal(&a, &b, sizeof(a));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_new_entry_copied_twice),
		cmocka_unit_test(test_touched_entry_copied_twice),
		cmocka_unit_test(test_normalized_copies_equal),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
