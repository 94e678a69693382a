// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_status.c - user/judge/status.c: the worst level wins, every message is kept
 * up to STATUS_MAX_MSGS and the rest counted, the one-line form, equality,
 * and which levels fail a --check run.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "judge/status.h"

/* every order of the four levels */
static void test_status_worst_wins_any_order(void **state)
{
	static const enum level lv[4] = { LEVEL_OK, LEVEL_STALE, LEVEL_WARN, LEVEL_ERROR };
	int a, b, c, d, n = 0;

	for (a = 0; a < 4; a++)
		for (b = 0; b < 4; b++)
			for (c = 0; c < 4; c++)
				for (d = 0; d < 4; d++) {
					struct status s;

					if (a == b || a == c || a == d || b == c || b == d || c == d)
						continue;
					status_reset(&s);
					status_add(&s, lv[a], "a");
					status_add(&s, lv[b], "b");
					status_add(&s, lv[c], "c");
					status_add(&s, lv[d], "d");
					assert_int_equal(s.level, LEVEL_ERROR);
					assert_int_equal(s.nmsg, 4);
					assert_int_equal(s.dropped, 0);
					n++;
				}
	assert_int_equal(n, 24);
}

/* the worst of a subset, whatever comes first */
static void test_status_worst_wins_subsets(void **state)
{
	struct status s;

	status_reset(&s);
	status_add(&s, LEVEL_WARN, "w");
	status_add(&s, LEVEL_OK, "o");
	status_add(&s, LEVEL_STALE, "s");
	assert_int_equal(s.level, LEVEL_WARN);

	status_reset(&s);
	status_add(&s, LEVEL_STALE, "s");
	status_add(&s, LEVEL_OK, "o");
	assert_int_equal(s.level, LEVEL_STALE);

	status_reset(&s);
	status_add(&s, LEVEL_OK, "o");
	assert_int_equal(s.level, LEVEL_OK);
	assert_int_equal(s.nmsg, 1);

	status_reset(&s);
	status_add(&s, LEVEL_ERROR, "e");
	status_add(&s, LEVEL_WARN, "w");
	status_add(&s, LEVEL_OK, "o");
	assert_int_equal(s.level, LEVEL_ERROR);
}

static void test_status_reset_clears(void **state)
{
	struct status s;
	int i;

	memset(&s, 0x5a, sizeof(s));
	status_reset(&s);
	assert_int_equal(s.level, LEVEL_OK);
	assert_int_equal(s.nmsg, 0);
	assert_int_equal(s.dropped, 0);

	for (i = 0; i < STATUS_MAX_MSGS + 3; i++)
		status_add(&s, LEVEL_ERROR, "m%d", i);
	status_reset(&s);
	assert_int_equal(s.level, LEVEL_OK);
	assert_int_equal(s.nmsg, 0);
	assert_int_equal(s.dropped, 0);
}

/* every message is kept, formatted, in order */
static void test_status_messages_all_kept(void **state)
{
	struct status s;
	char buf[256];

	status_reset(&s);
	status_add(&s, LEVEL_WARN, "first %d", 1);
	status_add(&s, LEVEL_OK, "second %s", "two");
	status_add(&s, LEVEL_ERROR, "third %.1f", 3.5);
	assert_int_equal(s.nmsg, 3);
	assert_int_equal(s.dropped, 0);
	assert_string_equal(s.msg[0], "first 1");
	assert_string_equal(s.msg[1], "second two");
	assert_string_equal(s.msg[2], "third 3.5");
	status_join(&s, buf, sizeof(buf));
	assert_string_equal(buf, "first 1; second two; third 3.5");
}

/* exactly STATUS_MAX_MSGS messages: nothing dropped */
static void test_status_full_no_dropped(void **state)
{
	struct status s;
	char buf[512];
	int i;

	status_reset(&s);
	for (i = 0; i < STATUS_MAX_MSGS; i++)
		status_add(&s, LEVEL_WARN, "m%d", i);
	assert_int_equal(s.nmsg, STATUS_MAX_MSGS);
	assert_int_equal(s.dropped, 0);
	status_join(&s, buf, sizeof(buf));
	assert_string_equal(buf, "m0; m1; m2; m3; m4; m5; m6; m7");
	assert_null(strstr(buf, "more"));
}

/* beyond the limit: counted in dropped, shown as "; N more", still judged */
static void test_status_overflow_dropped(void **state)
{
	struct status s;
	char buf[512];
	int i;

	status_reset(&s);
	for (i = 0; i < STATUS_MAX_MSGS + 3; i++)
		status_add(&s, LEVEL_OK, "m%d", i);
	/* a dropped message still sets the level */
	status_add(&s, LEVEL_ERROR, "late error");
	assert_int_equal(s.nmsg, STATUS_MAX_MSGS);
	assert_int_equal(s.dropped, 4);
	assert_int_equal(s.level, LEVEL_ERROR);
	assert_string_equal(s.msg[STATUS_MAX_MSGS - 1], "m7");
	status_join(&s, buf, sizeof(buf));
	assert_string_equal(buf, "m0; m1; m2; m3; m4; m5; m6; m7; 4 more");
}

static void test_status_join_empty(void **state)
{
	struct status s;
	char buf[16];

	memset(buf, 'x', sizeof(buf));
	status_reset(&s);
	status_join(&s, buf, sizeof(buf));
	assert_string_equal(buf, "");
}

/* a short buffer: cut, terminated, never written past */
static void test_status_join_truncates(void **state)
{
	struct status s;
	char buf[32];
	int i;

	status_reset(&s);
	for (i = 0; i < STATUS_MAX_MSGS + 2; i++)
		status_add(&s, LEVEL_WARN, "message number %d", i);
	memset(buf, 'x', sizeof(buf));
	status_join(&s, buf, 12);
	assert_int_equal(strlen(buf), 11);
	assert_string_equal(buf, "message num");
	for (i = 12; i < (int)sizeof(buf); i++)
		assert_int_equal(buf[i], 'x');

	/* room for the messages but not for all of "; N more" */
	status_reset(&s);
	for (i = 0; i < STATUS_MAX_MSGS + 1; i++)
		status_add(&s, LEVEL_WARN, "%c", 'a' + i);
	memset(buf, 'x', sizeof(buf));
	status_join(&s, buf, 26);
	assert_string_equal(buf, "a; b; c; d; e; f; g; h; 1");
	for (i = 26; i < (int)sizeof(buf); i++)
		assert_int_equal(buf[i], 'x');
	status_join(&s, buf, sizeof(buf));
	assert_string_equal(buf, "a; b; c; d; e; f; g; h; 1 more");
}

/* a message longer than STATUS_MSG_LEN is cut, not overflowed */
static void test_status_long_message_cut(void **state)
{
	char longtext[STATUS_MSG_LEN * 2];
	struct status s;

	memset(longtext, 'y', sizeof(longtext) - 1);
	longtext[sizeof(longtext) - 1] = '\0';
	status_reset(&s);
	status_add(&s, LEVEL_WARN, "%s", longtext);
	status_add(&s, LEVEL_WARN, "next");
	assert_int_equal(strlen(s.msg[0]), STATUS_MSG_LEN - 1);
	assert_string_equal(s.msg[1], "next");
}

/* an ongoing condition whose numbers grow is the same kind of status */
static void test_status_same_kind(void **state)
{
	struct status a, b;

	(void)state;
	status_reset(&a);
	status_reset(&b);
	status_add(&a, LEVEL_ERROR, "not responding: no frame for 30.0 ms (3 periods)");
	status_add(&b, LEVEL_ERROR, "not responding: no frame for 1240.5 ms (124 periods)");
	assert_true(status_same_kind(&a, &b));
	assert_false(status_same(&a, &b));
	/* other words, another level, or one more message: not the same kind */
	status_reset(&b);
	status_add(&b, LEVEL_ERROR, "no heartbeat for 30 ms");
	assert_false(status_same_kind(&a, &b));
	status_reset(&b);
	status_add(&b, LEVEL_WARN, "not responding: no frame for 30.0 ms (3 periods)");
	assert_false(status_same_kind(&a, &b));
	status_reset(&b);
	status_add(&b, LEVEL_ERROR, "not responding: no frame for 31.0 ms (3 periods)");
	status_add(&b, LEVEL_WARN, "gap jitter 5.0 us > 1.0 us");
	assert_false(status_same_kind(&a, &b));
	/* a number where the other has text is a difference */
	status_reset(&a);
	status_reset(&b);
	status_add(&a, LEVEL_WARN, "NMT state 5");
	status_add(&b, LEVEL_WARN, "NMT state stopped");
	assert_false(status_same_kind(&a, &b));
}

static void test_status_same(void **state)
{
	struct status a, b;

	status_reset(&a);
	status_reset(&b);
	assert_true(status_same(&a, &b));

	status_add(&a, LEVEL_WARN, "x %d", 1);
	status_add(&a, LEVEL_OK, "y");
	status_add(&b, LEVEL_WARN, "x 1");
	status_add(&b, LEVEL_OK, "y");
	assert_true(status_same(&a, &b));
	assert_true(status_same(&b, &a));

	/* another level */
	b.level = LEVEL_ERROR;
	assert_false(status_same(&a, &b));

	/* another text */
	status_reset(&b);
	status_add(&b, LEVEL_WARN, "x 2");
	status_add(&b, LEVEL_OK, "y");
	assert_false(status_same(&a, &b));

	/* one message more */
	status_reset(&b);
	status_add(&b, LEVEL_WARN, "x 1");
	status_add(&b, LEVEL_OK, "y");
	status_add(&b, LEVEL_OK, "z");
	assert_false(status_same(&a, &b));

	/* the same messages in another order */
	status_reset(&b);
	status_add(&b, LEVEL_OK, "y");
	status_add(&b, LEVEL_WARN, "x 1");
	assert_false(status_same(&a, &b));

	/* the same level, no messages vs one */
	status_reset(&a);
	status_reset(&b);
	status_add(&b, LEVEL_OK, "restarted");
	assert_false(status_same(&a, &b));
}

static void test_status_level_fails(void **state)
{
	assert_true(level_fails(LEVEL_WARN, LEVEL_WARN));
	assert_false(level_fails(LEVEL_WARN, LEVEL_ERROR));
	assert_true(level_fails(LEVEL_ERROR, LEVEL_ERROR));
	assert_true(level_fails(LEVEL_ERROR, LEVEL_WARN));
	assert_false(level_fails(LEVEL_STALE, LEVEL_WARN));
	assert_false(level_fails(LEVEL_OK, LEVEL_WARN));
	assert_false(level_fails(LEVEL_OK, LEVEL_ERROR));
	assert_false(level_fails(LEVEL_STALE, LEVEL_ERROR));
	/* OK and STALE never fail, whatever the minimum */
	assert_false(level_fails(LEVEL_OK, LEVEL_OK));
	assert_false(level_fails(LEVEL_STALE, LEVEL_STALE));
}

static void test_status_level_name(void **state)
{
	assert_string_equal(level_name(LEVEL_OK), "OK");
	assert_string_equal(level_name(LEVEL_STALE), "STALE");
	assert_string_equal(level_name(LEVEL_WARN), "WARN");
	assert_string_equal(level_name(LEVEL_ERROR), "ERROR");
	assert_string_equal(level_name((enum level)42), "?");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_status_worst_wins_any_order),
		cmocka_unit_test(test_status_worst_wins_subsets),
		cmocka_unit_test(test_status_reset_clears),
		cmocka_unit_test(test_status_messages_all_kept),
		cmocka_unit_test(test_status_full_no_dropped),
		cmocka_unit_test(test_status_overflow_dropped),
		cmocka_unit_test(test_status_join_empty),
		cmocka_unit_test(test_status_join_truncates),
		cmocka_unit_test(test_status_long_message_cut),
		cmocka_unit_test(test_status_same),
		cmocka_unit_test(test_status_same_kind),
		cmocka_unit_test(test_status_level_fails),
		cmocka_unit_test(test_status_level_name),
	};

	return cmocka_run_group_tests_name("status", tests, NULL, NULL);
}
