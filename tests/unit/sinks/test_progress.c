// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_progress.c - user/sinks/progress.c: the bar's text, and that nothing is
 * drawn when off (not a terminal, -q) or before a replay has taken a while.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "sinks/progress.h"

/* count - occurrences of c in s */
static int count(const char *s, char c)
{
	int n = 0;

	for (; *s; s++)
		n += *s == c;
	return n;
}

static void test_progress_line(void **state)
{
	char b[256];

	progress_line(b, sizeof(b), 0, 1000, 72);
	assert_int_equal(count(b, '#'), 0);
	assert_int_equal(count(b, '.') - 1, 72 - 28);	/* and the one in "MB" */
	assert_non_null(strstr(b, "]   0%"));
	progress_line(b, sizeof(b), 500, 1000, 72);
	assert_int_equal(count(b, '#'), (72 - 28) / 2);
	assert_non_null(strstr(b, "]  50%"));
	progress_line(b, sizeof(b), 2000, 1000, 72);	/* never past the end */
	assert_int_equal(count(b, '#'), 72 - 28);
	assert_non_null(strstr(b, "] 100%"));
	assert_true(strlen(b) <= 72);
}

/* drawn, then cleared: a carriage return, the bar, and the erased line */
static void test_progress_draw(void **state)
{
	char buf[4096] = "";
	FILE *f = fmemopen(buf, sizeof(buf), "w");
	struct progress p;

	assert_non_null(f);
	progress_start(&p, f, 1000, true);
	progress_draw(&p, 250);
	progress_end(&p);
	fclose(f);
	assert_true(buf[0] == '\r');
	assert_non_null(strstr(buf, "]  25%"));
	assert_non_null(strstr(buf, "\r\033[K"));
}

/* off, or too early: the stream stays empty */
static void test_progress_quiet(void **state)
{
	char buf[4096] = "";
	FILE *f = fmemopen(buf, sizeof(buf), "w");
	struct progress p;
	int i;

	assert_non_null(f);
	progress_start(&p, f, 1000, false);
	for (i = 0; i < 100000; i++)
		assert_false(progress_due(&p));
	progress_end(&p);
	/* on, but the replay is young: nothing yet either */
	progress_start(&p, f, 1000, true);
	for (i = 0; i < 1000; i++)
		assert_false(progress_due(&p));
	progress_end(&p);
	fclose(f);
	assert_string_equal(buf, "");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_progress_line),
		cmocka_unit_test(test_progress_quiet),
		cmocka_unit_test(test_progress_draw),
	};

	return cmocka_run_group_tests_name("progress", tests, NULL, NULL);
}
