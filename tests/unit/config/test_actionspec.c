// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_actionspec.c - user/config/actionspec.c: the --on-level SPEC parser (every
 * kind, every error), its printed form reading back, which changes fire an
 * action, and the rate limit (once a second per action and component).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <signal.h>
#include <string.h>
#include <cmocka.h>

#include "config/actionspec.h"

#define S 1000000000ULL

static struct action parse_ok(const char *spec)
{
	struct action a;
	char err[160] = "";

	if (action_parse(spec, &a, err, sizeof(err)))
		fail_msg("'%s': %s", spec, err);
	return a;
}

/* parse_err - the spec is refused, with a reason containing 'why' */
static void parse_err(const char *spec, const char *why)
{
	struct action a;
	char err[160] = "";

	assert_int_equal(action_parse(spec, &a, err, sizeof(err)), -1);
	if (!strstr(err, why))
		fail_msg("'%s': '%s' does not say '%s'", spec, err, why);
}

static void test_actionspec_command(void **state)
{
	struct action a = parse_ok("ERROR:logger -t rtsup \"$RTSUP_COMPONENT: $RTSUP_LEVEL\"");

	assert_int_equal(a.level, LEVEL_ERROR);
	assert_false(a.leave);
	assert_int_equal(a.kind, ACTION_RUN);
	assert_string_equal(a.arg, "logger -t rtsup \"$RTSUP_COMPONENT: $RTSUP_LEVEL\"");
	/* a colon in the command belongs to the command */
	a = parse_ok("warn:echo a:b");
	assert_int_equal(a.level, LEVEL_WARN);
	assert_string_equal(a.arg, "echo a:b");
	/* run= forces a command that starts like a keyword */
	a = parse_ok("OK:run=fifo=1 env");
	assert_int_equal(a.kind, ACTION_RUN);
	assert_string_equal(a.arg, "fifo=1 env");
}

static void test_actionspec_leave(void **state)
{
	struct action a = parse_ok("!ERROR:echo recovered");

	assert_int_equal(a.level, LEVEL_ERROR);
	assert_true(a.leave);
	assert_string_equal(a.arg, "echo recovered");
}

static void test_actionspec_signal(void **state)
{
	struct action a = parse_ok("WARN:signal=USR1");

	assert_int_equal(a.kind, ACTION_SIGNAL);
	assert_int_equal(a.sig, SIGUSR1);
	assert_int_equal(a.pid, 0);	/* the component's process */
	a = parse_ok("ERROR:signal=SIGTERM@1234");
	assert_int_equal(a.sig, SIGTERM);
	assert_int_equal(a.pid, 1234);
	a = parse_ok("ERROR:signal=10");
	assert_int_equal(a.sig, 10);
	a = parse_ok("ERROR:signal=RTMIN+3");
	assert_int_equal(a.sig, SIGRTMIN + 3);
}

static void test_actionspec_paths(void **state)
{
	struct action a = parse_ok("ERROR:fifo=/run/rtsup.fifo");

	assert_int_equal(a.kind, ACTION_FIFO);
	assert_string_equal(a.arg, "/run/rtsup.fifo");
	a = parse_ok("STALE:unix=/run/rtsup.sock");
	assert_int_equal(a.level, LEVEL_STALE);
	assert_int_equal(a.kind, ACTION_UNIX);
	assert_string_equal(a.arg, "/run/rtsup.sock");
}

static void test_actionspec_errors(void **state)
{
	char longs[300];

	parse_err("ERROR", "want [!]LEVEL:ACTION");
	parse_err("", "want [!]LEVEL:ACTION");
	parse_err("!", "want [!]LEVEL:ACTION");
	parse_err("FATAL:echo", "unknown level 'FATAL'");
	parse_err(":echo", "unknown level ''");
	parse_err("ERROR:", "nothing to do after 'ERROR:'");
	parse_err("!WARN:fifo=", "nothing to do after '!WARN:fifo='");
	parse_err("WARN:unix=", "nothing to do");
	parse_err("WARN:run=", "nothing to do");
	parse_err("WARN:signal=", "unknown signal ''");
	parse_err("WARN:signal=USR9", "unknown signal 'USR9'");
	parse_err("WARN:signal=0", "unknown signal '0'");
	parse_err("WARN:signal=RTMIN+999", "unknown signal");
	parse_err("WARN:signal=USR1@", "bad pid ''");
	parse_err("WARN:signal=USR1@0", "bad pid '0'");
	parse_err("WARN:signal=USR1@-5", "bad pid '-5'");
	parse_err("WARN:signal=USR1@12ab", "bad pid '12ab'");
	memset(longs, 'a', sizeof(longs) - 1);
	longs[sizeof(longs) - 1] = '\0';
	memcpy(longs, "OK:unix=/", 9);
	parse_err(longs, "too long (at most 107");
	memcpy(longs, "OK:fifo=/", 9);
	parse_err(longs, "too long (at most 255");
}

/* every spec prints to a spec that parses to the same action */
static void test_actionspec_format_reads_back(void **state)
{
	static const char *const specs[] = {
		"ERROR:echo hi", "!WARN:echo a:b", "OK:run=signal=1 x", "WARN:signal=USR1",
		"!ERROR:signal=TERM@77", "ERROR:signal=RTMIN+2", "ERROR:fifo=/tmp/f",
		"STALE:unix=/tmp/s", "WARN:a=b cmd",
	};
	char buf[400];
	size_t i;

	for (i = 0; i < sizeof(specs) / sizeof(specs[0]); i++) {
		struct action a = parse_ok(specs[i]), b;

		action_format(&a, buf, sizeof(buf));
		b = parse_ok(buf);
		if (memcmp(&a, &b, sizeof(a)))
			fail_msg("'%s' printed as '%s' reads back otherwise", specs[i], buf);
	}
	/* the canonical form of a few */
	{
		struct action a = parse_ok("warn:signal=SIGUSR1");

		action_format(&a, buf, sizeof(buf));
		assert_string_equal(buf, "WARN:signal=USR1");
		a = parse_ok("OK:run=fifo=x");
		action_format(&a, buf, sizeof(buf));
		assert_string_equal(buf, "OK:run=fifo=x");
	}
}

static void test_actionspec_matches(void **state)
{
	struct action enter = parse_ok("WARN:x"), leave = parse_ok("!WARN:x");

	assert_true(action_matches(&enter, LEVEL_OK, LEVEL_WARN));
	assert_true(action_matches(&enter, LEVEL_ERROR, LEVEL_WARN));
	assert_false(action_matches(&enter, LEVEL_WARN, LEVEL_WARN));
	assert_false(action_matches(&enter, LEVEL_OK, LEVEL_ERROR));
	assert_false(action_matches(&enter, LEVEL_WARN, LEVEL_OK));
	assert_true(action_matches(&leave, LEVEL_WARN, LEVEL_OK));
	assert_true(action_matches(&leave, LEVEL_WARN, LEVEL_ERROR));
	assert_false(action_matches(&leave, LEVEL_OK, LEVEL_WARN));
	assert_false(action_matches(&leave, LEVEL_WARN, LEVEL_WARN));
}

/* once a second per (action, component), each pair on its own */
static void test_rate_once_a_second(void **state)
{
	static struct rate_limit r;

	rate_init(&r);
	assert_true(rate_allow(&r, 0, "ctl[10]", 5 * S));
	assert_false(rate_allow(&r, 0, "ctl[10]", 5 * S));
	assert_false(rate_allow(&r, 0, "ctl[10]", 6 * S - 1));
	/* another component, another action: their own budget */
	assert_true(rate_allow(&r, 0, "ctl[11]", 5 * S));
	assert_true(rate_allow(&r, 1, "ctl[10]", 5 * S));
	/* a second after the last run, not after the refused try */
	assert_true(rate_allow(&r, 0, "ctl[10]", 6 * S));
	assert_false(rate_allow(&r, 0, "ctl[10]", 6 * S + S / 2));
	assert_true(rate_allow(&r, 0, "ctl[10]", 7 * S));
	/* the first run ever is allowed at any time, also at 0 */
	assert_true(rate_allow(&r, 2, "ctl[10]", 0));
	assert_false(rate_allow(&r, 2, "ctl[10]", 1));
}

/* a full table forgets the pair that ran longest ago, never a recent one */
static void test_rate_full_table_evicts_oldest(void **state)
{
	static struct rate_limit r;
	char name[48];
	int i;

	rate_init(&r);
	for (i = 0; i < RATE_SLOTS; i++) {
		snprintf(name, sizeof(name), "c[%d]", i);
		assert_true(rate_allow(&r, 0, name, 10 * S + i));
	}
	/* one more: c[0] (oldest) makes room */
	assert_true(rate_allow(&r, 0, "new[1]", 10 * S + RATE_SLOTS));
	/* the others are still limited */
	for (i = 1; i < RATE_SLOTS; i++) {
		snprintf(name, sizeof(name), "c[%d]", i);
		assert_false(rate_allow(&r, 0, name, 10 * S + RATE_SLOTS + 1));
	}
	assert_false(rate_allow(&r, 0, "new[1]", 10 * S + RATE_SLOTS + 1));
	/* c[0] was forgotten: allowed again (at worst one extra run, never a lost one) */
	assert_true(rate_allow(&r, 0, "c[0]", 10 * S + RATE_SLOTS + 2));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_actionspec_command),
		cmocka_unit_test(test_actionspec_leave),
		cmocka_unit_test(test_actionspec_signal),
		cmocka_unit_test(test_actionspec_paths),
		cmocka_unit_test(test_actionspec_errors),
		cmocka_unit_test(test_actionspec_format_reads_back),
		cmocka_unit_test(test_actionspec_matches),
		cmocka_unit_test(test_rate_once_a_second),
		cmocka_unit_test(test_rate_full_table_evicts_oldest),
	};

	return cmocka_run_group_tests_name("actionspec", tests, NULL, NULL);
}
