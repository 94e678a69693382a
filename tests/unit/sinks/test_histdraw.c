// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_histdraw.c - user/sinks/histdraw.c against a fixed histogram: rows in
 * 1-2-5 steps, empty ends trimmed, bars scaled to the largest count with
 * a lone outlier still visible, thresholds and percentiles on their rows.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "hist.h"
#include "sinks/histdraw.h"

#define US	1000ULL
#define MS	1000000ULL

static __u64 h[HIST_BUCKETS];

/* the fixed histogram: 1000 x 120 us, 10 x 300 us, 1 x 4 ms (the overrun) */
static int setup(void **state)
{
	memset(h, 0, sizeof(h));
	h[hist_bucket(120 * US)] = 1000;
	h[hist_bucket(300 * US)] = 10;
	h[hist_bucket(4 * MS)] = 1;
	return 0;
}

/* count - '#' in a line */
static int bars(const char *s)
{
	int n = 0;

	for (; *s; s++)
		n += *s == '#';
	return n;
}

/*
 * rows: buckets 118 (120 us) .. 159 (4 ms) are 42 kernel buckets, too many
 * for 20 rows one by one or by two; by four (half a power of two): 11 rows,
 * nothing before or after, bounds of kernel buckets
 */
static void test_histdraw_rows_trimmed(void **state)
{
	struct hd_row r[HD_MAX_ROWS];
	int n = histdraw_rows(h, NULL, r, HD_MAX_ROWS);

	assert_int_equal(hist_bucket(120 * US), 118);
	assert_int_equal(hist_bucket(4 * MS), 159);
	assert_int_equal(n, 11);
	assert_int_equal(r[0].lo, 98304);	/* bucket 116 .. 119 */
	assert_int_equal(r[0].hi, 131072);
	assert_int_equal(r[0].count, 1000);
	assert_int_equal(r[3].lo, 262144);	/* 300 us: bucket 129 in 128 .. 131 */
	assert_int_equal(r[3].hi, 393216);
	assert_int_equal(r[3].count, 10);
	assert_int_equal(r[1].count + r[2].count + r[4].count, 0);
	assert_int_equal(r[10].lo, 3145728);	/* 4 ms: 156 .. 159 */
	assert_int_equal(r[10].hi, 4194304);
	assert_int_equal(r[10].count, 1);
}

/* one row per kernel bucket when they fit; then powers of two and more */
static void test_histdraw_rows_grouping(void **state)
{
	struct hd_row r[HD_MAX_ROWS];

	memset(h, 0, sizeof(h));
	h[hist_bucket(100 * US)] = 5;	/* 98304 .. 106495 */
	h[hist_bucket(110 * US)] = 2;
	assert_int_equal(histdraw_rows(h, NULL, r, HD_MAX_ROWS), 2);
	assert_int_equal(r[0].lo, 98304);
	assert_int_equal(r[0].hi, 106496);
	assert_int_equal(r[0].count, 5);
	assert_int_equal(r[1].count, 2);
	/* 20 ns .. 4 ms in 10 rows: two powers of two a row */
	h[hist_bucket(20)] = 1;
	h[hist_bucket(4 * MS)] = 1;
	assert_int_equal(histdraw_rows(h, NULL, r, 10), 9);
	assert_int_equal(r[0].lo, 16);
	assert_int_equal(r[0].count, 1);
	assert_int_equal(r[8].hi, 4194304);
	assert_int_equal(r[8].count, 1);
}

/* a threshold beyond the data stretches the rows to it, when it fits */
static void test_histdraw_rows_to_threshold(void **state)
{
	struct hd_row r[HD_MAX_ROWS];
	__u64 mark[HD_NMARKS] = { [HD_WARN] = 8 * MS, [HD_ERROR] = 20 * MS };
	int n = histdraw_rows(h, mark, r, HD_MAX_ROWS);

	assert_int_equal(n, 16);
	assert_true(r[n - 1].lo <= 20 * MS && 20 * MS < r[n - 1].hi);
	assert_int_equal(r[n - 1].count, 0);
	/* 20 s still fits with a power of two a row */
	mark[HD_ERROR] = 20000 * MS;
	n = histdraw_rows(h, mark, r, HD_MAX_ROWS);
	assert_true(n > 16 && n <= HD_MAX_ROWS);
	assert_true(r[n - 1].lo <= 20000 * MS && 20000 * MS < r[n - 1].hi);
	/* 100 s is too far: the rows stop at the WARN one (8 ms) */
	mark[HD_ERROR] = 100000 * MS;
	n = histdraw_rows(h, mark, r, HD_MAX_ROWS);
	assert_true(r[n - 1].lo <= 8 * MS && 8 * MS < r[n - 1].hi);
	mark[HD_WARN] = 0;
	assert_int_equal(histdraw_rows(h, mark, r, HD_MAX_ROWS), 11);
}

/* empty histogram: a title and no rows */
static void test_histdraw_empty(void **state)
{
	static char out[HD_MAX_ROWS + 2][HD_LINE];
	struct hd_hist hh = { .title = "t", .h = h };

	memset(h, 0, sizeof(h));
	assert_int_equal(histdraw_lines(&hh, 80, false, out), 1);
	assert_string_equal(out[0], "t (0)");
}

/* bars scale to the biggest row; the one outlier still shows; marks on their rows */
static void test_histdraw_lines_scale_marks(void **state)
{
	static char out[HD_MAX_ROWS + 2][HD_LINE];
	struct hd_hist hh = { .title = "lg-0[42] exec", .h = h };
	int n, full, i;

	hh.mark[HD_WARN] = 700 * US;	/* row 5 */
	hh.mark[HD_ERROR] = 3 * MS;	/* row 9 */
	hh.mark[HD_P50] = 120 * US;
	hh.mark[HD_P99] = 125 * US;
	hh.mark[HD_P999] = 300 * US;
	hh.mark[HD_MAX] = 4 * MS;
	n = histdraw_lines(&hh, 100, false, out);
	assert_int_equal(n, 2 + 11);
	assert_string_equal(out[0], "lg-0[42] exec (1011)");
	assert_non_null(strstr(out[1], "count"));
	full = bars(out[2]);
	assert_int_equal(full, 100 - 48);	/* the biggest row fills the bar */
	assert_non_null(strstr(out[2], "98.3us .. 131us"));
	assert_non_null(strstr(out[2], " 1000 |"));
	assert_non_null(strstr(out[2], "| p50 p99"));
	/* 10 of 1000: rounded up, at least one */
	assert_int_equal(bars(out[2 + 3]), (10 * full + 999) / 1000);
	assert_non_null(strstr(out[2 + 3], "| p99.9"));
	assert_non_null(strstr(out[2 + 5], "| WARN"));	/* empty */
	assert_int_equal(bars(out[2 + 5]), 0);
	assert_non_null(strstr(out[2 + 9], "| ERROR"));
	assert_int_equal(bars(out[2 + 10]), 1);	/* the overrun: one value, one mark */
	assert_non_null(strstr(out[2 + 10], "| max"));
	for (i = 0; i < n; i++)
		assert_true(strlen(out[i]) <= 100);
	/* colour: rows with values above ERROR red, above WARN yellow, none below */
	histdraw_lines(&hh, 100, true, out);
	assert_non_null(strstr(out[2 + 10], "\033[31m"));
	assert_non_null(strstr(out[2 + 9], "\033[31m"));
	assert_non_null(strstr(out[2 + 8], "\033[33m"));
	assert_non_null(strstr(out[2 + 5], "\033[33m"));
	for (i = 0; i < 2 + 5; i++)
		assert_null(strchr(out[i], '\033'));
	/* a mark beyond the last row is on it, with its value */
	hh.mark[HD_MAX] = 50 * MS;
	histdraw_lines(&hh, 100, false, out);
	assert_non_null(strstr(out[2 + 10], "| max>50ms"));
}

/* units */
static void test_histdraw_fmt(void **state)
{
	char b[16];

	histdraw_fmt_ns(b, sizeof(b), 500);
	assert_string_equal(b, "500ns");
	histdraw_fmt_ns(b, sizeof(b), 2 * US);
	assert_string_equal(b, "2us");
	histdraw_fmt_ns(b, sizeof(b), 1500 * US);
	assert_string_equal(b, "1.5ms");
	histdraw_fmt_ns(b, sizeof(b), 10000 * MS);
	assert_string_equal(b, "10s");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup(test_histdraw_rows_trimmed, setup),
		cmocka_unit_test_setup(test_histdraw_rows_to_threshold, setup),
		cmocka_unit_test_setup(test_histdraw_rows_grouping, setup),
		cmocka_unit_test_setup(test_histdraw_empty, setup),
		cmocka_unit_test_setup(test_histdraw_lines_scale_marks, setup),
		cmocka_unit_test(test_histdraw_fmt),
	};

	return cmocka_run_group_tests_name("histdraw", tests, NULL, NULL);
}
