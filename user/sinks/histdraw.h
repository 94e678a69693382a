/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * histdraw.h - a metric's histogram as lines of text: the kernel's
 * log-linear buckets regrouped into at most HD_MAX_ROWS rows (each kernel
 * bucket, or aligned groups of 2, 4, 8 of them = one power of two, or of
 * several powers of two), empty rows at both ends trimmed, a bar
 * per row scaled to the largest count, and the thresholds and percentiles
 * marked on their rows; with colour, the rows that hold values above WARN
 * yellow, above ERROR red. Pure functions: no terminal, no model.
 */
#ifndef RTSUP_HISTDRAW_H
#define RTSUP_HISTDRAW_H

#include <stdbool.h>
#include <stdio.h>
#include <linux/types.h>
#include "rtsup.h"

/* at most this many rows: a histogram fits on a screen */
#define HD_MAX_ROWS	20
#define HD_LINE		256

/* What is marked on a histogram; 0 = not marked. */
enum hd_mark { HD_WARN, HD_ERROR, HD_P50, HD_P99, HD_P999, HD_MAX, HD_NMARKS };

struct hd_hist {
	char title[96];			/* e.g. "lg-0[1234] exec" */
	const __u64 *h;			/* HIST_BUCKETS counts */
	__u64 mark[HD_NMARKS];		/* ns */
};

/* One display row: the values in [lo, hi), in ns. */
struct hd_row {
	__u64 lo, hi;
	__u64 count;
};

/*
 * histdraw_rows - the kernel buckets h regrouped into at most max rows,
 * the finest grouping that fits, trimmed of empty rows at both ends but
 * stretched to the thresholds when that needs rows no coarser than a power
 * of two. Rows are whole kernel buckets, so their bounds and counts are
 * exact (readable round bounds such as 1-2-5 would cut kernel buckets in
 * two and misplace their counts). Returns the number of rows, 0 when empty.
 */
int histdraw_rows(const __u64 *h, const __u64 *mark, struct hd_row *rows, int max);

/*
 * histdraw_lines - one histogram as lines of at most 'width' columns (not
 * counting colour codes): a title, a header, one line per row. Returns the
 * number of lines written to out (at most HD_MAX_ROWS + 2).
 */
int histdraw_lines(const struct hd_hist *hh, int width, bool color,
		   char out[][HD_LINE]);

/*
 * histdraw_print - several histograms side by side in columns when 'width'
 * allows it (at least HD_MIN_WIDTH each), else one under the other
 */
#define HD_MIN_WIDTH	72
void histdraw_print(FILE *f, const struct hd_hist *hs, int n, int width, bool color);

/* histdraw_fmt_ns - a time with its unit, e.g. "500us", "1.5ms", "2s" */
void histdraw_fmt_ns(char *buf, size_t len, __u64 ns);

#endif
