// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_actions.c - user/robot/actions.c without the kernel: the JSON line a change
 * gives, and the sink's limits with real /bin/sh commands: at most
 * ACTIONS_MAX_RUNNING at once (the rest skipped and counted), once a second
 * per action and component, and a FIFO without reader is no failure of ours.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/stat.h>
#include <cmocka.h>
#include <jansson.h>

#include "robot/actions.h"

#define S 1000000000ULL

static struct level_change change(const char *comp, const struct status *st, __u32 tid,
				  __u64 mono)
{
	struct level_change c = {
		.component = comp, .from = LEVEL_OK, .to = LEVEL_WARN, .mono_ns = mono,
		.when = "2026-11-23T20:00:00.000Z", .st = st, .tid = tid, .pid = tid ? 42 : 0,
	};

	return c;
}

/* a thread's change: every key; messages escaped as JSON */
static void test_actions_json_thread(void **state)
{
	struct status st;
	struct level_change c;
	json_error_t e;
	json_t *o;
	char *line;

	status_reset(&st);
	status_check(&st, "rt_unsafe");
	status_add(&st, LEVEL_WARN, "mmap 1 \"quoted\"\n");
	c = change("ctl[7]", &st, 7, 0);
	line = actions_json(&c);
	assert_non_null(line);
	assert_null(strchr(line, '\n'));	/* one line */
	o = json_loads(line, 0, &e);
	assert_non_null(o);
	assert_string_equal(json_string_value(json_object_get(o, "type")), "level_change");
	assert_string_equal(json_string_value(json_object_get(o, "component")), "ctl[7]");
	assert_string_equal(json_string_value(json_object_get(o, "level")), "WARN");
	assert_string_equal(json_string_value(json_object_get(o, "from")), "OK");
	assert_string_equal(json_string_value(json_object_get(o, "time")),
			    "2026-11-23T20:00:00.000Z");
	assert_int_equal(json_integer_value(json_object_get(o, "tid")), 7);
	assert_int_equal(json_integer_value(json_object_get(o, "pid")), 42);
	assert_string_equal(json_string_value(json_array_get(json_object_get(o, "messages"), 0)),
			    "mmap 1 \"quoted\"\n");
	assert_string_equal(json_string_value(json_array_get(json_object_get(o, "checks"), 0)),
			    "rt_unsafe");
	json_decref(o);
	free(line);
}

/* not a thread: no tid, no pid; no messages: empty arrays */
static void test_actions_json_not_a_thread(void **state)
{
	struct status st;
	struct level_change c;
	json_t *o;
	char *line;

	status_reset(&st);
	c = change("rtsup-trace", &st, 0, 0);
	line = actions_json(&c);
	o = json_loads(line, 0, NULL);
	assert_non_null(o);
	assert_null(json_object_get(o, "tid"));
	assert_null(json_object_get(o, "pid"));
	assert_int_equal(json_array_size(json_object_get(o, "messages")), 0);
	assert_int_equal(json_array_size(json_object_get(o, "checks")), 0);
	json_decref(o);
	free(line);
}

/* wait_reaped - poll until no command runs (at most 5 s) */
static void wait_reaped(struct actions *a)
{
	int i, n, tries;

	for (tries = 0; tries < 500; tries++) {
		actions_poll(a);
		for (i = n = 0; i < ACTIONS_MAX_RUNNING; i++)
			n += a->child[i].pid != 0;
		if (!n)
			return;
		usleep(10000);
	}
	fail_msg("commands still running after 5 s");
}

/* five changes at once: four commands run, the fifth is skipped and counted */
static void test_actions_at_most_four_running(void **state)
{
	static struct supervisor s;
	struct action act;
	struct actions a;
	struct status st;
	char err[160], comp[16], spec[256], dir[] = "/tmp/test_actions.XXXXXX", path[300];
	struct timespec t0, t1;
	int i, n = 0;

	assert_non_null(mkdtemp(dir));
	memset(&s, 0, sizeof(s));
	snprintf(spec, sizeof(spec), "WARN:touch %s/$RTSUP_TID; sleep 0.3", dir);
	assert_int_equal(action_parse(spec, &act, err, sizeof(err)), 0);
	assert_int_equal(config_add_action(&s.cfg, &act), 0);
	s.gen = 1;
	actions_open(&a, &s);
	assert_non_null(s.on_change);
	status_reset(&st);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (i = 1; i <= 5; i++) {
		struct level_change c;

		snprintf(comp, sizeof(comp), "c[%d]", i);
		c = change(comp, &st, i, 10 * S);
		s.on_change(s.on_change_ctx, &c);
	}
	clock_gettime(CLOCK_MONOTONIC, &t1);
	/* spawning did not wait for the commands (0.3 s each) */
	assert_true((t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec) < 0.25e9);
	assert_int_equal(a.runs, ACTIONS_MAX_RUNNING);
	assert_int_equal(a.skipped_busy, 1);
	wait_reaped(&a);
	for (i = 1; i <= 5; i++) {
		struct stat sb;

		snprintf(path, sizeof(path), "%s/%d", dir, i);
		n += !stat(path, &sb);
		unlink(path);
	}
	assert_int_equal(n, ACTIONS_MAX_RUNNING);
	rmdir(dir);
	actions_close(&a);
	assert_null(s.on_change);
	config_free(&s.cfg);
}

/* the same action for the same component within a second: skipped and counted */
static void test_actions_rate_limited(void **state)
{
	static struct supervisor s;
	struct action act;
	struct actions a;
	struct status st;
	struct level_change c;
	char err[160];

	memset(&s, 0, sizeof(s));
	assert_int_equal(action_parse("WARN:true", &act, err, sizeof(err)), 0);
	assert_int_equal(config_add_action(&s.cfg, &act), 0);
	s.gen = 1;
	actions_open(&a, &s);
	status_reset(&st);
	c = change("c[1]", &st, 1, 10 * S);
	s.on_change(s.on_change_ctx, &c);
	c.mono_ns = 10 * S + S / 2;
	s.on_change(s.on_change_ctx, &c);
	assert_int_equal(a.runs, 1);
	assert_int_equal(a.skipped_rate, 1);
	c.mono_ns = 11 * S;
	s.on_change(s.on_change_ctx, &c);
	assert_int_equal(a.runs, 2);
	/* leaving WARN does not match "WARN:" */
	c.from = LEVEL_WARN;
	c.to = LEVEL_OK;
	c.mono_ns = 20 * S;
	s.on_change(s.on_change_ctx, &c);
	assert_int_equal(a.runs, 2);
	wait_reaped(&a);
	actions_close(&a);
	config_free(&s.cfg);
}

/* a FIFO without reader: not written, not counted, the caller goes on */
static void test_actions_fifo_without_reader(void **state)
{
	static struct supervisor s;
	struct action act;
	struct actions a;
	struct status st;
	struct level_change c;
	char err[160], dir[] = "/tmp/test_actions.XXXXXX", spec[300];

	assert_non_null(mkdtemp(dir));
	snprintf(spec, sizeof(spec), "WARN:fifo=%s/f", dir);
	memset(&s, 0, sizeof(s));
	assert_int_equal(action_parse(spec, &act, err, sizeof(err)), 0);
	assert_int_equal(config_add_action(&s.cfg, &act), 0);
	actions_open(&a, &s);
	snprintf(spec, sizeof(spec), "%s/f", dir);
	assert_int_equal(mkfifo(spec, 0600), 0);
	status_reset(&st);
	c = change("c[1]", &st, 1, 10 * S);
	s.on_change(s.on_change_ctx, &c);	/* must not block */
	assert_int_equal(a.runs, 0);
	unlink(spec);
	rmdir(dir);
	actions_close(&a);
	config_free(&s.cfg);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_actions_json_thread),
		cmocka_unit_test(test_actions_json_not_a_thread),
		cmocka_unit_test(test_actions_at_most_four_running),
		cmocka_unit_test(test_actions_rate_limited),
		cmocka_unit_test(test_actions_fifo_without_reader),
	};

	return cmocka_run_group_tests_name("actions", tests, NULL, NULL);
}
