// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* rowcut.c - which threads a report lists when there are many (rowcut.h) */
#include <stdlib.h>
#include "sinks/rowcut.h"

/* 0 is LEVEL_OK (judge/status.h): the cut needs no more of the judge */
#define ROWCUT_OK	0

static const struct rowcut_row *sort_rows;

/* worse_first - the worse row first; the earlier one of equals */
static int worse_first(const void *a, const void *b)
{
	int i = *(const int *)a, j = *(const int *)b;
	const struct rowcut_row *x = &sort_rows[i], *y = &sort_rows[j];

	if (x->misses != y->misses)
		return x->misses > y->misses ? -1 : 1;
	if (x->unsafe != y->unsafe)
		return x->unsafe > y->unsafe ? -1 : 1;
	if (x->lat_max_ns != y->lat_max_ns)
		return x->lat_max_ns > y->lat_max_ns ? -1 : 1;
	return i - j;
}

/* by_index - input order */
static int by_index(const void *a, const void *b)
{
	return *(const int *)a - *(const int *)b;
}

/* heap_down - heap[0..n) with the least bad row on top again, from position i */
static void heap_down(int *heap, int n, int i)
{
	for (;;) {
		int l = 2 * i + 1, r = l + 1, top = i, t;

		/* the least bad: the one worse_first puts last */
		if (l < n && worse_first(&heap[l], &heap[top]) > 0)
			top = l;
		if (r < n && worse_first(&heap[r], &heap[top]) > 0)
			top = r;
		if (top == i)
			return;
		t = heap[i];
		heap[i] = heap[top];
		heap[top] = t;
		i = top;
	}
}

/*
 * worst_n - the top first of ok[0..n) as worse_first sorts them, in
 * ok[0..top), in no order: a heap of top whose least bad row a worse one
 * replaces. Most of 1000 threads are parked and alike (no miss, nothing
 * unsafe): each costs one comparison, not a sort's ten.
 */
static void worst_n(int *ok, int n, int top)
{
	int i, t;

	for (i = top / 2 - 1; i >= 0; i--)
		heap_down(ok, top, i);
	for (i = top; i < n; i++) {
		if (worse_first(&ok[i], &ok[0]) >= 0)
			continue;
		t = ok[0];
		ok[0] = ok[i];
		ok[i] = t;
		heap_down(ok, top, 0);
	}
}

int rowcut_pick(const struct rowcut_row *rows, int n, int top, bool all, int *show,
		int *order, int *cut)
{
	int i, nshow = 0, nok = 0;

	*cut = 0;
	for (i = 0; i < n; i++) {
		if (rows[i].skip)
			continue;
		if (all || rows[i].level > ROWCUT_OK)
			show[nshow++] = i;
		else
			order[nok++] = i;
	}
	if (nok > top) {
		sort_rows = rows;
		if (top > 0)
			worst_n(order, nok, top);
		*cut = nok - top;
		nok = top;
	}
	for (i = 0; i < nok; i++)
		show[nshow++] = order[i];
	qsort(show, nshow, sizeof(*show), by_index);
	return nshow;
}

bool rowcut_active(__u64 cycles, __u64 switches, bool level_changed)
{
	return cycles || switches || level_changed;
}
