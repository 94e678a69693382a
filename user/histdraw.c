// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* histdraw.c - histograms as text: rows, bars and marks (see histdraw.h) */
#include <stdio.h>
#include <string.h>
#include "hist.h"
#include "histdraw.h"

static const char *const mark_names[HD_NMARKS] = {
	[HD_WARN] = "WARN", [HD_ERROR] = "ERROR", [HD_P50] = "p50",
	[HD_P99] = "p99", [HD_P999] = "p99.9", [HD_MAX] = "max",
};

/* edge - the i-th row edge: 1-2-5 per decade (step 3) or decades (step 1) */
static __u64 edge(int i, int per_decade)
{
	static const __u64 f125[3] = { 1, 2, 5 };
	__u64 v = 1;
	int d;

	for (d = 0; d < i / per_decade; d++)
		v *= 10;
	return per_decade == 3 ? v * f125[i % 3] : v;
}

/* row_of - index of the row holding value v (edge(i) <= v < edge(i + 1)) */
static int row_of(__u64 v, int per_decade)
{
	int i = 0;

	/* edges up to 1e19 fit in a __u64: 19 decades */
	while (i < 19 * per_decade && edge(i + 1, per_decade) <= v)
		i++;
	return i;
}

/* bucket_row - the row of kernel bucket b: the one its middle falls in */
static int bucket_row(int b, int per_decade)
{
	__u64 lo = hist_bucket_low(b);

	return row_of(lo + (hist_bucket_high(b) - lo) / 2, per_decade);
}

/* span - first and last row that hold counts, -1 when none */
static int span(const __u64 *h, int per_decade, int *first, int *last)
{
	int b;

	*first = *last = -1;
	for (b = 0; b < HIST_BUCKETS; b++) {
		if (!h[b])
			continue;
		if (*first < 0)
			*first = bucket_row(b, per_decade);
		*last = bucket_row(b, per_decade);
	}
	return *first;
}

int histdraw_rows(const __u64 *h, const __u64 *mark, struct hd_row *rows, int max)
{
	int pd = 3, first, last, i, t, b;

	if (span(h, pd, &first, &last) < 0)
		return 0;
	if (last - first + 1 > max) {	/* too wide for 1-2-5: decades */
		pd = 1;
		span(h, pd, &first, &last);
		if (last - first + 1 > max)
			first = last - max + 1;	/* the tail matters most */
	}
	/* show how far the thresholds are, when they fit */
	for (t = HD_WARN; t <= HD_ERROR; t++) {
		int r;

		if (!mark || !mark[t])
			continue;
		r = row_of(mark[t], pd);
		if (r > last && r - first + 1 <= max)
			last = r;
		if (r < first && last - r + 1 <= max)
			first = r;
	}
	for (i = first; i <= last; i++) {
		rows[i - first].lo = edge(i, pd);
		rows[i - first].hi = edge(i + 1, pd);
		rows[i - first].count = 0;
	}
	rows[0].lo = first ? edge(first, pd) : 0;
	for (b = 0; b < HIST_BUCKETS; b++) {
		int r;

		if (!h[b])
			continue;
		r = bucket_row(b, pd);
		if (r < first)
			r = first;	/* cut off at the top of the tail (decades only) */
		rows[r - first].count += h[b];
	}
	return last - first + 1;
}

void histdraw_fmt_ns(char *buf, size_t len, __u64 ns)
{
	static const struct { __u64 div; const char *unit; } u[] = {
		{ 1000000000ULL, "s" }, { 1000000, "ms" }, { 1000, "us" }, { 1, "ns" },
	};
	int i;

	for (i = 0; i < 3 && ns < u[i].div; i++)
		;
	if (ns % u[i].div == 0)
		snprintf(buf, len, "%llu%s", (unsigned long long)(ns / u[i].div), u[i].unit);
	else
		snprintf(buf, len, "%.3g%s", (double)ns / (double)u[i].div, u[i].unit);
}

/* marks_of - the names of the marks that fall in [lo, hi), space separated */
static int marks_of(const struct hd_hist *hh, const struct hd_row *r, bool last_row,
		    char *buf, size_t len)
{
	int m, worst = -1;
	size_t n = 0;

	buf[0] = '\0';
	for (m = 0; m < HD_NMARKS; m++) {
		__u64 v = hh->mark[m];

		if (!v || v < r->lo || (v >= r->hi && !last_row))
			continue;
		n += snprintf(buf + n, len - n, "%s%s", n ? " " : "", mark_names[m]);
		if (n >= len)
			break;
		if (m == HD_ERROR || (m == HD_WARN && worst < 0))
			worst = m;
	}
	return worst;
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
	/* "  500us .. 1ms   count |bar| marks": 30 columns besides the bar and marks */
	bar = width - 30 - 18;
	if (bar < 10)
		bar = 10;
	snprintf(out[nl++], HD_LINE, "%17s %10s  %-*s", "range", "count", bar + 2, "distribution");
	for (i = 0; i < n; i++) {
		const struct hd_row *r = &rows[i];
		/* every row with a count shows at least one mark: the outlier is seen */
		int fill = top ? (int)((r->count * bar + top - 1) / top) : 0;
		int worst = marks_of(hh, r, i == n - 1, mk, sizeof(mk));
		const char *on = "", *off = "";

		if (color && worst >= 0) {
			on = worst == HD_ERROR ? "\033[31m" : "\033[33m";
			off = "\033[0m";
		}
		if (fill > bar)
			fill = bar;
		histdraw_fmt_ns(lo, sizeof(lo), r->lo);
		histdraw_fmt_ns(hi, sizeof(hi), r->hi);
		len = snprintf(out[nl], HD_LINE, "%7s .. %-6s %10llu |%s", lo, hi,
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
