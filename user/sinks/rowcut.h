/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * rowcut.h - which threads a report lists when there are many (issue 19):
 * the table shows every thread that is not OK and the worst N of the
 * others, with one line for the rest (--all: every thread); JSON intervals
 * may list only the threads that did something or changed level
 * (--json-threads active). Plain data in, indices out: unit-tested.
 */
#ifndef RTSUP_ROWCUT_H
#define RTSUP_ROWCUT_H

#include <stdbool.h>
#include <linux/types.h>

/* The worst N of the OK threads, by default. */
#define ROWCUT_TOP_DEFAULT	10

/* One thread, as the cut ranks it. */
struct rowcut_row {
	int level;		/* enum level: above LEVEL_OK is always shown */
	bool skip;		/* not a row of this report (reported before) */
	__u64 misses;		/* ranked by these, in this order, the most first */
	__u64 unsafe;
	__u64 lat_max_ns;
};

/*
 * rowcut_pick - the rows to show: every row not OK, then the top worst of
 * the OK rows (misses, RT-unsafe events, worst latency; ties in input
 * order); all: every row. show[] gets their indices in input order, n at
 * most; order[] is scratch of n ints. Returns how many; *cut the rows
 * left out (skipped rows are neither).
 */
int rowcut_pick(const struct rowcut_row *rows, int n, int top, bool all, int *show,
		int *order, int *cut);

/*
 * rowcut_active - does a JSON interval with --json-threads active list the
 * thread: switched or ran a cycle in the interval, or its level changed
 */
bool rowcut_active(__u64 cycles, __u64 switches, bool level_changed);

#endif
