// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_histdraw.c - user/histdraw.c against a fixed histogram: rows in
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
#include "histdraw.h"

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

/* rows: 100us..5ms in 1-2-5 steps, nothing before or after */
static void test_histdraw_rows_trimmed(void **state)
{
	struct hd_row r[HD_MAX_ROWS];
	int n = histdraw_rows(h, NULL, r, HD_MAX_ROWS);

	assert_int_equal(n, 5);	/* 100-200-500us-1-2-5ms */
	assert_int_equal(r[0].lo, 100 * US);
	assert_int_equal(r[0].hi, 200 * US);
	assert_int_equal(r[0].count, 1000);
	assert_int_equal(r[1].count, 10);	/* 200..500 us */
	assert_int_equal(r[2].count, 0);
	assert_int_equal(r[4].lo, 2 * MS);
	assert_int_equal(r[4].count, 1);	/* 4 ms in 2..5 ms */
	assert_int_equal(r[4].hi, 5 * MS);
}

/* a threshold beyond the data stretches the rows to it */
static void test_histdraw_rows_to_threshold(void **state)
{
	struct hd_row r[HD_MAX_ROWS];
	__u64 mark[HD_NMARKS] = { [HD_WARN] = 8 * MS, [HD_ERROR] = 20 * MS };
	int n = histdraw_rows(h, mark, r, HD_MAX_ROWS);

	assert_int_equal(r[n - 1].lo, 20 * MS);
	assert_int_equal(r[n - 1].count, 0);
	/* too far to fit: decades, the data's tail kept */
	memset(mark, 0, sizeof(mark));
	h[hist_bucket(20)] = 1;	/* 20 ns .. 4 ms: 17 rows of 1-2-5 fit */
	assert_int_equal(histdraw_rows(h, mark, r, 10), 6);	/* 10ns..10ms in decades */
	assert_int_equal(r[0].lo, 10);
	assert_int_equal(r[5].hi, 10 * MS);
}

/* 100 us sits in kernel bucket 98304..106495: drawn in the row of its middle */
static void test_histdraw_rows_straddle(void **state)
{
	struct hd_row r[HD_MAX_ROWS];

	memset(h, 0, sizeof(h));
	h[hist_bucket(100 * US)] = 5;
	assert_true(hist_bucket_low(hist_bucket(100 * US)) < 100 * US);
	assert_int_equal(histdraw_rows(h, NULL, r, HD_MAX_ROWS), 1);
	assert_int_equal(r[0].lo, 100 * US);
	assert_int_equal(r[0].count, 5);
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

	hh.mark[HD_WARN] = 700 * US;
	hh.mark[HD_ERROR] = 3 * MS;
	hh.mark[HD_P50] = 120 * US;
	hh.mark[HD_P99] = 125 * US;
	hh.mark[HD_P999] = 300 * US;
	hh.mark[HD_MAX] = 4 * MS;
	n = histdraw_lines(&hh, 100, false, out);
	assert_int_equal(n, 2 + 5);
	assert_string_equal(out[0], "lg-0[42] exec (1011)");
	assert_non_null(strstr(out[1], "count"));
	full = bars(out[2]);
	assert_int_equal(full, 100 - 48);	/* the biggest row fills the bar */
	assert_non_null(strstr(out[2], "  100us .. 200us"));
	assert_non_null(strstr(out[2], "1000 |"));
	assert_non_null(strstr(out[2], "| p50 p99"));
	/* 10 of 1000: rounded up, at least one */
	assert_int_equal(bars(out[3]), (10 * full + 999) / 1000);
	assert_non_null(strstr(out[3], "| p99.9"));
	assert_non_null(strstr(out[4], "| WARN"));	/* 500us..1ms, empty */
	assert_int_equal(bars(out[4]), 0);
	assert_int_equal(bars(out[6]), 1);	/* the overrun: one value, one mark */
	assert_non_null(strstr(out[6], "| ERROR max"));
	for (i = 0; i < n; i++)
		assert_true(strlen(out[i]) <= 100);
	/* colour: the ERROR row red, the WARN row yellow, nothing elsewhere */
	histdraw_lines(&hh, 100, true, out);
	assert_non_null(strstr(out[6], "\033[31m"));
	assert_non_null(strstr(out[4], "\033[33m"));
	assert_null(strchr(out[2], '\033'));
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
		cmocka_unit_test_setup(test_histdraw_rows_straddle, setup),
		cmocka_unit_test_setup(test_histdraw_empty, setup),
		cmocka_unit_test_setup(test_histdraw_lines_scale_marks, setup),
		cmocka_unit_test(test_histdraw_fmt),
	};

	return cmocka_run_group_tests_name("histdraw", tests, NULL, NULL);
}
