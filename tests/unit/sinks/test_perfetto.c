// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_perfetto.c - user/sinks/perfetto.c: the Chrome JSON trace parses back
 * with the thread/process names, cycle slices and instant events written,
 * one event per line, strings escaped, errors reported at close.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <dirent.h>
#include <unistd.h>
#include <cmocka.h>
#include <jansson.h>

#include "sinks/perfetto.h"

#define ERRLEN	512

struct fx {
	char dir[256];
	char path[300];
};

static int fx_setup(void **state)
{
	const char *tmp = getenv("TMPDIR");
	struct fx *f = calloc(1, sizeof(*f));

	if (!f)
		return -1;
	snprintf(f->dir, sizeof(f->dir), "%s/rtsup-pf-XXXXXX", tmp && *tmp ? tmp : "/tmp");
	if (!mkdtemp(f->dir)) {
		free(f);
		return -1;
	}
	snprintf(f->path, sizeof(f->path), "%s/trace.json", f->dir);
	*state = f;
	return 0;
}

static int fx_teardown(void **state)
{
	struct fx *f = *state;
	struct dirent *d;
	char p[600];
	DIR *dir;

	dir = opendir(f->dir);
	if (dir) {
		while ((d = readdir(dir)))
			if (strcmp(d->d_name, ".") && strcmp(d->d_name, "..")) {
				snprintf(p, sizeof(p), "%s/%s", f->dir, d->d_name);
				unlink(p);
			}
		closedir(dir);
	}
	rmdir(f->dir);
	free(f);
	return 0;
}

/* load - parse the whole file; checks the envelope, returns traceEvents' owner */
static json_t *load(const char *path, json_t **events)
{
	json_error_t jerr;
	json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);

	if (!root)
		fail_msg("%s: %s (line %d)", path, jerr.text, jerr.line);
	assert_true(json_is_object(root));
	assert_string_equal(json_string_value(json_object_get(root, "displayTimeUnit")), "ns");
	*events = json_object_get(root, "traceEvents");
	assert_true(json_is_array(*events));
	return root;
}

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	char *b;
	long n;

	assert_non_null(f);
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	rewind(f);
	b = malloc(n + 1);
	assert_non_null(b);
	assert_int_equal(fread(b, 1, n, f), (size_t)n);
	b[n] = '\0';
	fclose(f);
	return b;
}

static const char *sget(json_t *o, const char *k)
{
	json_t *v = json_object_get(o, k);

	return json_is_string(v) ? json_string_value(v) : NULL;
}

static json_int_t iget(json_t *o, const char *k)
{
	json_t *v = json_object_get(o, k);

	assert_true(json_is_integer(v));
	return json_integer_value(v);
}

static void assert_num(json_t *o, const char *k, double want)
{
	json_t *v = json_object_get(o, k);

	if (!json_is_number(v))
		fail_msg("%s is not a number", k);
	if (fabs(json_number_value(v) - want) > 1e-9 * fmax(1, fabs(want)))
		fail_msg("%s = %.6f, want %.6f", k, json_number_value(v), want);
}

/* find - the n-th event with this phase and name (NULL name: any) */
static json_t *find(json_t *ev, const char *ph, const char *name, int nth)
{
	json_t *e;
	size_t i;

	json_array_foreach(ev, i, e) {
		if (strcmp(sget(e, "ph"), ph) || (name && strcmp(sget(e, "name"), name)))
			continue;
		if (nth-- == 0)
			return e;
	}
	return NULL;
}

static int count(json_t *ev, const char *ph, const char *name)
{
	int n = 0;

	while (find(ev, ph, name, n))
		n++;
	return n;
}

static struct rtsup_event mkev(__u32 type, __u64 ts, __u64 arg, __u64 arg2)
{
	struct rtsup_event e = { .ts = ts, .type = type, .tid = 101, .tgid = 100, .cpu = 3,
				 .arg = arg, .arg2 = arg2 };

	strcpy(e.comm, "ctl");
	return e;
}

/* threads, cycles and every kind of event parse back as written */
static void test_perfetto_structure(void **state)
{
	struct fx *f = *state;
	struct perfetto *p;
	struct rtsup_cycle c = { 0 };
	struct rtsup_event e;
	json_t *root, *ev, *x, *a;
	char err[ERRLEN], *text;

	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	perfetto_thread(p, 100, 101, "ctl", "app");
	perfetto_thread(p, 100, 102, "io", "app");
	perfetto_thread(p, 200, 200, "solo", "solo");
	perfetto_thread(p, 100, 101, "ctl2", "app");	/* renamed: again, no process */

	c.start = 1234567890123ULL;	/* ns */
	c.exec = 456789;
	c.cpu = 400000;
	c.period = 1000000;
	c.latency = 12345;
	c.nominal = 1000000;
	c.preempt = 1;
	c.blocks = 2;
	c.migrations = 3;
	c.syscalls = 4;
	c.unsafe_sys = 5;
	c.minflt = 6;
	c.majflt = 7;
	c.flags = RTSUP_CF_HAS_PERIOD | RTSUP_CF_HAS_LATENCY | RTSUP_CF_MISS;
	perfetto_cycle(p, 100, 101, &c);
	c.start = 5;		/* below a microsecond */
	c.exec = 1000;
	c.flags = RTSUP_CF_OVERRUN;
	c.nominal = 0;
	perfetto_cycle(p, 100, 102, &c);
	c.start = 2000000000000ULL;
	c.exec = 0;
	c.flags = 0;
	perfetto_cycle(p, 200, 200, &c);

	e = mkev(RTSUP_EV_MISS, 1234568000000ULL, 1500, 0);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_UNSAFE, 1234568000001ULL, RTSUP_U_SYSCALL, 9);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_UNSAFE, 1234568000002ULL, RTSUP_U_MINFLT, 3);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_UNSAFE, 1234568000003ULL, RTSUP_U_MAJFLT, 1);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_UNSAFE, 1234568000004ULL, RTSUP_U_BLOCK, 0);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_UNSAFE, 1234568000005ULL, RTSUP_U_MIGRATE, 0);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_EXIT, 1234568000006ULL, 1, 0);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_SIGNAL, 1234568000007ULL, 11, 0);
	perfetto_event(p, &e);
	e = mkev(RTSUP_EV_NEW, 1234568000008ULL, 0, 0);
	perfetto_event(p, &e);
	e = mkev(77, 1234568000009ULL, 1, 2);	/* unknown: still written */
	perfetto_event(p, &e);
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);

	root = load(f->path, &ev);
	assert_int_equal(json_array_size(ev), 4 + 2 + 3 + 10);

	/* metadata: a process name once per tgid, every thread name */
	assert_int_equal(count(ev, "M", "process_name"), 2);
	assert_int_equal(count(ev, "M", "thread_name"), 4);
	x = find(ev, "M", "process_name", 0);
	assert_int_equal(iget(x, "pid"), 100);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), "app");
	x = find(ev, "M", "process_name", 1);
	assert_int_equal(iget(x, "pid"), 200);
	x = find(ev, "M", "thread_name", 1);
	assert_int_equal(iget(x, "pid"), 100);
	assert_int_equal(iget(x, "tid"), 102);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), "io");
	x = find(ev, "M", "thread_name", 3);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), "ctl2");

	/* cycles: complete events in microseconds */
	assert_int_equal(count(ev, "X", "cycle"), 3);
	x = find(ev, "X", "cycle", 0);
	assert_string_equal(sget(x, "cat"), "cycle");
	assert_int_equal(iget(x, "pid"), 100);
	assert_int_equal(iget(x, "tid"), 101);
	assert_num(x, "ts", 1234567890.123);
	assert_num(x, "dur", 456.789);
	a = json_object_get(x, "args");
	assert_num(a, "period_us", 1000);
	assert_num(a, "exec_us", 456.789);
	assert_num(a, "cpu_us", 400);
	assert_num(a, "latency_us", 12.345);
	assert_num(a, "nominal_us", 1000);
	assert_int_equal(iget(a, "preempt"), 1);
	assert_int_equal(iget(a, "blocks"), 2);
	assert_int_equal(iget(a, "migrations"), 3);
	assert_int_equal(iget(a, "syscalls"), 4);
	assert_int_equal(iget(a, "unsafe_syscalls"), 5);
	assert_int_equal(iget(a, "minflt"), 6);
	assert_int_equal(iget(a, "majflt"), 7);
	assert_true(json_is_true(json_object_get(a, "miss")));
	assert_true(json_is_false(json_object_get(a, "overrun")));
	x = find(ev, "X", "cycle", 1);
	assert_int_equal(iget(x, "tid"), 102);
	assert_num(x, "ts", 0.005);
	assert_num(x, "dur", 1);
	a = json_object_get(x, "args");
	assert_null(json_object_get(a, "period_us"));	/* unknown: left out */
	assert_null(json_object_get(a, "latency_us"));
	assert_null(json_object_get(a, "nominal_us"));
	assert_true(json_is_true(json_object_get(a, "overrun")));
	assert_true(json_is_false(json_object_get(a, "miss")));
	x = find(ev, "X", "cycle", 2);
	assert_int_equal(iget(x, "pid"), 200);
	assert_num(x, "dur", 0);

	/* ts and dur exactly ns / 1000 with three decimals */
	text = slurp(f->path);
	assert_non_null(strstr(text, "\"ts\":1234567890.123,\"dur\":456.789,"));
	assert_non_null(strstr(text, "\"ts\":0.005,\"dur\":1.000,"));
	assert_non_null(strstr(text, "\"ts\":2000000000.000,\"dur\":0.000,"));
	assert_non_null(strstr(text, "\"ts\":1234568000.009,"));
	free(text);

	/* instants on the thread's track */
	assert_int_equal(count(ev, "i", NULL), 10);
	x = find(ev, "i", "deadline miss", 0);
	assert_non_null(x);
	assert_string_equal(sget(x, "s"), "t");
	assert_int_equal(iget(x, "pid"), 100);
	assert_int_equal(iget(x, "tid"), 101);
	assert_num(x, "ts", 1234568000.000);
	assert_num(json_object_get(x, "args"), "late_us", 1.5);
	/* annotated with its cause: none measured in this synthetic event */
	assert_string_equal(sget(json_object_get(x, "args"), "kind"), "none");
	assert_string_equal(sget(json_object_get(x, "args"), "cause"), "no cause measured");
	assert_int_equal(iget(json_object_get(x, "args"), "cpu"), 3);
	x = find(ev, "i", "unsafe: syscall", 0);
	assert_non_null(x);
	assert_num(x, "ts", 1234568000.001);
	assert_int_equal(iget(json_object_get(x, "args"), "nr"), 9);
	x = find(ev, "i", "unsafe: minor_fault", 0);
	assert_non_null(x);
	assert_int_equal(iget(json_object_get(x, "args"), "count"), 3);
	assert_non_null(find(ev, "i", "unsafe: major_fault", 0));
	assert_non_null(find(ev, "i", "unsafe: block", 0));
	assert_non_null(find(ev, "i", "unsafe: migration", 0));
	x = find(ev, "i", "exit", 0);
	assert_non_null(x);
	assert_true(json_is_true(json_object_get(json_object_get(x, "args"), "mid_cycle")));
	x = find(ev, "i", "signal", 0);
	assert_non_null(x);
	assert_int_equal(iget(json_object_get(x, "args"), "signo"), 11);
	x = find(ev, "i", "new thread", 0);
	assert_non_null(x);
	assert_string_equal(sget(json_object_get(x, "args"), "comm"), "ctl");
	assert_non_null(find(ev, "i", "event 77", 0));
	json_decref(root);
}

/* one event per line, a comma ending every event line but the last */
static void test_perfetto_lines(void **state)
{
	struct fx *f = *state;
	struct perfetto *p;
	struct rtsup_cycle c = { .start = 1000, .exec = 10 };
	char err[ERRLEN], *text, *line, *save = NULL;
	int i, n = 0, events = 0;

	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	perfetto_thread(p, 1, 2, "a", "b");
	for (i = 0; i < 5; i++)
		perfetto_cycle(p, 1, 2, &c);
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);
	text = slurp(f->path);
	for (line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save), n++) {
		size_t len = strlen(line);
		json_error_t jerr;
		json_t *o;

		if (n == 0) {
			assert_string_equal(line, "{\"displayTimeUnit\":\"ns\",\"traceEvents\":[");
			continue;
		}
		if (!strcmp(line, "]}"))
			break;
		events++;
		if (events < 7) {
			assert_int_equal(line[len - 1], ',');
			len--;
		} else {
			assert_int_equal(line[len - 1], '}');
		}
		o = json_loadb(line, len, 0, &jerr);
		assert_non_null(o);
		assert_true(json_is_object(o));
		json_decref(o);
	}
	assert_int_equal(events, 7);	/* process, thread, 5 cycles */
	assert_non_null(line);
	assert_null(strtok_r(NULL, "\n", &save));
	free(text);
}

/* names with quotes, backslashes, control characters and UTF-8 */
static void test_perfetto_escape(void **state)
{
	static const char comm[] = "a\"b\\c\n\t\x01\x1f/\xc3\xa9</x>";
	static const char pcomm[] = "p\"\r\x7f";
	struct fx *f = *state;
	struct perfetto *p;
	struct rtsup_event e = mkev(RTSUP_EV_NEW, 1, 0, 0);
	json_t *root, *ev, *x;
	char err[ERRLEN];

	memcpy(e.comm, "0123456789\"bcdef", RTSUP_COMM_LEN);	/* no NUL */
	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	perfetto_thread(p, 7, 8, comm, pcomm);
	perfetto_thread(p, 9, 9, "bad\xff\xc3(utf8", "\xe0\x80\x80");
	perfetto_event(p, &e);
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);

	root = load(f->path, &ev);
	x = find(ev, "M", "thread_name", 0);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), comm);
	x = find(ev, "M", "process_name", 0);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), pcomm);
	/* invalid UTF-8 becomes U+FFFD, the event is kept */
	x = find(ev, "M", "thread_name", 1);
	assert_string_equal(sget(json_object_get(x, "args"), "name"),
			    "bad\xef\xbf\xbd\xef\xbf\xbd(utf8");
	x = find(ev, "M", "process_name", 1);
	assert_string_equal(sget(json_object_get(x, "args"), "name"),
			    "\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd");
	/* a comm filling its array without a NUL stops at the array */
	x = find(ev, "i", "new thread", 0);
	assert_string_equal(sget(json_object_get(x, "args"), "comm"), "0123456789\"bcdef");
	json_decref(root);
}

/* open and close: valid JSON with no events */
static void test_perfetto_empty(void **state)
{
	struct fx *f = *state;
	struct perfetto *p;
	json_t *root, *ev;
	char err[ERRLEN];

	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);
	root = load(f->path, &ev);
	assert_int_equal(json_array_size(ev), 0);
	json_decref(root);
}

/* many cycles stream through and parse back */
static void test_perfetto_many(void **state)
{
	enum { N = 50000 };
	struct fx *f = *state;
	struct perfetto *p;
	struct rtsup_cycle c = { .start = 1000000, .exec = 250000, .period = 1000000,
				 .flags = RTSUP_CF_HAS_PERIOD };
	json_t *root, *ev, *x;
	char err[ERRLEN];
	int i;

	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	for (i = 0; i < N; i++) {
		perfetto_thread(p, 10 + i % 4, 100 + i % 16, "rt", "proc");
		c.start += 1000000;
		perfetto_cycle(p, 10 + i % 4, 100 + i % 16, &c);
	}
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);
	root = load(f->path, &ev);
	assert_int_equal(count(ev, "M", "process_name"), 4);
	assert_int_equal(json_array_size(ev), 4 + 2 * N);
	x = json_array_get(ev, json_array_size(ev) - 1);
	assert_num(x, "ts", (1000000 + (double)N * 1000000) / 1000);
	json_decref(root);
}

static void test_perfetto_open_fails(void **state)
{
	struct fx *f = *state;
	struct perfetto *p = (void *)1;
	char err[ERRLEN], path[400];

	snprintf(path, sizeof(path), "%s/no/such/trace.json", f->dir);
	assert_int_equal(perfetto_open(&p, path, err, sizeof(err)), -1);
	assert_null(p);
	assert_non_null(strstr(err, path));
	assert_non_null(strstr(err, "No such file or directory"));
	assert_null(strchr(err, '\n'));
}

/* a full device: the error comes out of perfetto_close, once */
static void test_perfetto_full_device(void **state)
{
	struct rtsup_cycle c = { .start = 1, .exec = 2 };
	struct perfetto *p;
	char err[ERRLEN];
	int i;

	if (access("/dev/full", W_OK))
		skip();
	assert_int_equal(perfetto_open(&p, "/dev/full", err, sizeof(err)), 0);
	for (i = 0; i < 20000; i++) {
		perfetto_thread(p, 1, 2, "x", "y");
		perfetto_cycle(p, 1, 2, &c);
	}
	assert_int_equal(perfetto_close(p, err, sizeof(err)), -1);
	assert_non_null(strstr(err, "/dev/full"));
	assert_non_null(strstr(err, "No space left on device"));
	assert_null(strchr(err, '\n'));
}

/* a NULL writer (no --perfetto) is ignored */
static void test_perfetto_null(void **state)
{
	struct rtsup_cycle c = { 0 };
	struct rtsup_event e = mkev(RTSUP_EV_MISS, 1, 1, 0);

	perfetto_thread(NULL, 1, 1, "a", "b");
	perfetto_cycle(NULL, 1, 1, &c);
	perfetto_event(NULL, &e);
	assert_int_equal(perfetto_close(NULL, NULL, 0), 0);
}

/*
 * a late cycle explained where it happened: its longest wait on its CPU's
 * track, named after its holder; its longest block's wakeup a flow from a
 * slice on the waker's track to the woken thread; its migration on the
 * migration event. Twice: the CPU track and the waker are named once.
 */
static void test_perfetto_cause_slices_and_flow(void **state)
{
	struct fx *f = *state;
	struct perfetto *p;
	struct rtsup_event e;
	char err[ERRLEN];
	json_t *root, *ev, *x, *a;
	int k;

	assert_int_equal(perfetto_open(&p, f->path, err, sizeof(err)), 0);
	for (k = 0; k < 2; k++) {
		e = mkev(RTSUP_EV_MISS, 20000000 + k * 1000000ULL, 3100000, 0);
		e.cause.kind = RTSUP_CAUSE_BLOCK;
		e.cause.ns = 2000000;
		e.cause.block_max = 2000000;
		e.cause.block_op = 1;
		e.cause.waker = (struct rtsup_who){ .tid = 900, .tgid = 899, .policy = 1,
						    .prio = 10, .comm = "owner" };
		e.cause.who = e.cause.waker;
		e.cause.block_woke = 15000000 + k * 1000000ULL;
		e.cause.block_ran = 15010000 + k * 1000000ULL;
		e.cause.held_from = 12000000 + k * 1000000ULL;
		e.cause.held_to = 13000000 + k * 1000000ULL;
		e.cause.held_cpu = 2;
		e.cause.held_tid = 812;
		e.cause.top[0] = (struct rtsup_culprit){ .who = { .tid = 812, .tgid = 812,
				.policy = 1, .prio = 99, .comm = "hog" }, .ns = 1000000, .count = 1 };
		perfetto_event(p, &e);
	}
	e = mkev(RTSUP_EV_UNSAFE, 30000000, RTSUP_U_MIGRATE, RTSUP_MIG_ARG(0, 1, RTSUP_MIG_AFFINITY));
	perfetto_event(p, &e);
	assert_int_equal(perfetto_close(p, err, sizeof(err)), 0);
	root = load(f->path, &ev);

	/* the miss: its parts and culprits in its args */
	x = find(ev, "i", "deadline miss", 0);
	a = json_object_get(x, "args");
	assert_string_equal(sget(a, "kind"), "block");
	assert_num(json_object_get(a, "parts"), "block_us", 0);
	assert_string_equal(sget(json_array_get(json_object_get(a, "culprits"), 0), "who"),
			    "hog[812] FIFO/99");
	/* the CPU track, named once: process "CPUs", thread "CPU 2" */
	assert_int_equal(count(ev, "M", "process_name"), 1);
	x = find(ev, "M", "process_name", 0);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), "CPUs");
	x = find(ev, "X", "held by hog[812] FIFO/99", 1);
	assert_non_null(x);
	assert_num(x, "ts", 13000.0);
	assert_num(x, "dur", 1000.0);
	assert_int_equal(iget(json_object_get(x, "args"), "waiting_tid"), 101);
	assert_int_equal(iget(x, "tid"), iget(find(ev, "M", "thread_name", 0), "tid"));
	assert_string_equal(sget(json_object_get(find(ev, "M", "thread_name", 0), "args"), "name"),
			    "CPU 2");
	/* the waker's track named once, its slice, the flow to the woken thread */
	assert_int_equal(count(ev, "M", "thread_name"), 2);
	x = find(ev, "M", "thread_name", 1);
	assert_int_equal(iget(x, "tid"), 900);
	assert_string_equal(sget(json_object_get(x, "args"), "name"), "owner");
	x = find(ev, "X", "wakes ctl[101]", 0);
	assert_int_equal(iget(x, "tid"), 900);
	assert_num(x, "ts", 15000.0);
	x = find(ev, "s", "wakeup", 1);
	assert_int_equal(iget(x, "tid"), 900);
	assert_int_equal(iget(x, "pid"), 899);
	assert_num(x, "ts", 16000.0);
	a = find(ev, "f", "wakeup", 1);
	assert_int_equal(iget(a, "id"), iget(x, "id"));
	assert_int_equal(iget(a, "tid"), 101);
	assert_string_equal(sget(a, "bp"), "e");
	assert_num(a, "ts", 16010.0);
	assert_int_not_equal(iget(a, "id"), iget(find(ev, "f", "wakeup", 0), "id"));
	/* the migration: from, to, why */
	x = find(ev, "i", "unsafe: migration", 0);
	a = json_object_get(x, "args");
	assert_int_equal(iget(a, "from_cpu"), 0);
	assert_int_equal(iget(a, "to_cpu"), 1);
	assert_string_equal(sget(a, "why"), "affinity");
	json_decref(root);
}

#define T(fn) cmocka_unit_test_setup_teardown(fn, fx_setup, fx_teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(test_perfetto_structure),
		T(test_perfetto_cause_slices_and_flow),
		T(test_perfetto_lines),
		T(test_perfetto_escape),
		T(test_perfetto_empty),
		T(test_perfetto_many),
		T(test_perfetto_open_fails),
		T(test_perfetto_full_device),
		cmocka_unit_test(test_perfetto_null),
	};

	return cmocka_run_group_tests_name("perfetto", tests, NULL, NULL);
}
