// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_checks.c - user/judge/checks.c: every check of a thread (exceptions,
 * scheduling, initialization, starvation, overrun/deadline miss, execution
 * near the period, RT-safety loss, latency, jitter) and of the supervisor,
 * fed with numbers; exact levels and message texts.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "judge/checks.h"
#include "collect/since.h"

#define US	1000ULL
#define MS	1000000ULL
#define SEC	1000000000ULL

/* One thread's inputs; every test starts from a healthy FIFO thread. */
static struct rule R;
static struct span_view W, L;
static struct check_in IN;
static struct status S;

/* rule_defaults - the built-in defaults of user/config/config.c, by hand */
static void rule_defaults(struct rule *r)
{
	memset(r, 0, sizeof(*r));
	snprintf(r->name, sizeof(r->name), "defaults");
	r->ewma_weight = 0.1;
	r->policy = -1;
	r->prio = -1;
	r->th.init_timeout_s = 5;
	r->th.miss_warn = 1;
	r->th.miss_error_rate = 0.01;
	r->th.exec_warn_ratio = 0.8;
	r->th.exec_stat = EXEC_STAT_P99;
	r->th.starve_warn_periods = 10;
	r->th.starve_error_periods = 100;
	r->th.unsafe_warn = 1;
	r->th.unsafe_error[RTSUP_U_MAJFLT] = 1;
	r->th.overhead_warn_pct = 1;
	r->th.overhead_error_pct = 5;
}

static int setup(void **state)
{
	rule_defaults(&R);
	memset(&W, 0, sizeof(W));
	memset(&L, 0, sizeof(L));
	memset(&IN, 0, sizeof(IN));
	memset(&S, 0x5a, sizeof(S));	/* check_thread must reset it */
	W.cycles = 1000;
	L.cycles = 100000;
	IN.win = &W;
	IN.life = &L;
	IN.rule = &R;
	IN.judged = true;
	IN.alive = true;
	IN.policy = 1;		/* SCHED_FIFO */
	IN.prio = 80;
	IN.now_ns = 100 * SEC;
	IN.first_seen_ns = 1 * SEC;
	IN.last_cycle_ns = IN.now_ns - 500 * US;
	IN.nominal_ns = 1 * MS;
	IN.unsafe_names = "";
	return 0;
}

/* find - index of the message containing 'sub', -1 if none */
static int find(const struct status *s, const char *sub)
{
	int i;

	for (i = 0; i < s->nmsg; i++)
		if (strstr(s->msg[i], sub))
			return i;
	return -1;
}

/* run - check_thread into S */
static void run(void)
{
	check_thread(&IN, &S);
}

/* expect_one - exactly one message, this level and this text */
static void expect_one(enum level l, const char *text)
{
	assert_int_equal(S.nmsg, 1);
	assert_int_equal(S.dropped, 0);
	assert_string_equal(S.msg[0], text);
	assert_int_equal(S.level, l);
}

static void expect_none(void)
{
	assert_int_equal(S.nmsg, 0);
	assert_int_equal(S.dropped, 0);
	assert_int_equal(S.level, LEVEL_OK);
}

/* ---- baseline and judged ---- */

static void test_checks_healthy_ok(void **state)
{
	run();
	expect_none();
}

static void test_checks_not_judged_silent(void **state)
{
	/* everything wrong at once, but the thread is neither RT nor in a rule */
	IN.judged = false;
	W.misses = 500;
	W.overruns = 500;
	W.unsafe[RTSUP_U_MAJFLT] = 3;
	W.unsafe[RTSUP_U_SYSCALL] = 7;
	W.unsafe_total = 10;
	IN.unsafe_names = "mmap 7";
	W.m[RTSUP_M_EXEC].count = 1000;
	W.m[RTSUP_M_EXEC].p99 = 5 * MS;
	R.policy = 1;
	R.prio = 90;
	IN.policy = 0;
	IN.last_cycle_ns = IN.now_ns - 10 * SEC;
	R.th.lifetime = true;
	L.misses = 1000;
	L.unsafe[RTSUP_U_MAJFLT] = 9;
	L.unsafe_total = 9;
	IN.restarted_from = 77;
	run();
	expect_none();
}

/* ---- check_period ---- */

static void test_checks_period_from_rule(void **state)
{
	R.period_ns = 2 * MS;
	IN.nominal_ns = 1 * MS;
	L.m[RTSUP_M_PERIOD].count = 100;
	L.m[RTSUP_M_PERIOD].mean = 3 * MS;
	assert_int_equal(check_period(&IN), 2 * MS);
}

static void test_checks_period_from_nominal(void **state)
{
	IN.nominal_ns = 1 * MS;
	L.m[RTSUP_M_PERIOD].count = 100;
	L.m[RTSUP_M_PERIOD].mean = 3 * MS;
	assert_int_equal(check_period(&IN), 1 * MS);
}

static void test_checks_period_from_mean(void **state)
{
	IN.nominal_ns = 0;
	L.m[RTSUP_M_PERIOD].mean = 3 * MS + 0.75;
	L.m[RTSUP_M_PERIOD].count = 7;
	assert_int_equal(check_period(&IN), 0);
	L.m[RTSUP_M_PERIOD].count = 8;
	assert_int_equal(check_period(&IN), 3 * MS);
	L.m[RTSUP_M_PERIOD].count = 0;
	L.m[RTSUP_M_PERIOD].mean = 0;
	assert_int_equal(check_period(&IN), 0);
}

/* ---- initialization ---- */

static void no_cycles_yet(void)
{
	W.cycles = 0;
	L.cycles = 0;
	IN.last_cycle_ns = 0;
}

static void test_checks_init_timeout_warn(void **state)
{
	no_cycles_yet();
	IN.expect_run = true;	/* a rule names it */
	IN.first_seen_ns = IN.now_ns - 6 * SEC;
	run();
	expect_one(LEVEL_WARN, "not initialized: no cycle 6.0 s after it appeared");
}

static void test_checks_init_at_timeout_warn(void **state)
{
	no_cycles_yet();
	IN.expect_run = true;
	IN.first_seen_ns = IN.now_ns - 5 * SEC;
	run();
	expect_one(LEVEL_WARN, "not initialized: no cycle 5.0 s after it appeared");
}

static void test_checks_init_before_timeout(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 4 * SEC;
	run();
	expect_none();
}

static void test_checks_init_with_cycles(void **state)
{
	IN.first_seen_ns = IN.now_ns - 60 * SEC;
	L.cycles = 1;
	W.cycles = 0;
	run();
	assert_int_equal(find(&S, "not initialized"), -1);
	expect_none();
}

static void test_checks_init_dead(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 60 * SEC;
	IN.alive = false;
	IN.exit_expected = true;
	run();
	assert_int_equal(find(&S, "not initialized"), -1);
	expect_one(LEVEL_STALE, "exited");
}

/* --rt let go of a thread that left RT: said once, STALE, not judged as an exit */
static void test_checks_left_rt(void **state)
{
	IN.left_rt = true;
	IN.policy = 0;
	run();
	expect_one(LEVEL_STALE, "left RT (policy SCHED_OTHER): no longer a --rt target");
}

static void test_checks_init_timeout_off(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 60 * SEC;
	R.th.init_timeout_s = 0;
	run();
	expect_none();
}

/* an RT thread no rule names that never showed a cycle waits for work: idle (issue 12) */
static void test_checks_init_unnamed_is_idle(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 6 * SEC;
	run();
	expect_one(LEVEL_OK, "idle: no cycle 6.0 s after it appeared");
}

static void test_checks_init_unnamed_before_timeout(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 4 * SEC;
	run();
	expect_none();
}

/* a kernel thread no rule names (watchdogd, irq/24-ACPI:Ged under --rt): shown, not judged */
static void test_checks_kthread_unnamed_not_judged(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 60 * SEC;
	IN.judged = false;
	IN.kthread = true;
	W.misses = 50;
	run();
	expect_one(LEVEL_OK, "kernel thread: judged when a rule names it");
}

/*
 * an unjudged thread's status is a function of check_shown_key alone: the
 * supervisor keeps it while the key stays. Every input check_thread reads
 * is varied; two statuses of the same key are the same.
 */
static void test_checks_shown_key_is_all_it_reads(void **state)
{
	struct status first[4];
	bool have[4] = { false };
	int v;

	(void)state;
	assert_int_equal(check_shown_key(true, false, true), 0);
	assert_int_equal(check_shown_key(true, true, true), 0);
	for (v = 0; v < 256; v++) {
		unsigned key;

		setup(NULL);
		IN.judged = false;
		IN.kthread = v & 1;
		IN.alive = v & 2;
		IN.left_rt = v & 4;
		IN.policy = v & 8 ? 1 : 0;
		IN.last_cycle_ns = v & 16 ? 0 : IN.now_ns - 10 * SEC;
		IN.exit_code = v & 32 ? 9 : 0;
		IN.process_ended = v & 32;
		W.misses = v & 64 ? 500 : 0;
		R.th.lifetime = v & 128;
		IN.win = v & 64 ? &W : NULL;
		key = check_shown_key(IN.judged, IN.kthread, IN.alive);
		assert_true(key >= 1 && key < 4);
		run();
		if (!have[key]) {
			status_copy(&first[key], &S);
			have[key] = true;
		}
		assert_true(status_same(&first[key], &S));
		assert_int_equal(first[key].level, S.level);
	}
	/* a kernel thread alive says so; the others say nothing */
	assert_true(have[1] && have[3] && !have[2]);
	assert_int_equal(first[3].nmsg, 1);
	assert_int_equal(first[1].nmsg, 0);
}

/* a kernel thread a rule names is judged like any other thread */
static void test_checks_kthread_named_judged(void **state)
{
	no_cycles_yet();
	IN.first_seen_ns = IN.now_ns - 60 * SEC;
	IN.kthread = true;
	IN.expect_run = true;
	run();
	expect_one(LEVEL_WARN, "not initialized: no cycle 60.0 s after it appeared");
}

/*
 * A thread first seen while the maps were read has a first_seen newer than
 * 'now': it is 0 s old, not 18446744073.7 s (issue 12, item 5).
 */
static void test_checks_init_first_seen_after_now(void **state)
{
	no_cycles_yet();
	IN.expect_run = true;
	IN.first_seen_ns = IN.now_ns + 1000;
	run();
	expect_none();
}

/* a cycle that started after 'now' was read is no starvation */
static void test_checks_starve_last_cycle_after_now(void **state)
{
	IN.last_cycle_ns = IN.now_ns + 1000;
	run();
	expect_none();
}

static void test_checks_ns_since_clamps(void **state)
{
	assert_int_equal(ns_since(10, 3), 7);
	assert_int_equal(ns_since(10, 10), 0);
	assert_int_equal(ns_since(10, 11), 0);
	assert_int_equal(ns_since(0, ~0ULL), 0);
}

/* ---- overrun / deadline miss ---- */

static void test_checks_miss_warn(void **state)
{
	W.misses = 5;		/* 0.5 % of 1000 */
	run();
	expect_one(LEVEL_WARN,
		   "5 deadline misses, 0 overruns in 1000 cycles in the last interval (0.50 %)");
}

/* the misses' top cause (model/causes.h) follows the numbers */
static void test_checks_miss_names_cause(void **state)
{
	W.misses = 5;
	IN.why_win = "4 caused by noise-hog[812] FIFO/99 (wait, 3.1 ms max)";
	run();
	expect_one(LEVEL_WARN,
		   "5 deadline misses, 0 overruns in 1000 cycles in the last interval (0.50 %), "
		   "4 caused by noise-hog[812] FIFO/99 (wait, 3.1 ms max)");
	/* overruns alone: no miss to explain */
	W.misses = 0;
	W.overruns = 5;
	run();
	expect_one(LEVEL_WARN,
		   "0 deadline misses, 5 overruns in 1000 cycles in the last interval (0.50 %)");
	IN.why_win = NULL;
}

static void test_checks_miss_at_rate_warn(void **state)
{
	W.misses = 10;		/* exactly 1 %: not above */
	run();
	expect_one(LEVEL_WARN,
		   "10 deadline misses, 0 overruns in 1000 cycles in the last interval (1.00 %)");
}

static void test_checks_miss_rate_error(void **state)
{
	W.misses = 20;		/* 2 % > 1 % */
	run();
	expect_one(LEVEL_ERROR,
		   "20 deadline misses, 0 overruns in 1000 cycles in the last interval (2.00 %)");
}

static void test_checks_overrun_without_miss(void **state)
{
	W.overruns = 3;
	run();
	expect_one(LEVEL_WARN,
		   "0 deadline misses, 3 overruns in 1000 cycles in the last interval (0.30 %)");

	setup(state);
	W.overruns = 50;	/* 5 %: the rate counts overruns too */
	W.misses = 2;
	run();
	expect_one(LEVEL_ERROR,
		   "2 deadline misses, 50 overruns in 1000 cycles in the last interval (5.00 %)");
}

static void test_checks_miss_below_warn(void **state)
{
	R.th.miss_warn = 3;
	W.misses = 2;
	run();
	expect_none();
	W.misses = 3;
	run();
	expect_one(LEVEL_WARN,
		   "3 deadline misses, 0 overruns in 1000 cycles in the last interval (0.30 %)");
}

static void test_checks_miss_warn_zero_off(void **state)
{
	R.th.miss_warn = 0;
	W.misses = 500;
	W.overruns = 500;
	run();
	expect_none();
}

static void test_checks_miss_error_rate_zero_warn_only(void **state)
{
	R.th.miss_error_rate = 0;
	W.misses = 500;
	run();
	expect_one(LEVEL_WARN,
		   "500 deadline misses, 0 overruns in 1000 cycles in the last interval (50.00 %)");
}

static void test_checks_miss_lifetime(void **state)
{
	L.misses = 50;		/* 0.05 % of 100000 */
	run();
	expect_none();		/* lifetime off by default */

	R.th.lifetime = true;
	run();
	expect_one(LEVEL_WARN,
		   "50 deadline misses, 0 overruns in 100000 cycles in total (0.05 %)");

	L.misses = 2000;	/* 2 % */
	run();
	expect_one(LEVEL_ERROR,
		   "2000 deadline misses, 0 overruns in 100000 cycles in total (2.00 %)");
}

static void test_checks_miss_no_window(void **state)
{
	IN.win = NULL;		/* before the first interval */
	run();
	expect_none();
}

/* ---- execution near the period ---- */

static void exec_p99(__u64 p99, double ewma)
{
	W.m[RTSUP_M_EXEC].count = 1000;
	W.m[RTSUP_M_EXEC].p99 = p99;
	W.m[RTSUP_M_EXEC].ewma = ewma;
	W.m[RTSUP_M_EXEC].mean = ewma;
	W.m[RTSUP_M_EXEC].max = p99;
}

static void test_checks_exec_p99_warn(void **state)
{
	exec_p99(900 * US, 100 * US);
	run();
	expect_one(LEVEL_WARN, "execution p99 900.0 us is 90 % of the 1000.0 us period");
}

static void test_checks_exec_p99_below(void **state)
{
	exec_p99(700 * US, 950 * US);	/* the EWMA is not looked at */
	run();
	expect_none();
	exec_p99(800 * US, 0);		/* exactly 80 %: not above */
	run();
	expect_none();
}

static void test_checks_exec_ewma_warn(void **state)
{
	R.th.exec_stat = EXEC_STAT_EWMA;
	exec_p99(100 * US, 850.0 * US);
	run();
	expect_one(LEVEL_WARN, "execution EWMA 850.0 us is 85 % of the 1000.0 us period");
}

static void test_checks_exec_ewma_below(void **state)
{
	R.th.exec_stat = EXEC_STAT_EWMA;
	exec_p99(990 * US, 500.0 * US);	/* the p99 is not looked at */
	run();
	expect_none();
}

static void test_checks_exec_period_from_rule(void **state)
{
	R.period_ns = 2 * MS;
	IN.nominal_ns = 1 * MS;
	exec_p99(900 * US, 0);		/* 45 % of the rule's period */
	run();
	expect_none();
	exec_p99(1700 * US, 0);
	run();
	expect_one(LEVEL_WARN, "execution p99 1700.0 us is 85 % of the 2000.0 us period");
}

static void test_checks_exec_period_from_mean(void **state)
{
	IN.nominal_ns = 0;
	exec_p99(900 * US, 0);
	L.m[RTSUP_M_PERIOD].mean = 1 * MS;
	L.m[RTSUP_M_PERIOD].count = 7;	/* not enough periods yet: no period */
	run();
	expect_none();
	L.m[RTSUP_M_PERIOD].count = 8;
	run();
	expect_one(LEVEL_WARN, "execution p99 900.0 us is 90 % of the 1000.0 us period");
}

static void test_checks_exec_off(void **state)
{
	R.th.exec_warn_ratio = 0;
	exec_p99(5 * MS, 5.0 * MS);
	run();
	expect_none();

	setup(state);
	exec_p99(900 * US, 0);
	W.m[RTSUP_M_EXEC].count = 0;	/* no execution measured in the window */
	run();
	expect_none();
}

/* ---- starvation ---- */

static void test_checks_starve_warn(void **state)
{
	IN.last_cycle_ns = IN.now_ns - 15 * MS;
	run();
	expect_one(LEVEL_WARN, "starving: no new cycle for 15.0 ms (15 periods)");
}

static void test_checks_starve_at_warn(void **state)
{
	IN.last_cycle_ns = IN.now_ns - 10 * MS;
	run();
	expect_one(LEVEL_WARN, "starving: no new cycle for 10.0 ms (10 periods)");
	IN.last_cycle_ns = IN.now_ns - 9 * MS;
	run();
	expect_none();
}

static void test_checks_starve_error(void **state)
{
	IN.last_cycle_ns = IN.now_ns - 150 * MS;
	run();
	expect_one(LEVEL_ERROR, "starving: no new cycle for 150.0 ms (150 periods)");
	IN.last_cycle_ns = IN.now_ns - 100 * MS;
	run();
	expect_one(LEVEL_ERROR, "starving: no new cycle for 100.0 ms (100 periods)");
}

static void test_checks_starve_rule_period(void **state)
{
	R.period_ns = 10 * MS;		/* 150 ms = 15 periods of the rule */
	IN.last_cycle_ns = IN.now_ns - 150 * MS;
	run();
	expect_one(LEVEL_WARN, "starving: no new cycle for 150.0 ms (15 periods)");
}

static void test_checks_starve_dead(void **state)
{
	IN.last_cycle_ns = IN.now_ns - 150 * MS;
	IN.alive = false;
	IN.exit_expected = true;
	run();
	assert_int_equal(find(&S, "starving"), -1);
	expect_one(LEVEL_STALE, "exited");
}

static void test_checks_starve_no_period_or_cycle(void **state)
{
	IN.last_cycle_ns = IN.now_ns - 150 * MS;
	IN.nominal_ns = 0;		/* no period known */
	run();
	expect_none();

	setup(state);
	IN.last_cycle_ns = 0;		/* never a cycle: initialization's job */
	IN.first_seen_ns = IN.now_ns - 1 * SEC;
	run();
	expect_none();
}

static void test_checks_starve_error_off(void **state)
{
	R.th.starve_error_periods = 0;
	IN.last_cycle_ns = IN.now_ns - 5 * SEC;
	run();
	expect_one(LEVEL_WARN, "starving: no new cycle for 5000.0 ms (5000 periods)");
}

/* ---- RT-safety loss ---- */

static void test_checks_unsafe_warn_names(void **state)
{
	W.unsafe[RTSUP_U_SYSCALL] = 2;
	W.unsafe[RTSUP_U_MINFLT] = 1;
	W.unsafe_total = 3;
	IN.unsafe_names = "mmap 1, munmap 1";
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in the last interval: syscall 2, minor_fault 1 "
		   "(syscalls: mmap 1, munmap 1)");
}

/* every message says its check, its level and its numbers, for machines */
static void test_checks_facts_name_check_and_counts(void **state)
{
	const struct status_fact *f;

	W.misses = 20;
	W.unsafe[RTSUP_U_SYSCALL] = 2;
	W.unsafe[RTSUP_U_MINFLT] = 1;
	W.unsafe_total = 3;
	IN.policy = 0;		/* SCHED_OTHER */
	R.policy = 1;
	run();
	assert_int_equal(S.nmsg, 3);
	f = &S.fact[0];
	assert_string_equal(f->check, CHECK_SCHED);
	assert_int_equal(f->level, LEVEL_ERROR);
	assert_int_equal(f->ncounts, 0);
	f = &S.fact[1];
	assert_string_equal(f->check, CHECK_MISS);
	assert_int_equal(f->level, LEVEL_ERROR);
	assert_int_equal(f->ncounts, 3);
	assert_string_equal(f->counts[0].key, "deadline_misses");
	assert_int_equal(f->counts[0].val, 20);
	assert_string_equal(f->counts[2].key, "cycles");
	assert_int_equal(f->counts[2].val, 1000);
	f = &S.fact[2];
	assert_string_equal(f->check, CHECK_UNSAFE);
	assert_int_equal(f->level, LEVEL_WARN);
	assert_int_equal(f->ncounts, 2);
	assert_string_equal(f->counts[0].key, "syscall");
	assert_int_equal(f->counts[0].val, 2);
	assert_string_equal(f->counts[1].key, "minor_fault");
	assert_int_equal(f->counts[1].val, 1);
}

static void test_checks_unsafe_warn_no_names(void **state)
{
	W.unsafe[RTSUP_U_BLOCK] = 1;
	W.unsafe[RTSUP_U_MIGRATE] = 4;
	W.unsafe_total = 5;
	IN.unsafe_names = "";
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in the last interval: block 1, migration 4");
	IN.unsafe_names = NULL;
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in the last interval: block 1, migration 4");
}

static void test_checks_unsafe_major_fault_error(void **state)
{
	W.unsafe[RTSUP_U_MAJFLT] = 1;
	W.unsafe_total = 1;
	run();
	expect_one(LEVEL_ERROR, "RT-unsafe in the last interval: major_fault 1");
}

static void test_checks_unsafe_reason_threshold(void **state)
{
	R.th.unsafe_error[RTSUP_U_BLOCK] = 10;
	W.unsafe[RTSUP_U_BLOCK] = 9;
	W.unsafe_total = 9;
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in the last interval: block 9");
	W.unsafe[RTSUP_U_BLOCK] = 10;
	W.unsafe_total = 10;
	run();
	expect_one(LEVEL_ERROR, "RT-unsafe in the last interval: block 10");
}

static void test_checks_unsafe_below_warn(void **state)
{
	R.th.unsafe_warn = 5;
	W.unsafe[RTSUP_U_SYSCALL] = 4;
	W.unsafe_total = 4;
	run();
	expect_none();
	W.unsafe[RTSUP_U_SYSCALL] = 5;
	W.unsafe_total = 5;
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in the last interval: syscall 5");
}

static void test_checks_unsafe_warn_zero_off(void **state)
{
	/* the documented "0 switches the whole check off, errors included" */
	R.th.unsafe_warn = 0;
	W.unsafe[RTSUP_U_MAJFLT] = 3;
	W.unsafe_total = 3;
	run();
	expect_none();
}

static void test_checks_unsafe_lifetime(void **state)
{
	L.unsafe[RTSUP_U_MIGRATE] = 4;
	L.unsafe_total = 4;
	run();
	expect_none();		/* lifetime off */

	R.th.lifetime = true;
	run();
	expect_one(LEVEL_WARN, "RT-unsafe in total: migration 4");

	L.unsafe[RTSUP_U_MAJFLT] = 1;
	L.unsafe_total = 5;
	run();
	expect_one(LEVEL_ERROR, "RT-unsafe in total: major_fault 1, migration 4");
}

/*
 * unsafe_names are the window's syscalls (check_in, supervise.c): they must
 * not be given as the syscalls of the lifetime totals.
 */
static void test_checks_unsafe_lifetime_not_named_by_window(void **state)
{
	int t;

	R.th.lifetime = true;
	W.unsafe[RTSUP_U_SYSCALL] = 1;
	W.unsafe_total = 1;
	IN.unsafe_names = "mmap 1";
	L.unsafe[RTSUP_U_SYSCALL] = 40;
	L.unsafe_total = 40;
	run();
	assert_int_equal(S.level, LEVEL_WARN);
	assert_int_equal(S.nmsg, 2);
	assert_string_equal(S.msg[0], "RT-unsafe in the last interval: syscall 1 "
			    "(syscalls: mmap 1)");
	t = find(&S, "RT-unsafe in total: syscall 40");
	assert_int_equal(t, 1);
	/* "syscall 40 (syscalls: mmap 1)" would name 1 of the 40 as all of them */
	assert_null(strstr(S.msg[t], "mmap 1"));
}

/* ---- latency ---- */

static void latency(__u64 p99, __u64 max)
{
	W.m[RTSUP_M_LATENCY].count = 1000;
	W.m[RTSUP_M_LATENCY].p99 = p99;
	W.m[RTSUP_M_LATENCY].max = max;
}

static void test_checks_latency_p99_warn(void **state)
{
	R.th.latency_p99_warn_ns = 100 * US;
	latency(150 * US, 180 * US);
	run();
	expect_one(LEVEL_WARN, "wakeup latency p99 150.0 us > 100.0 us");
	latency(100 * US, 180 * US);	/* not above */
	run();
	expect_none();
}

static void test_checks_latency_max_warn(void **state)
{
	R.th.latency_max_warn_ns = 200 * US;
	R.th.latency_max_error_ns = 1 * MS;
	latency(50 * US, 250 * US);
	run();
	expect_one(LEVEL_WARN, "wakeup latency max 250.0 us > 200.0 us");
	latency(50 * US, 200 * US);
	run();
	expect_none();
}

static void test_checks_latency_max_error(void **state)
{
	R.th.latency_max_warn_ns = 200 * US;
	R.th.latency_max_error_ns = 1 * MS;
	latency(50 * US, 1500 * US);
	run();
	/* the error replaces the warning of the same statistic */
	expect_one(LEVEL_ERROR, "wakeup latency max 1500.0 us > 1000.0 us");
}

static void test_checks_latency_p99_and_max(void **state)
{
	R.th.latency_p99_warn_ns = 100 * US;
	R.th.latency_max_error_ns = 1 * MS;
	latency(150 * US, 2 * MS);
	run();
	assert_int_equal(S.level, LEVEL_ERROR);
	assert_int_equal(S.nmsg, 2);
	assert_string_equal(S.msg[0], "wakeup latency max 2000.0 us > 1000.0 us");
	assert_string_equal(S.msg[1], "wakeup latency p99 150.0 us > 100.0 us");
}

static void test_checks_latency_zero_off(void **state)
{
	latency(5 * MS, 50 * MS);
	run();
	expect_none();
}

static void test_checks_latency_lifetime(void **state)
{
	R.th.latency_max_error_ns = 1 * MS;
	L.m[RTSUP_M_LATENCY].count = 100000;
	L.m[RTSUP_M_LATENCY].p99 = 20 * US;
	L.m[RTSUP_M_LATENCY].max = 3 * MS;
	run();
	expect_none();
	R.th.lifetime = true;
	run();
	expect_one(LEVEL_ERROR, "wakeup latency max 3000.0 us > 1000.0 us");
}

/* ---- jitter ---- */

static void periods(__u64 min, __u64 max)
{
	W.m[RTSUP_M_PERIOD].count = 1000;
	W.m[RTSUP_M_PERIOD].min = min;
	W.m[RTSUP_M_PERIOD].max = max;
	W.m[RTSUP_M_PERIOD].mean = 1.0 * MS;
}

static void test_checks_jitter_warn_late(void **state)
{
	R.th.jitter_warn_ns = 20 * US;
	R.th.jitter_error_ns = 200 * US;
	periods(990 * US, 1030 * US);
	run();
	expect_one(LEVEL_WARN, "period jitter 30.0 us > 20.0 us");
}

static void test_checks_jitter_warn_early(void **state)
{
	R.th.jitter_warn_ns = 20 * US;
	periods(950 * US, 1010 * US);
	run();
	expect_one(LEVEL_WARN, "period jitter 50.0 us > 20.0 us");
}

static void test_checks_jitter_error(void **state)
{
	R.th.jitter_warn_ns = 20 * US;
	R.th.jitter_error_ns = 200 * US;
	periods(700 * US, 1010 * US);
	run();
	expect_one(LEVEL_ERROR, "period jitter 300.0 us > 200.0 us");

	/* the error threshold alone */
	R.th.jitter_warn_ns = 0;
	periods(1 * MS, 1250 * US);
	run();
	expect_one(LEVEL_ERROR, "period jitter 250.0 us > 200.0 us");
}

static void test_checks_jitter_below(void **state)
{
	R.th.jitter_warn_ns = 20 * US;
	R.th.jitter_error_ns = 200 * US;
	periods(980 * US, 1020 * US);	/* exactly 20 us: not above */
	run();
	expect_none();
}

static void test_checks_jitter_zero_off(void **state)
{
	periods(100 * US, 10 * MS);
	run();
	expect_none();
}

static void test_checks_jitter_rule_period(void **state)
{
	R.period_ns = 2 * MS;		/* against the rule's period, not the nominal */
	R.th.jitter_warn_ns = 20 * US;
	periods(1990 * US, 2010 * US);
	run();
	expect_none();
	periods(1 * MS, 2010 * US);
	run();
	expect_one(LEVEL_WARN, "period jitter 1000.0 us > 20.0 us");
}

static void test_checks_jitter_lifetime(void **state)
{
	R.th.jitter_warn_ns = 20 * US;
	L.m[RTSUP_M_PERIOD].count = 100000;
	L.m[RTSUP_M_PERIOD].min = 1 * MS;
	L.m[RTSUP_M_PERIOD].max = 1100 * US;
	L.m[RTSUP_M_PERIOD].mean = 1.0 * MS;
	run();
	expect_none();
	R.th.lifetime = true;
	run();
	expect_one(LEVEL_WARN, "period jitter 100.0 us > 20.0 us");
}

/* ---- exceptions ---- */

static void test_checks_exc_signal(void **state)
{
	char want[STATUS_MSG_LEN];

	IN.alive = false;
	IN.exit_code = SIGSEGV;
	run();
	snprintf(want, sizeof(want), "killed by signal 11 (%s)", strsignal(SIGSEGV));
	expect_one(LEVEL_ERROR, want);
	assert_non_null(strstr(S.msg[0], "Segmentation fault"));

	/* with the core dump bit */
	IN.exit_code = SIGSEGV | 0x80;
	run();
	expect_one(LEVEL_ERROR, want);

	/* killed even though the command's end was expected */
	IN.exit_expected = true;
	run();
	expect_one(LEVEL_ERROR, want);
}

static void test_checks_exc_signal_mid_cycle(void **state)
{
	char want[STATUS_MSG_LEN];

	IN.alive = false;
	IN.exit_code = SIGKILL;
	IN.exit_mid_cycle = true;
	run();
	snprintf(want, sizeof(want), "killed by signal 9 (%s) inside a cycle",
		 strsignal(SIGKILL));
	expect_one(LEVEL_ERROR, want);
}

static void test_checks_exc_status(void **state)
{
	IN.alive = false;
	IN.exit_code = 3 << 8;
	run();
	expect_one(LEVEL_ERROR, "exited with status 3");
	IN.exit_mid_cycle = true;
	run();
	expect_one(LEVEL_ERROR, "exited with status 3 inside a cycle");
	IN.exit_expected = true;
	run();
	expect_one(LEVEL_ERROR, "exited with status 3 inside a cycle");
}

static void test_checks_exc_unexpected_exit(void **state)
{
	IN.alive = false;
	IN.exit_code = 0;
	run();
	expect_one(LEVEL_ERROR, "thread exited");
	IN.exit_mid_cycle = true;
	run();
	expect_one(LEVEL_ERROR, "thread exited inside a cycle");
}

static void test_checks_exc_expected_exit_stale(void **state)
{
	IN.alive = false;
	IN.exit_code = 0;
	IN.exit_expected = true;
	run();
	expect_one(LEVEL_STALE, "exited");
}

/* the whole process ended with status 0: a clean end, inside a cycle or not */
static void test_checks_exc_process_ended_cleanly_stale(void **state)
{
	IN.alive = false;
	IN.exit_code = 0;
	IN.process_ended = true;
	run();
	expect_one(LEVEL_STALE, "exited: its process ended with status 0");
	IN.exit_mid_cycle = true;
	run();
	expect_one(LEVEL_STALE, "exited: its process ended with status 0");
}

/* ... but not with another status, nor by a signal (its exit code is the signal) */
static void test_checks_exc_process_ended_badly_error(void **state)
{
	char want[STATUS_MSG_LEN];

	IN.alive = false;
	IN.process_ended = true;
	IN.exit_code = 3 << 8;
	run();
	expect_one(LEVEL_ERROR, "exited with status 3");
	IN.exit_code = SIGKILL;
	run();
	snprintf(want, sizeof(want), "killed by signal 9 (%s)", strsignal(SIGKILL));
	expect_one(LEVEL_ERROR, want);
}

static void test_checks_exc_alive_ignores_exit_code(void **state)
{
	IN.exit_code = SIGSEGV;		/* stale value of a live thread */
	run();
	expect_none();
}

static void test_checks_exc_restarted(void **state)
{
	IN.restarted_from = 4242;
	run();
	expect_one(LEVEL_OK, "restarted: replaces tid 4242, which died");
}

static void test_checks_exc_restarted_with_warn(void **state)
{
	IN.restarted_from = 4242;
	W.misses = 1;
	run();
	assert_int_equal(S.level, LEVEL_WARN);
	assert_int_equal(S.nmsg, 2);
	assert_string_equal(S.msg[0], "restarted: replaces tid 4242, which died");
	assert_int_equal(find(&S, "1 deadline misses"), 1);
}

/* a dead thread with nothing else to say is STALE, and worse stays worse */
static void test_checks_dead_stale_unless_worse(void **state)
{
	IN.alive = false;
	IN.exit_expected = true;
	W.misses = 1;		/* its last interval still counts */
	run();
	assert_int_equal(S.level, LEVEL_WARN);
	assert_int_equal(S.nmsg, 2);
	assert_string_equal(S.msg[0], "exited");
	assert_int_equal(find(&S, "1 deadline misses, 0 overruns"), 1);
}

/* ---- scheduling ---- */

static void test_checks_sched_policy_error(void **state)
{
	R.policy = 1;
	R.prio = 80;
	IN.policy = 0;
	IN.prio = 0;
	run();
	/* the priority is not judged when the policy is already wrong */
	expect_one(LEVEL_ERROR, "policy SCHED_OTHER, expected SCHED_FIFO");

	IN.policy = 2;
	IN.prio = 80;
	run();
	expect_one(LEVEL_ERROR, "policy SCHED_RR, expected SCHED_FIFO");
}

static void test_checks_sched_prio_warn(void **state)
{
	R.policy = 1;
	R.prio = 80;
	IN.prio = 50;
	run();
	expect_one(LEVEL_WARN, "priority 50, expected 80");

	R.policy = -1;		/* any policy, but this priority */
	IN.policy = 2;
	run();
	expect_one(LEVEL_WARN, "priority 50, expected 80");
}

static void test_checks_sched_any(void **state)
{
	R.policy = -1;
	R.prio = -1;
	IN.policy = 0;
	IN.prio = 0;
	run();
	expect_none();

	R.policy = 1;
	R.prio = 80;
	IN.policy = 1;
	IN.prio = 80;
	run();
	expect_none();
}

static void test_checks_sched_dead(void **state)
{
	R.policy = 1;
	R.prio = 80;
	IN.alive = false;
	IN.exit_expected = true;
	IN.policy = -1;		/* gone */
	run();
	expect_one(LEVEL_STALE, "exited");
}

/* ---- several checks at once ---- */

static void test_checks_several_worst_wins(void **state)
{
	R.prio = 90;				/* WARN */
	R.th.latency_p99_warn_ns = 100 * US;	/* WARN */
	latency(150 * US, 200 * US);
	W.misses = 30;				/* ERROR: 3 % */
	W.unsafe[RTSUP_U_SYSCALL] = 1;		/* WARN */
	W.unsafe_total = 1;
	IN.unsafe_names = "write 1";
	exec_p99(900 * US, 0);			/* WARN */
	IN.last_cycle_ns = IN.now_ns - 20 * MS;	/* WARN: 20 periods */
	IN.restarted_from = 9;			/* OK */
	run();
	assert_int_equal(S.level, LEVEL_ERROR);
	assert_int_equal(S.nmsg, 7);
	assert_int_equal(S.dropped, 0);
	/* check order: exceptions, scheduling, init, starvation, window checks */
	assert_string_equal(S.msg[0], "restarted: replaces tid 9, which died");
	assert_string_equal(S.msg[1], "priority 80, expected 90");
	assert_string_equal(S.msg[2], "starving: no new cycle for 20.0 ms (20 periods)");
	assert_string_equal(S.msg[3],
			    "30 deadline misses, 0 overruns in 1000 cycles in the last interval (3.00 %)");
	assert_string_equal(S.msg[4], "execution p99 900.0 us is 90 % of the 1000.0 us period");
	assert_string_equal(S.msg[5], "RT-unsafe in the last interval: syscall 1 (syscalls: write 1)");
	assert_string_equal(S.msg[6], "wakeup latency p99 150.0 us > 100.0 us");
}

static void test_checks_several_warn_only(void **state)
{
	R.policy = 1;
	R.prio = 90;
	R.th.jitter_warn_ns = 10 * US;
	periods(1 * MS, 1050 * US);
	W.overruns = 1;
	run();
	assert_int_equal(S.level, LEVEL_WARN);
	assert_int_equal(S.nmsg, 3);
	assert_true(find(&S, "priority 80, expected 90") >= 0);
	assert_true(find(&S, "0 deadline misses, 1 overruns in 1000 cycles") >= 0);
	assert_true(find(&S, "period jitter 50.0 us > 10.0 us") >= 0);
}

/* ---- check_self ---- */

static struct thresholds T;
static struct self_in SI;

static int self_setup(void **state)
{
	struct rule r;

	rule_defaults(&r);
	T = r.th;
	memset(&SI, 0, sizeof(SI));
	SI.th = &T;
	SI.overhead_pct = 0.2;
	memset(&S, 0x5a, sizeof(S));
	return 0;
}

static void test_checks_self_ok(void **state)
{
	check_self(&SI, &S);
	expect_none();
	SI.overhead_pct = 1.0;		/* exactly the limit: not above */
	check_self(&SI, &S);
	expect_none();
}

static void test_checks_self_overhead_warn(void **state)
{
	SI.overhead_pct = 2.5;
	check_self(&SI, &S);
	expect_one(LEVEL_WARN, "BPF overhead 2.50 % of a CPU > 1.00 %");
}

static void test_checks_self_overhead_error(void **state)
{
	SI.overhead_pct = 7;
	check_self(&SI, &S);
	expect_one(LEVEL_ERROR, "BPF overhead 7.00 % of a CPU > 5.00 %");

	T.overhead_warn_pct = 0;	/* the error alone */
	check_self(&SI, &S);
	expect_one(LEVEL_ERROR, "BPF overhead 7.00 % of a CPU > 5.00 %");
}

static void test_checks_self_overhead_unknown(void **state)
{
	SI.overhead_pct = -1;
	check_self(&SI, &S);
	expect_none();
}

static void test_checks_self_overhead_off(void **state)
{
	T.overhead_warn_pct = 0;
	T.overhead_error_pct = 0;
	SI.overhead_pct = 80;
	check_self(&SI, &S);
	expect_none();
}

static void test_checks_self_lost_events(void **state)
{
	SI.lost_events = 3;
	check_self(&SI, &S);
	expect_one(LEVEL_WARN, "3 rare events lost (ring buffer full)");
}

static void test_checks_self_untracked(void **state)
{
	SI.untracked_threads = 2;
	check_self(&SI, &S);
	expect_one(LEVEL_WARN, "2 threads not tracked: the thread map is full (--max-threads)");
}

static void test_checks_self_all(void **state)
{
	SI.overhead_pct = 6;
	SI.lost_events = 1;
	SI.untracked_threads = 5;
	check_self(&SI, &S);
	assert_int_equal(S.level, LEVEL_ERROR);
	assert_int_equal(S.nmsg, 3);
	assert_string_equal(S.msg[0], "BPF overhead 6.00 % of a CPU > 5.00 %");
	assert_string_equal(S.msg[1], "1 rare events lost (ring buffer full)");
	assert_string_equal(S.msg[2],
			    "5 threads not tracked: the thread map is full (--max-threads)");
}

#define C(fn) cmocka_unit_test_setup(fn, setup)
#define SELF(fn) cmocka_unit_test_setup(fn, self_setup)

int main(void)
{
	const struct CMUnitTest tests[] = {
		C(test_checks_healthy_ok),
		C(test_checks_not_judged_silent),
		C(test_checks_period_from_rule),
		C(test_checks_period_from_nominal),
		C(test_checks_period_from_mean),
		C(test_checks_init_timeout_warn),
		C(test_checks_init_at_timeout_warn),
		C(test_checks_init_before_timeout),
		C(test_checks_init_with_cycles),
		C(test_checks_init_dead),
		C(test_checks_left_rt),
		C(test_checks_init_timeout_off),
		C(test_checks_init_unnamed_is_idle),
		C(test_checks_init_unnamed_before_timeout),
		C(test_checks_kthread_unnamed_not_judged),
		C(test_checks_shown_key_is_all_it_reads),
		C(test_checks_kthread_named_judged),
		C(test_checks_init_first_seen_after_now),
		C(test_checks_starve_last_cycle_after_now),
		C(test_checks_ns_since_clamps),
		C(test_checks_miss_warn),
		C(test_checks_miss_names_cause),
		C(test_checks_miss_at_rate_warn),
		C(test_checks_miss_rate_error),
		C(test_checks_overrun_without_miss),
		C(test_checks_miss_below_warn),
		C(test_checks_miss_warn_zero_off),
		C(test_checks_miss_error_rate_zero_warn_only),
		C(test_checks_miss_lifetime),
		C(test_checks_miss_no_window),
		C(test_checks_exec_p99_warn),
		C(test_checks_exec_p99_below),
		C(test_checks_exec_ewma_warn),
		C(test_checks_exec_ewma_below),
		C(test_checks_exec_period_from_rule),
		C(test_checks_exec_period_from_mean),
		C(test_checks_exec_off),
		C(test_checks_starve_warn),
		C(test_checks_starve_at_warn),
		C(test_checks_starve_error),
		C(test_checks_starve_rule_period),
		C(test_checks_starve_dead),
		C(test_checks_starve_no_period_or_cycle),
		C(test_checks_starve_error_off),
		C(test_checks_unsafe_warn_names),
		C(test_checks_facts_name_check_and_counts),
		C(test_checks_unsafe_warn_no_names),
		C(test_checks_unsafe_major_fault_error),
		C(test_checks_unsafe_reason_threshold),
		C(test_checks_unsafe_below_warn),
		C(test_checks_unsafe_warn_zero_off),
		C(test_checks_unsafe_lifetime),
		C(test_checks_unsafe_lifetime_not_named_by_window),
		C(test_checks_latency_p99_warn),
		C(test_checks_latency_max_warn),
		C(test_checks_latency_max_error),
		C(test_checks_latency_p99_and_max),
		C(test_checks_latency_zero_off),
		C(test_checks_latency_lifetime),
		C(test_checks_jitter_warn_late),
		C(test_checks_jitter_warn_early),
		C(test_checks_jitter_error),
		C(test_checks_jitter_below),
		C(test_checks_jitter_zero_off),
		C(test_checks_jitter_rule_period),
		C(test_checks_jitter_lifetime),
		C(test_checks_exc_signal),
		C(test_checks_exc_signal_mid_cycle),
		C(test_checks_exc_status),
		C(test_checks_exc_unexpected_exit),
		C(test_checks_exc_expected_exit_stale),
		C(test_checks_exc_process_ended_cleanly_stale),
		C(test_checks_exc_process_ended_badly_error),
		C(test_checks_exc_alive_ignores_exit_code),
		C(test_checks_exc_restarted),
		C(test_checks_exc_restarted_with_warn),
		C(test_checks_dead_stale_unless_worse),
		C(test_checks_sched_policy_error),
		C(test_checks_sched_prio_warn),
		C(test_checks_sched_any),
		C(test_checks_sched_dead),
		C(test_checks_several_worst_wins),
		C(test_checks_several_warn_only),
		SELF(test_checks_self_ok),
		SELF(test_checks_self_overhead_warn),
		SELF(test_checks_self_overhead_error),
		SELF(test_checks_self_overhead_unknown),
		SELF(test_checks_self_overhead_off),
		SELF(test_checks_self_lost_events),
		SELF(test_checks_self_untracked),
		SELF(test_checks_self_all),
	};

	return cmocka_run_group_tests_name("checks", tests, NULL, NULL);
}
