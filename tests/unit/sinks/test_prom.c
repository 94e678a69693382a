// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_prom.c - user/sinks/prom.c: the Prometheus exposition of a model and its
 * verdicts: counters, histograms built from the log-linear kernel one,
 * status gauges, label escaping, which threads are exported, the
 * extension hook; and model_prune_dead, which keeps memory bounded.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "hist.h"
#include "sinks/prom.h"

static __u64 counters[RTSUP_C_NR];

/* add_value - one value into a metric's lifetime statistics, as the kernel does */
static void add_value(struct rtsup_metric_stats *m, __u64 v)
{
	m->count++;
	m->sum += v;
	if (!m->min || v < m->min)
		m->min = v;
	if (v > m->max)
		m->max = v;
	m->hist[hist_bucket(v)]++;
}

/* thread - a live RT thread with n cycles of exec 100 us and latency 10..10+n us */
static struct thread_model *thread(struct model *m, __u32 tid, const char *comm, int n)
{
	struct thread_model *tm = model_get(m, tid, true);
	struct rtsup_thread t = { .first_seen = 1 };
	int i;

	tm->tgid = 100;
	snprintf(tm->comm, sizeof(tm->comm), "%s", comm);
	snprintf(tm->pcomm, sizeof(tm->pcomm), "ctrl");
	tm->alive = true;
	tm->policy = 1;
	tm->prio = 80;
	tm->was_rt = true;
	tm->rule = -1;
	snprintf(tm->cpus, sizeof(tm->cpus), "0-1");
	t.cycles = n;
	t.misses = 2;
	t.vol_cs = n;
	t.unsafe[RTSUP_U_MINFLT] = 3;
	for (i = 0; i < n; i++) {
		add_value(&t.m[RTSUP_M_EXEC], 100000);
		add_value(&t.m[RTSUP_M_LATENCY], 10000 + i * 1000ULL);
	}
	/* the first snapshot, as the collector takes it */
	model_set(tm, &t, 0);
	status_reset(&tm->st);
	return tm;
}

struct fixture {
	struct model m;
	struct supervisor s;
	struct textbuf b;
	struct prom_in in;
};

static int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof(*f));

	if (!f)
		return -1;
	status_reset(&f->s.self);
	f->s.gen = 1;
	f->in.m = &f->m;
	f->in.s = &f->s;
	f->in.counters = counters;
	f->in.map_capacity = 4096;
	memset(counters, 0, sizeof(counters));
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	model_free(&f->m);
	textbuf_free(&f->b);
	free(f);
	return 0;
}

/* value_of - the value of the sample line that starts with 'series', or -1 */
static double value_of(const char *text, const char *series)
{
	const char *p = text;
	size_t n = strlen(series);

	while ((p = strstr(p, series))) {
		if ((p == text || p[-1] == '\n') && p[n] == ' ')
			return strtod(p + n + 1, NULL);
		p += n;
	}
	return -1;
}

static void test_prom_counters_and_info(void **state)
{
	struct fixture *f = *state;

	thread(&f->m, 101, "lg-0", 1000);
	counters[RTSUP_C_MAP_FULL] = 7;
	f->in.map_entries = 3;
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_cycles_total{comm=\"lg-0\",tid=\"101\","
				  "tgid=\"100\",process=\"ctrl\"}"), 1000);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_deadline_misses_total{comm=\"lg-0\","
				  "tid=\"101\",tgid=\"100\",process=\"ctrl\"}"), 2);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_unsafe_events_total{comm=\"lg-0\","
				  "tid=\"101\",tgid=\"100\",process=\"ctrl\",reason=\"minor_fault\"}"), 3);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_context_switches_total{comm=\"lg-0\","
				  "tid=\"101\",tgid=\"100\",process=\"ctrl\",kind=\"voluntary\"}"), 1000);
	assert_int_equal(value_of(f->b.p, "rtsup_untracked_threads_total"), 7);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_map_entries"), 3);
	assert_int_equal(value_of(f->b.p, "rtsup_thread_map_capacity"), 4096);
	assert_int_equal(value_of(f->b.p, "rtsup_threads{state=\"alive\"}"), 1);
	assert_non_null(strstr(f->b.p, "rtsup_thread_info{comm=\"lg-0\",tid=\"101\",tgid=\"100\","
				     "process=\"ctrl\",policy=\"SCHED_FIFO\",priority=\"80\","
				     "cpus=\"0-1\",rule=\"\"} 1\n"));
	/* every counter family is typed counter and named _total */
	assert_non_null(strstr(f->b.p, "# TYPE rtsup_thread_cycles_total counter\n"));
	assert_non_null(strstr(f->b.p, "# TYPE rtsup_lost_events_total counter\n"));
}

/*
 * A kernel bucket wraps (0xFFFFFFF0 -> 0x10, 0x20 more values): the
 * exposed counts keep growing, as a Prometheus histogram must.
 */
static void test_prom_histogram_monotonic_wrap(void **state)
{
	struct fixture *f = *state;
	const char *lab = "{comm=\"lg-0\",tid=\"101\",tgid=\"100\",process=\"ctrl\"";
	struct thread_model *tm = thread(&f->m, 101, "lg-0", 10);
	struct rtsup_thread t = tm->cur;
	struct rtsup_metric_stats *m = &t.m[RTSUP_M_EXEC];
	char series[256];

	/* 100 us exec: 0xFFFFFFF0 values so far */
	m->hist[hist_bucket(100000)] = 0xFFFFFFF0;
	m->count = 0xFFFFFFF0;
	model_set(tm, &t, 1);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	snprintf(series, sizeof(series), "rtsup_thread_exec_seconds_bucket%s,le=\"0.00025\"}",
		 lab);
	assert_true(value_of(f->b.p, series) == (double)0xFFFFFFF0);

	m->hist[hist_bucket(100000)] = 0x10;
	m->count += 0x20;
	model_set(tm, &t, 0);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_true(value_of(f->b.p, series) == (double)0x100000010ULL);
	snprintf(series, sizeof(series), "rtsup_thread_exec_seconds_bucket%s,le=\"+Inf\"}", lab);
	assert_true(value_of(f->b.p, series) == (double)0x100000010ULL);
}

/* latency 10..1009 us: the buckets count what is surely below their bound */
static void test_prom_histogram_cumulative(void **state)
{
	struct fixture *f = *state;
	const char *lab = "{comm=\"lg-0\",tid=\"101\",tgid=\"100\",process=\"ctrl\"";
	char series[256];
	double last = -1, v;
	const char *p;

	thread(&f->m, 101, "lg-0", 1000);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	/* cumulative, never decreasing, +Inf is the count */
	p = f->b.p;
	while ((p = strstr(p, "rtsup_thread_latency_seconds_bucket{"))) {
		v = strtod(strchr(p, '}') + 2, NULL);
		assert_true(v >= last);
		last = v;
		p++;
	}
	assert_int_equal(last, 1000);
	snprintf(series, sizeof(series), "rtsup_thread_latency_seconds_count%s}", lab);
	assert_int_equal(value_of(f->b.p, series), 1000);
	/* below 10 us: nothing; up to 100 us: within 1/8 below the truth (91) */
	snprintf(series, sizeof(series), "rtsup_thread_latency_seconds_bucket%s,le=\"1e-05\"}",
		 lab);
	assert_int_equal(value_of(f->b.p, series), 0);
	snprintf(series, sizeof(series), "rtsup_thread_latency_seconds_bucket%s,le=\"0.0001\"}",
		 lab);
	v = value_of(f->b.p, series);
	assert_true(v <= 91 && v >= 91 - 91 / 8);
	/* 1 ms: all but those in the bucket straddling it */
	snprintf(series, sizeof(series), "rtsup_thread_latency_seconds_bucket%s,le=\"0.001\"}",
		 lab);
	v = value_of(f->b.p, series);
	assert_true(v <= 991 && v >= 991 - 991 / 8);
	/* exec is always 100 us = 100000 ns: exactly in le 0.00025 and above */
	snprintf(series, sizeof(series), "rtsup_thread_exec_seconds_bucket%s,le=\"0.00025\"}",
		 lab);
	assert_int_equal(value_of(f->b.p, series), 1000);
	snprintf(series, sizeof(series), "rtsup_thread_exec_seconds_sum%s}", lab);
	assert_true(value_of(f->b.p, series) > 0.0999 && value_of(f->b.p, series) < 0.1001);
}

static void test_prom_status_gauges(void **state)
{
	struct fixture *f = *state;
	struct thread_model *a, *b;

	a = thread(&f->m, 101, "lg-0", 10);
	b = thread(&f->m, 102, "lg-1", 10);
	status_add(&a->st, LEVEL_WARN, "overrun");
	a->worst = LEVEL_ERROR;
	b->alive = false;
	b->reported_exit = true;
	status_add(&b->st, LEVEL_STALE, "gone");
	b->worst = LEVEL_STALE;
	status_add(&f->s.self, LEVEL_ERROR, "lost events");
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_int_equal(value_of(f->b.p, "rtsup_component_status{component=\"rtsup-trace\"}"), 2);
	assert_int_equal(value_of(f->b.p, "rtsup_component_status{component=\"lg-0[101]\","
				  "comm=\"lg-0\",tid=\"101\",tgid=\"100\",process=\"ctrl\"}"), 1);
	assert_int_equal(value_of(f->b.p, "rtsup_component_worst_status{component=\"lg-0[101]\","
				  "comm=\"lg-0\",tid=\"101\",tgid=\"100\",process=\"ctrl\"}"), 2);
	/* STALE is 3, although the enum orders it second */
	assert_int_equal(value_of(f->b.p, "rtsup_component_status{component=\"lg-1[102]\","
				  "comm=\"lg-1\",tid=\"102\",tgid=\"100\",process=\"ctrl\"}"), 3);
	assert_int_equal(prom_level_value(LEVEL_OK), 0);
	assert_int_equal(prom_level_value(LEVEL_WARN), 1);
	assert_int_equal(prom_level_value(LEVEL_ERROR), 2);
	assert_int_equal(prom_level_value(LEVEL_STALE), 3);
}

/* dead threads: only judged ones, until a restart replaces them */
static void test_prom_exported_threads(void **state)
{
	struct fixture *f = *state;
	struct thread_model *other, *rt, *old;

	other = thread(&f->m, 201, "worker", 5);
	other->was_rt = false;
	other->policy = 0;
	rt = thread(&f->m, 202, "rt", 5);
	old = thread(&f->m, 203, "restarted", 5);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_non_null(strstr(f->b.p, "comm=\"worker\""));
	/* dead: the non-RT thread goes; the RT one stays (STALE) until replaced */
	other->alive = rt->alive = old->alive = false;
	other->reported_exit = rt->reported_exit = old->reported_exit = true;
	old->replaced = true;
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_null(strstr(f->b.p, "comm=\"worker\""));
	assert_non_null(strstr(f->b.p, "comm=\"rt\""));
	assert_null(strstr(f->b.p, "comm=\"restarted\""));
	assert_int_equal(value_of(f->b.p, "rtsup_threads{state=\"exited\"}"), 3);
}

static void test_prom_label_escaping(void **state)
{
	struct fixture *f = *state;

	thread(&f->m, 101, "a\"b\\c", 1);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_non_null(strstr(f->b.p, "comm=\"a\\\"b\\\\c\""));
}

/* a newline in a name is escaped too, and the process label comes after tgid */
static void test_prom_label_newline(void **state)
{
	struct fixture *f = *state;
	struct thread_model *tm = thread(&f->m, 101, "x\ny", 1);

	snprintf(tm->pcomm, sizeof(tm->pcomm), "p\\q");
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_true(value_of(f->b.p, "rtsup_thread_cycles_total{comm=\"x\\ny\",tid=\"101\","
				  "tgid=\"100\",process=\"p\\\\q\"}") == 1);
	assert_true(value_of(f->b.p, "rtsup_component_status{component=\"x\\ny[101]\","
				  "comm=\"x\\ny\",tid=\"101\",tgid=\"100\",process=\"p\\\\q\"}") == 0);
}

/*
 * The interval maximum is written as the exact decimal of its ns: it reads
 * back as the same double as ns / 1e9, with no 17-digit tail.
 */
static void test_prom_interval_max_exact(void **state)
{
	static const __u64 ns[] = { 1234567, 2000000000, 1000000001, 10000, 999999999 };
	static const char *const text[] = { " 0.001234567\n", " 2\n", " 1.000000001\n",
					    " 0.00001\n", " 0.999999999\n" };
	struct fixture *f = *state;
	char series[160];
	unsigned i;

	for (i = 0; i < sizeof(ns) / sizeof(ns[0]); i++) {
		struct thread_model *tm = thread(&f->m, 200 + i, "lg", 3);
		const char *p;

		tm->win.m[RTSUP_M_LATENCY].max = ns[i];
		assert_int_equal(prom_render(&f->in, &f->b), 0);
		snprintf(series, sizeof(series), "rtsup_thread_interval_max_seconds{comm=\"lg\","
			 "tid=\"%u\",tgid=\"100\",process=\"ctrl\",metric=\"latency\"}", 200 + i);
		assert_true(value_of(f->b.p, series) == (double)ns[i] / 1e9);
		p = strstr(f->b.p, series);
		assert_non_null(p);
		assert_int_equal(strncmp(p + strlen(series), text[i], strlen(text[i])), 0);
	}
}

static void extra(struct textbuf *b, void *ctx)
{
	(*(int *)ctx)++;
	prom_family(b, "rtsup_can_frames_total", "counter", "Frames.");
	prom_sample(b, "rtsup_can_frames_total", 5,
		    (const char *const[]){ "interface", "can0", "id", "0x181", NULL });
}

/* other modules (CAN) append their families through the hook */
static void test_prom_extra_hook(void **state)
{
	struct fixture *f = *state;
	int calls = 0;

	f->in.extra = extra;
	f->in.extra_ctx = &calls;
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_int_equal(calls, 1);
	assert_int_equal(value_of(f->b.p, "rtsup_can_frames_total{interface=\"can0\",id=\"0x181\"}"),
			 5);
	assert_int_equal(f->b.len, strlen(f->b.p));
}

/* each family has one HELP and one TYPE, before its samples; lines are well formed */
static void test_prom_format(void **state)
{
	struct fixture *f = *state;
	char *text, *line, *save, fam[128] = "";
	int types = 0;

	thread(&f->m, 101, "lg-0", 50);
	thread(&f->m, 102, "lg-1", 0);
	assert_int_equal(prom_render(&f->in, &f->b), 0);
	assert_true(f->b.len > 0 && f->b.p[f->b.len - 1] == '\n');
	text = strdup(f->b.p);
	for (line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
		if (!strncmp(line, "# TYPE ", 7)) {
			char name[128];

			assert_int_equal(sscanf(line + 7, "%127s", name), 1);
			/* a family is declared once */
			assert_true(strcmp(name, fam));
			snprintf(fam, sizeof(fam), "%s", name);
			types++;
			continue;
		}
		if (line[0] == '#')
			continue;
		/* a sample of the current family: name, optional labels, a number */
		assert_int_equal(strncmp(line, fam, strlen(fam)), 0);
		assert_non_null(strrchr(line, ' '));
		assert_true(strrchr(line, ' ')[1] != '\0');
	}
	free(text);
	assert_true(types >= 20);
}

/* weeks of thread churn: only the newest MODEL_KEEP_DEAD exited threads stay */
static void test_model_prune_dead(void **state)
{
	struct fixture *f = *state;
	__u32 tid;
	int i, alive = 0;

	for (tid = 1; tid <= 50; tid++) {
		struct thread_model *tm = thread(&f->m, tid, "t", 0);

		if (tid % 10 == 0)
			continue;	/* stays alive */
		tm->alive = false;
		tm->reported_exit = true;
		model_prune_dead(&f->m, 100);	/* one death per "interval" */
	}
	assert_int_equal(f->m.n, 50);
	model_prune_dead(&f->m, 20);
	assert_int_equal(f->m.n, 25);
	assert_int_equal(f->m.forgotten, 25);
	for (i = 0; i < f->m.n; i++) {
		alive += f->m.t[i]->alive;
		/* the oldest dead went first: the survivors died last */
		if (!f->m.t[i]->alive)
			assert_true(f->m.t[i]->tid > 50 - 25);
		if (i)
			assert_true(f->m.t[i]->tid > f->m.t[i - 1]->tid);
	}
	assert_int_equal(alive, 5);
	/* threads not yet reported are never dropped */
	model_get(&f->m, 60, true)->alive = false;
	model_prune_dead(&f->m, 0);
	assert_int_equal(f->m.n, 6);
	assert_non_null(model_get(&f->m, 60, false));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_prom_counters_and_info, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_histogram_cumulative, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_histogram_monotonic_wrap, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_status_gauges, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_exported_threads, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_label_escaping, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_label_newline, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_interval_max_exact, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_extra_hook, setup, teardown),
		cmocka_unit_test_setup_teardown(test_prom_format, setup, teardown),
		cmocka_unit_test_setup_teardown(test_model_prune_dead, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
