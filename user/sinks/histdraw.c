// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* histdraw.c - histograms as text: rows, bars and marks (see histdraw.h) */
#include <stdio.h>
#include <string.h>
#include "hist.h"
#include "sinks/histdraw.h"

static const char *const mark_names[HD_NMARKS] = {
	[HD_WARN] = "WARN", [HD_ERROR] = "ERROR", [HD_P50] = "p50",
	[HD_P99] = "p99", [HD_P999] = "p99.9", [HD_MAX] = "max",
};

/* range - first and last non-empty kernel bucket, -1 when none */
static int range(const __u64 *h, int *first, int *last)
{
	int b;

	*first = *last = -1;
	for (b = 0; b < HIST_BUCKETS; b++) {
		if (!h[b])
			continue;
		if (*first < 0)
			*first = b;
		*last = b;
	}
	return *first;
}

/* rows_for - rows that buckets first..last take in groups of g */
static int rows_for(int first, int last, int g)
{
	return last / g - first / g + 1;
}

/*
 * group - the finest grouping that fits in max rows: 1, 2, 4 or 8 kernel
 * buckets (8 make a power of two), then 2, 4... powers of two; groups are
 * aligned, so a row's bounds are kernel bucket bounds, exact
 */
static int group(int first, int last, int max)
{
	int g = 1;

	while (rows_for(first, last, g) > max)
		g *= 2;
	return g;
}

int histdraw_rows(const __u64 *h, const __u64 *mark, struct hd_row *rows, int max)
{
	int first, last, f, l, g, t, b, n, i;

	if (max < 1 || range(h, &first, &last) < 0)
		return 0;
	g = group(first, last, max);
	/* show how far the thresholds are, when that needs no coarser rows */
	f = first;
	l = last;
	for (t = HD_WARN; t <= HD_ERROR; t++) {
		if (!mark || !mark[t])
			continue;
		b = hist_bucket(mark[t]);
		if (b > l && group(f, b, max) <= (g > 8 ? g : 8))
			l = b;
		if (b < f && group(b, l, max) <= (g > 8 ? g : 8))
			f = b;
	}
	g = group(f, l, max);
	n = rows_for(f, l, g);
	for (i = 0; i < n; i++) {
		int lo = (f / g + i) * g, hi = lo + g - 1;

		rows[i].lo = hist_bucket_low(lo);
		rows[i].hi = hi >= HIST_BUCKETS - 1 ? ~0ULL : hist_bucket_high(hi) + 1;
		rows[i].count = 0;
	}
	for (b = first; b <= last; b++)
		rows[b / g - f / g].count += h[b];
	return n;
}

void histdraw_fmt_ns(char *buf, size_t len, __u64 ns)
{
	static const struct { __u64 div; const char *unit; } u[] = {
		{ 1000000000ULL, "s" }, { 1000000, "ms" }, { 1000, "us" }, { 1, "ns" },
	};
	int i;

	if (ns == ~0ULL) {
		snprintf(buf, len, "inf");
		return;
	}
	for (i = 0; i < 3 && ns < u[i].div; i++)
		;
	if (ns % u[i].div == 0)
		snprintf(buf, len, "%llu%s", (unsigned long long)(ns / u[i].div), u[i].unit);
	else
		snprintf(buf, len, "%.3g%s", (double)ns / (double)u[i].div, u[i].unit);
}

/*
 * marks_of - the names of the marks in [lo, hi), space separated; on the
 * last row also those beyond it, with their value ("ERROR>20ms")
 */
static void marks_of(const struct hd_hist *hh, const struct hd_row *r, bool last_row,
		     char *buf, size_t len)
{
	char val[16] = "";
	int m;
	size_t n = 0;

	buf[0] = '\0';
	for (m = 0; m < HD_NMARKS; m++) {
		__u64 v = hh->mark[m];

		if (!v || v < r->lo || (v >= r->hi && !last_row))
			continue;
		val[0] = '\0';
		if (v >= r->hi) {
			val[0] = '>';
			histdraw_fmt_ns(val + 1, sizeof(val) - 1, v);
		}
		n += snprintf(buf + n, len - n, "%s%s%s", n ? " " : "", mark_names[m], val);
		if (n >= len)
			break;
	}
}

/* row_level - HD_ERROR or HD_WARN when the row holds values above that threshold, else -1 */
static int row_level(const struct hd_hist *hh, const struct hd_row *r)
{
	if (hh->mark[HD_ERROR] && r->hi - 1 > hh->mark[HD_ERROR])
		return HD_ERROR;
	if (hh->mark[HD_WARN] && r->hi - 1 > hh->mark[HD_WARN])
		return HD_WARN;
	return -1;
}

int histdraw_lines(const struct hd_hist *hh, int width, bool color, char out[][HD_LINE])
{
	struct hd_row rows[HD_MAX_ROWS];
	char lo[16], hi[16], mk[48];
	__u64 top = 0, total = 0;
	int n, i, bar, len, nl = 0;

	n = histdraw_rows(hh->h, hh->mark, rows, HD_MAX_ROWS);
	for (i = 0; i < n; i++) {
		total += rows[i].count;
		if (rows[i].count > top)
			top = rows[i].count;
	}
	if (width >= HD_LINE)
		width = HD_LINE - 1;
	snprintf(out[nl++], HD_LINE, "%.*s (%llu)", width - 24 > 0 ? width - 24 : 0, hh->title,
		 (unsigned long long)total);
	if (!n)
		return nl;
	/* " 9.44ms .. 10.5ms      count |bar| marks": 30 columns before the bar */
	bar = width - 30 - 18;
	if (bar < 10)
		bar = 10;
	snprintf(out[nl++], HD_LINE, "%18s %9s  %-*s", "range", "count", bar + 2, "distribution");
	for (i = 0; i < n; i++) {
		const struct hd_row *r = &rows[i];
		/* every row with a count shows at least one mark: the outlier is seen */
		int fill = top ? (int)((r->count * bar + top - 1) / top) : 0;
		int worst = row_level(hh, r);
		const char *on = "", *off = "";

		if (color && worst >= 0) {
			on = worst == HD_ERROR ? "\033[31m" : "\033[33m";
			off = "\033[0m";
		}
		if (fill > bar)
			fill = bar;
		marks_of(hh, r, i == n - 1, mk, sizeof(mk));
		histdraw_fmt_ns(lo, sizeof(lo), r->lo);
		histdraw_fmt_ns(hi, sizeof(hi), r->hi);
		len = snprintf(out[nl], HD_LINE, "%7s .. %-7s %9llu |%s", lo, hi,
			       (unsigned long long)r->count, on);
		memset(out[nl] + len, '#', fill);
		memset(out[nl] + len + fill, ' ', bar - fill);
		len += bar;
		snprintf(out[nl] + len, HD_LINE - len, "%s| %s", off, mk);
		nl++;
	}
	return nl;
}

/* visible - columns a line takes: colour codes take none */
static int visible(const char *s)
{
	int n = 0;

	while (*s) {
		if (*s == '\033') {
			while (*s && *s != 'm')
				s++;
			if (*s)
				s++;
			continue;
		}
		n++;
		s++;
	}
	return n;
}

void histdraw_print(FILE *f, const struct hd_hist *hs, int n, int width, bool color)
{
	static char lines[8][HD_MAX_ROWS + 2][HD_LINE];
	int nl[8], cols, colw, i, j, k, most;

	cols = width / HD_MIN_WIDTH;
	if (cols < 1)
		cols = 1;
	if (cols > 8)
		cols = 8;
	if (cols > n)
		cols = n;
	colw = cols > 1 ? width / cols : width;
	for (i = 0; i < n; i += cols) {
		most = 0;
		for (j = 0; j < cols && i + j < n; j++) {
			nl[j] = histdraw_lines(&hs[i + j], colw - (cols > 1 ? 2 : 0), color,
					       lines[j]);
			if (nl[j] > most)
				most = nl[j];
		}
		for (k = 0; k < most; k++) {
			for (j = 0; j < cols && i + j < n; j++) {
				const char *s = k < nl[j] ? lines[j][k] : "";
				bool more = j + 1 < cols && i + j + 1 < n;

				fputs(s, f);
				if (more)
					fprintf(f, "%*s", colw - visible(s), "");
			}
			fputc('\n', f);
		}
		fputc('\n', f);
	}
}
