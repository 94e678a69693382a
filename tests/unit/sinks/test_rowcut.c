// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* test_rowcut.c - which threads a report lists when there are many (user/sinks/rowcut.c) */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "sinks/rowcut.h"

#define N	1000
#define OK	0
#define WARN	2
#define ERROR	3

static struct rowcut_row rows[N];
static int show[N], order[N];

static int setup(void **state)
{
	memset(rows, 0, sizeof(rows));
	return 0;
}

/* 1000 OK threads: the worst 10 by misses, then unsafe, then latency, in input order */
static void test_rowcut_worst_n_of_many(void **state)
{
	int i, n, cut;

	for (i = 0; i < N; i++)
		rows[i].lat_max_ns = 1000 + i % 7;
	rows[500].misses = 1;
	rows[20].misses = 3;
	rows[900].unsafe = 2;
	rows[3].unsafe = 1;
	/* the largest latencies: i % 7 == 6, the first ones in input order */
	n = rowcut_pick(rows, N, 10, false, show, order, &cut);
	assert_int_equal(n, 10);
	assert_int_equal(cut, N - 10);
	{
		/* 4 by counts, then 6 by latency 1006: i = 6, 13, 27, 34, 41, 48 (20 is in) */
		int want[10] = { 3, 6, 13, 20, 27, 34, 41, 48, 500, 900 };

		assert_memory_equal(show, want, sizeof(want));
	}
}

static const struct rowcut_row *ref_rows;

/* ref_worse - the order rowcut_pick's cut is by (rowcut.h), written again */
static int ref_worse(const void *a, const void *b)
{
	int i = *(const int *)a, j = *(const int *)b;
	const struct rowcut_row *x = &ref_rows[i], *y = &ref_rows[j];

	if (x->misses != y->misses)
		return x->misses > y->misses ? -1 : 1;
	if (x->unsafe != y->unsafe)
		return x->unsafe > y->unsafe ? -1 : 1;
	if (x->lat_max_ns != y->lat_max_ns)
		return x->lat_max_ns > y->lat_max_ns ? -1 : 1;
	return i - j;
}

static int ref_index(const void *a, const void *b)
{
	return *(const int *)a - *(const int *)b;
}

/*
 * the cut keeps what a sort of every row would: random rows with many ties
 * (most alike, as parked threads are), every top from 0 to past n
 */
static void test_rowcut_same_as_a_sort(void **state)
{
	static int want[N];
	unsigned seed = 1;
	int round, i, n, cut, top, nrows;

	for (round = 0; round < 40; round++) {
		nrows = 1 + round * 25;
		for (i = 0; i < nrows; i++) {
			seed = seed * 1103515245u + 12345u;
			rows[i] = (struct rowcut_row){ .misses = (seed >> 16) % 7 == 0 ? (seed >> 8) % 3 : 0,
				.unsafe = (seed >> 20) % 5 == 0 ? (seed >> 4) % 2 : 0,
				.lat_max_ns = (seed >> 12) % 4 };
		}
		for (top = 0; top <= nrows + 1; top += 1 + nrows / 7) {
			for (i = 0; i < nrows; i++)
				want[i] = i;
			ref_rows = rows;
			qsort(want, nrows, sizeof(*want), ref_worse);
			n = top < nrows ? top : nrows;
			qsort(want, n, sizeof(*want), ref_index);
			assert_int_equal(rowcut_pick(rows, nrows, top, false, show, order, &cut), n);
			assert_int_equal(cut, nrows - n);
			assert_memory_equal(show, want, n * sizeof(*want));
		}
	}
}

/* every thread that is not OK is shown, on top of the worst N of the others */
static void test_rowcut_not_ok_always(void **state)
{
	int i, n, cut;

	for (i = 0; i < N; i += 50)
		rows[i].level = i % 100 ? WARN : ERROR;
	rows[7].misses = 5;
	n = rowcut_pick(rows, N, 1, false, show, order, &cut);
	assert_int_equal(n, 21);
	assert_int_equal(cut, N - 21);
	for (i = 0; i < 20; i++)
		assert_int_equal(show[i + (i > 0)], i * 50);
	assert_int_equal(show[1], 7);
}

/* --all: every row; rows reported before are no rows; few rows: nothing cut */
static void test_rowcut_all_and_skip(void **state)
{
	int i, n, cut;

	rows[2].skip = true;
	n = rowcut_pick(rows, N, 10, true, show, order, &cut);
	assert_int_equal(n, N - 1);
	assert_int_equal(cut, 0);
	for (i = 0; i < n; i++)
		assert_int_equal(show[i], i < 2 ? i : i + 1);
	n = rowcut_pick(rows, 11, 10, false, show, order, &cut);
	assert_int_equal(n, 10);
	assert_int_equal(cut, 0);
	n = rowcut_pick(rows, 12, 10, false, show, order, &cut);
	assert_int_equal(n, 10);
	assert_int_equal(cut, 1);
	/* --top 0: only what is not OK */
	rows[5].level = ERROR;
	n = rowcut_pick(rows, N, 0, false, show, order, &cut);
	assert_int_equal(n, 1);
	assert_int_equal(show[0], 5);
	assert_int_equal(cut, N - 2);
}

/* --json-threads active: ran, switched or changed level */
static void test_rowcut_active(void **state)
{
	assert_false(rowcut_active(0, 0, false));
	assert_true(rowcut_active(1, 0, false));
	assert_true(rowcut_active(0, 2, false));
	assert_true(rowcut_active(0, 0, true));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup(test_rowcut_worst_n_of_many, setup),
		cmocka_unit_test_setup(test_rowcut_same_as_a_sort, setup),
		cmocka_unit_test_setup(test_rowcut_not_ok_always, setup),
		cmocka_unit_test_setup(test_rowcut_all_and_skip, setup),
		cmocka_unit_test_setup(test_rowcut_active, setup),
	};

	return cmocka_run_group_tests_name("rowcut", tests, NULL, NULL);
}
