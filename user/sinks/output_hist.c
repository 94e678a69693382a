// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* output_hist.c - the --hist sink: histograms per thread with cycles, text or JSON */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/ioctl.h>
#include "judge/checks.h"
#include "hist.h"
#include "sinks/histdraw.h"
#include "sinks/output_hist.h"

static const char *const titles[RTSUP_M_NR] = {
	[RTSUP_M_PERIOD] = "period", [RTSUP_M_EXEC] = "exec",
	[RTSUP_M_CPU] = "cpu", [RTSUP_M_LATENCY] = "latency",
};

bool hist_shown(const struct thread_model *tm)
{
	/*
	 * every thread with cycles: the table shows the same ones, and a
	 * short run may end before the thread was seen with its RT policy
	 */
	return tm->life.cycles > 0;
}

/* counts - a thread's bucket counts of metric m (lifetime or last interval) */
static const __u64 *counts(const struct thread_model *tm, int m, bool window, __u64 *buf)
{
	int lo, hi;

	memset(buf, 0, HIST_BUCKETS * sizeof(*buf));
	if (!(window ? model_win_counts : model_life_counts)(tm, m, buf, &lo, &hi))
		hist_delta(tm->cur.m[m].hist, NULL, buf);
	return buf;
}

/* view_marks - where a view's percentiles and maximum are */
static void view_marks(const struct metric_view *v, __u64 *mark)
{
	mark[HD_P50] = v->p50;
	mark[HD_P99] = v->p99;
	mark[HD_P999] = v->p999;
	mark[HD_MAX] = v->max;
}

/* hist_alloc - n histograms to draw and their counts; false, said, when out of memory */
static bool hist_alloc(int n, struct hd_hist **hs, __u64 (**bufs)[HIST_BUCKETS])
{
	*hs = calloc(n ? n : 1, sizeof(**hs));
	*bufs = calloc(n ? n : 1, sizeof(**bufs));
	if (*hs && *bufs)
		return true;
	fprintf(stderr, "rtsup-trace: --hist: out of memory\n");
	return false;
}

/*
 * marks - what the checks compare metric m with, and where its
 * percentiles are: latency against its max thresholds, exec and cpu
 * against the share of the period that warns, the period against the
 * nominal one plus the jitter thresholds
 */
static void marks(const struct supervisor *sv, const struct thread_model *tm, int m,
		  const struct metric_view *v, __u64 *mark)
{
	const struct rule *r = supervise_rule(sv, tm);
	const struct thresholds *th = &r->th;
	struct check_in in = { .life = &tm->life, .rule = r, .nominal_ns = tm->cur.cs.nominal };
	__u64 period = check_period(&in);

	memset(mark, 0, HD_NMARKS * sizeof(*mark));
	switch (m) {
	case RTSUP_M_LATENCY:
		mark[HD_WARN] = th->latency_max_warn_ns ? th->latency_max_warn_ns
							: th->latency_p99_warn_ns;
		mark[HD_ERROR] = th->latency_max_error_ns;
		break;
	case RTSUP_M_EXEC:
	case RTSUP_M_CPU:
		if (period && th->exec_warn_ratio)
			mark[HD_WARN] = (__u64)(th->exec_warn_ratio * (double)period);
		break;
	case RTSUP_M_PERIOD:
		if (period && th->jitter_warn_ns)
			mark[HD_WARN] = period + th->jitter_warn_ns;
		if (period && th->jitter_error_ns)
			mark[HD_ERROR] = period + th->jitter_error_ns;
		break;
	}
	if (v->count)
		view_marks(v, mark);
}

/* term_width - the terminal's columns; COLUMNS or 80 when not a terminal */
static int term_width(void)
{
	struct winsize ws;
	const char *e = getenv("COLUMNS");

	if (isatty(STDOUT_FILENO) && !ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) && ws.ws_col)
		return ws.ws_col;
	if (e && atoi(e) >= 40)
		return atoi(e);
	return 80;
}

/* hist_draw - the n histograms filled, on stdout; colour only on a terminal, unless told */
static void hist_draw(const struct options *o, struct hd_hist *hs, int n)
{
	if (n)
		histdraw_print(stdout, hs, n, term_width(),
			       o->color < 0 ? isatty(STDOUT_FILENO) : o->color);
}

void hist_table(const struct collector *c, const struct supervisor *sv, bool window)
{
	const struct options *o = c->o;
	struct hd_hist *hs;
	__u64 (*bufs)[HIST_BUCKETS];
	int m, i, n;

	if (!hist_alloc(c->model.n, &hs, &bufs))
		goto out;
	for (m = 0; m < RTSUP_M_NR; m++) {
		if (!(o->hist & (1u << m)))
			continue;
		for (i = 0, n = 0; i < c->model.n; i++) {
			const struct thread_model *tm = c->model.t[i];
			const struct metric_view *v = window ? &tm->win.m[m] : &tm->life.m[m];

			if (!hist_shown(tm) || (window && (tm->reported_exit || !v->count)))
				continue;
			snprintf(hs[n].title, sizeof(hs[n].title), "%s[%u] %s%s", tm->comm,
				 tm->tid, titles[m], window ? " (interval)" : "");
			hs[n].h = counts(tm, m, window, bufs[n]);
			marks(sv, tm, m, v, hs[n].mark);
			n++;
		}
		hist_draw(o, hs, n);
	}
	fflush(stdout);
out:
	free(hs);
	free(bufs);
}

/* json_buckets - {"count": N, "buckets": [[lo, hi, count], ...]} of counts h */
static json_t *json_buckets(const __u64 *h)
{
	json_t *bk = json_array();
	__u64 total = 0;
	int b;

	for (b = 0; b < HIST_BUCKETS; b++) {
		if (!h[b])
			continue;
		total += h[b];
		/* the last bucket has no upper bound: null */
		json_array_append_new(bk, json_pack("[I,o,I]", (json_int_t)hist_bucket_low(b),
			b == HIST_BUCKETS - 1 ? json_null() :
			json_integer((json_int_t)hist_bucket_high(b)), (json_int_t)h[b]));
	}
	return json_pack("{s:I,s:o}", "count", (json_int_t)total, "buckets", bk);
}

json_t *hist_json(const struct thread_model *tm, unsigned int metrics, bool window)
{
	json_t *o = json_object();
	__u64 buf[HIST_BUCKETS];
	int m;

	for (m = 0; m < RTSUP_M_NR; m++)
		if (metrics & (1u << m))
			json_object_set_new(o, metric_name(m),
					    json_buckets(counts(tm, m, window, buf)));
	return o;
}

/*
 * hist_can_table - the gaps between frames of each identifier over the
 * whole run, with their percentiles; a learned period marks nothing: the
 * CAN checks judge frames missing, not gaps
 */
void hist_can_table(const struct can_model *m, const struct options *o)
{
	struct hd_hist *hs;
	__u64 (*bufs)[HIST_BUCKETS];
	struct metric_view v;
	int i, n = 0;

	if (!hist_alloc(m->n, &hs, &bufs))
		goto out;
	for (i = 0; i < m->n; i++) {
		const struct can_entry *e = &m->e[i];

		if (!e->cur.gap.count)
			continue;
		snprintf(hs[n].title, sizeof(hs[n].title), "%s 0x%x%s %s gap",
			 can_iface_name(m, e->key.netns, e->key.ifindex),
			 e->key.can_id & RTSUP_CAN_EFF_MASK,
			 e->key.can_id & RTSUP_CAN_EFF_FLAG ? "x" : "",
			 e->key.dir == RTSUP_CAN_TX ? "tx" : "rx");
		can_gap_life(e, bufs[n]);
		hs[n].h = bufs[n];
		can_gap_view_life(e, &v);
		view_marks(&v, hs[n].mark);
		n++;
	}
	hist_draw(o, hs, n);
	fflush(stdout);
out:
	free(hs);
	free(bufs);
}

void hist_can_json(json_t *can, const struct can_model *m)
{
	json_t *ids = json_object_get(can, "ids");
	__u64 buf[HIST_BUCKETS];
	int i;

	for (i = 0; i < m->n && i < (int)json_array_size(ids); i++) {
		can_gap_life(&m->e[i], buf);
		json_object_set_new(json_array_get(ids, i), "gap_hist", json_buckets(buf));
	}
}
