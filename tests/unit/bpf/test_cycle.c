// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_cycle.c - the cycle state machine (include/cycle.h) fed synthetic
 * scheduler and syscall event sequences; the model is deterministic, so
 * every number is checked exactly.
 */
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "cycle.h"

#define US	1000ULL
#define MS	1000000ULL
#define T0	(1000 * MS)	/* first requested release */

/* One traced thread plus what the kernel side would pass to the hooks. */
struct fx {
	struct rtsup_thread t;
	struct cycle_cfg cfg;
	struct rtsup_cycle out;
	__u64 minflt;		/* the task's fault counters */
	__u64 majflt;
	__s32 cpu;		/* CPU of the next switch-in */
	__s32 run_cpu;		/* CPU it runs on: its last switch-in's, seen or not */
	__u32 moved;		/* CYC_EV_* of the moves its syscalls found */
	int relative;		/* the delimiter is a relative sleep */
	struct cycle_switch_rec rec;	/* a switch-in held, as on the kernel's CPU */
	int held;		/* switch-ins held so far */
	__u32 settled;		/* CYC_EV_* of the held switch-ins applied */
};

static int fx_setup(void **state)
{
	struct fx *f = calloc(1, sizeof(*f));

	if (!f)
		return -1;
	cycle_thread_init(&f->t, 100, 100, 1);
	f->cfg.ewma_w = 102;
	*state = f;
	return 0;
}

static int fx_teardown(void **state)
{
	free(*state);
	return 0;
}

/*
 * Small wrappers: the hooks with the fixture's counters and CPU. A known
 * expected release is absolute (clock_nanosleep TIMER_ABSTIME) unless the
 * fixture says the delimiter is a relative sleep.
 */
/*
 * settle - every event of the thread first applies a switch-in held for it,
 * as the hooks do; its CYC_EV_* bits (a migration) are returned apart.
 */
static void settle(struct fx *f)
{
	f->settled |= cycle_settle(&f->t, &f->rec);
}

/* on_cpu - a syscall's hook, its held switch-in settled: where it runs now */
static void on_cpu(struct fx *f)
{
	settle(f);
	f->moved |= cycle_on_cpu(&f->t, f->run_cpu);
}

/* unseen_in - a switch-in on 'cpu' no hook saw (docs/design.md, "Unseen events") */
static void unseen_in(struct fx *f, __s32 cpu)
{
	f->run_cpu = cpu;
}

static __u32 enter(struct fx *f, __u64 now, __u64 expected)
{
	on_cpu(f);
	return cycle_delim_enter(&f->t, &f->cfg, now, expected,
				 expected && !f->relative, f->minflt,
				 f->majflt, &f->out);
}

/*
 * The kernel side reads no clock when cycle_*_timed says the time is not
 * used; these wrappers then pass a time far off, so any use of it breaks
 * the exact numbers the tests check.
 */
#define UNTIMED	(1ULL << 62)

static int untimed_out, untimed_exit;	/* how often the clock read was skipped */

static void leave(struct fx *f, __u64 now)
{
	on_cpu(f);
	if (!cycle_delim_exit_timed(&f->t, 0)) {
		now = UNTIMED;
		untimed_exit++;
	}
	cycle_delim_exit(&f->t, now, 0, f->minflt, f->majflt);
}

static __u32 sw_out(struct fx *f, __u64 now, int voluntary)
{
	settle(f);
	if (!cycle_switch_out_timed(&f->t, voluntary)) {
		now = UNTIMED;
		untimed_out++;
	}
	return cycle_switch_out(&f->t, &f->cfg, now, voluntary, f->minflt,
				f->majflt, &f->out);
}

static __u32 sw_in(struct fx *f, __u64 now)
{
	f->run_cpu = f->cpu;
	/* held like the kernel side holds it: when the thread's wakeup bit is clear */
	if (!cycle_wakeup_read(&f->t)) {
		cycle_switch_in_later(&f->rec, f->t.tid, now, f->cpu, f->minflt, f->majflt);
		f->held++;
		return 0;
	}
	return cycle_switch_in(&f->t, now, f->cpu, f->minflt, f->majflt);
}

/* running - a syscall's entry or exit: the thread runs (the hooks' test first) */
static void running(struct fx *f, __u64 now)
{
	if (cycle_switch_in_unseen(&f->t))
		cycle_running(&f->t, now, f->minflt, f->majflt);
}

static __u32 sys(struct fx *f, int unsafe)
{
	on_cpu(f);
	return cycle_syscall(&f->t, unsafe);
}


/*
 * delim_sleep - the delimiter sleeps: enter at 'now' asking for release
 * 'expected', block, wakeup at 'wake', switch-in at 'in', return at 'exit'.
 * Returns the CYC_EV_* bits of the delimiter entry.
 */
static __u32 delim_sleep(struct fx *f, __u64 now, __u64 expected, __u64 wake,
			 __u64 in, __u64 exit)
{
	__u32 ev = enter(f, now, expected);

	assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
	cycle_wakeup(&f->t, wake);
	assert_int_equal(sw_in(f, in), 0);
	leave(f, exit);
	return ev;
}

/*
 * steady - absolute sleeps, period 1 ms: release k is requested at
 * T0 + k ms, woken 2 us late, switched in 5 us late, returns 1 us later
 * and works 'exec' from the switch-in. Runs releases first..last; the
 * thread enters the delimiter of release 'first' at 'now'.
 */
#define LAT	(5 * US)
#define EXEC	(200 * US)

static __u64 rel(int k)
{
	return T0 + (__u64)k * MS;
}

static __u64 steady(struct fx *f, __u64 now, int first, int last)
{
	int k;

	for (k = first; k <= last; k++) {
		delim_sleep(f, now, rel(k), rel(k) + 2 * US, rel(k) + LAT,
			    rel(k) + LAT + 1 * US);
		now = rel(k) + LAT + EXEC;
	}
	return now;	/* next delimiter entry */
}

/* wake_up - the rest of a delimiter sleep for release k, steady timing */
static void wake_up(struct fx *f, int k)
{
	assert_int_equal(sw_out(f, rel(k) - 100 * US, 1), 0);
	cycle_wakeup(&f->t, rel(k) + 2 * US);
	assert_int_equal(sw_in(f, rel(k) + LAT), 0);
	leave(f, rel(k) + LAT + 1 * US);
}

/* wake_up_rest - wake_up() after the switch-out, the clock's offset unchanged */
static void wake_up_rest(struct fx *f, int k, __u64 r, __s64 off)
{
	cycle_wakeup(&f->t, r + 2 * US);
	assert_int_equal(sw_in(f, r + LAT), 0);
	settle(f);
	cycle_clock_at_exit(&f->t.cs, off);
	leave(f, r + LAT + 1 * US);
	(void)k;
}

/* steady absolute sleeps: period, exec, cpu and latency are exact */
static void test_cycle_steady_abs_sleep(void **state)
{
	struct fx *f = *state;
	__u64 now;
	__u32 ev;
	int k;

	/* the thread is tracked while running: its first delimiter */
	ev = delim_sleep(f, rel(0) + 300 * US, rel(1), rel(1) + 2 * US,
			 rel(1) + LAT, rel(1) + LAT + 1 * US);
	assert_int_equal(ev, 0);
	assert_int_equal(f->t.cs.mode, RTSUP_MODE_DELIM);
	assert_int_equal(f->t.cycles, 0);
	now = rel(1) + LAT + EXEC;

	for (k = 2; k <= 11; k++) {
		ev = enter(f, now, rel(k));
		assert_int_equal(ev, CYC_EV_CLOSED);
		assert_int_equal(f->out.start, rel(k - 1) + LAT);
		assert_int_equal(f->out.exec, EXEC);
		assert_int_equal(f->out.cpu, EXEC);	/* on CPU throughout */
		assert_int_equal(f->out.latency, LAT);
		assert_int_equal(f->out.nominal, MS);
		assert_int_equal(f->out.preempt, 0);
		assert_int_equal(f->out.blocks, 0);
		assert_true(f->out.flags & RTSUP_CF_HAS_LATENCY);
		assert_false(f->out.flags & (RTSUP_CF_MISS | RTSUP_CF_OVERRUN));
		if (k == 2) {
			assert_false(f->out.flags & RTSUP_CF_HAS_PERIOD);
		} else {
			assert_true(f->out.flags & RTSUP_CF_HAS_PERIOD);
			assert_int_equal(f->out.period, MS);
		}
		wake_up(f, k);		/* finish the sleep of release k */
		now = rel(k) + LAT + EXEC;
	}
	assert_int_equal(f->t.cycles, 10);
	assert_int_equal(f->t.misses, 0);
	assert_int_equal(f->t.overruns, 0);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].count, 9);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].sum, 9 * MS);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].sum, 10 * EXEC);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].count, 10);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].sum, 10 * LAT);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].max, LAT);
	assert_int_equal(f->t.vol_cs, 11);
	assert_int_equal(f->t.invol_cs, 0);
}

/* lifetime min/max of the metrics after steady cycles */
static void test_cycle_steady_lifetime_minmax(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 5);

	enter(f, now, rel(6));
	assert_int_equal(f->t.cycles, 5);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].max, MS);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].min, MS);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].min, EXEC);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].min, LAT);
	/* the interval bank, reset by cycle_epoch, is right */
	assert_int_equal(f->t.m[RTSUP_M_EXEC].win[0].min, EXEC);
}

/*
 * relative sleep: the expected release is entry + duration; it gives the
 * latency but neither a nominal period (cfg.period is used) nor a miss
 */
static void test_cycle_relative_sleep(void **state)
{
	struct fx *f = *state;
	const __u64 dur = 800 * US, work = 150 * US, lat = 3 * US;
	__u64 now = T0, s[4];
	int k;

	f->relative = 1;
	for (k = 0; k < 4; k++) {
		__u32 ev = delim_sleep(f, now, now + dur, now + dur + 1 * US,
				       now + dur + lat, now + dur + lat + 1 * US);

		s[k] = now + dur + lat;
		if (k > 0) {
			assert_int_equal(ev, CYC_EV_CLOSED);
			assert_int_equal(f->out.exec, work);
			assert_int_equal(f->out.cpu, work);
			assert_int_equal(f->out.latency, lat);
			assert_int_equal(f->out.nominal, 0);
			assert_true(f->out.flags & RTSUP_CF_HAS_LATENCY);
		}
		if (k > 1)
			assert_int_equal(f->out.period, s[k - 1] - s[k - 2]);
		now = s[k] + work;
	}
	assert_int_equal(s[3] - s[2], work + dur + lat);
	assert_int_equal(f->t.cycles, 3);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].sum, 2 * (work + dur + lat));
	assert_int_equal(f->t.overruns, 0);

	/* the configured period is the nominal one: 150 us > 100 us */
	f->cfg.period = 100 * US;
	assert_int_equal(enter(f, now, now), CYC_EV_CLOSED);	/* 0 ns sleep */
	assert_int_equal(f->out.nominal, 100 * US);
	assert_true(f->out.flags & RTSUP_CF_OVERRUN);
	assert_false(f->out.flags & RTSUP_CF_MISS);	/* never a miss */
	assert_int_equal(f->t.misses, 0);
	assert_int_equal(f->t.overruns, 1);
}

/* preemption inside a cycle: counted; CPU time excludes the time off CPU */
static void test_cycle_preempt_in_cycle(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	steady(f, rel(0), 1, 2);
	assert_int_equal(sw_out(f, s + 50 * US, 0), 0);
	assert_int_equal(sw_in(f, s + 80 * US), 0);
	assert_int_equal(enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, 200 * US);
	assert_int_equal(f->out.cpu, 170 * US);
	assert_int_equal(f->out.preempt, 1);
	assert_int_equal(f->out.blocks, 0);
	assert_int_equal(f->t.invol_cs, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 0);
	assert_int_equal(f->t.unsafe[RTSUP_U_MIGRATE], 0);
}

/* voluntary block inside a cycle: a block, unsafe, CYC_EV_BLOCK */
static void test_cycle_block_in_cycle(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	steady(f, rel(0), 1, 2);
	assert_int_equal(sw_out(f, s + 50 * US, 1), CYC_EV_BLOCK);
	cycle_wakeup(&f->t, s + 90 * US);
	assert_int_equal(sw_in(f, s + 100 * US), 0);
	assert_int_equal(enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, 200 * US);
	assert_int_equal(f->out.cpu, 150 * US);
	assert_int_equal(f->out.blocks, 1);
	assert_int_equal(f->out.preempt, 0);
	assert_int_equal(f->out.latency, LAT);	/* the block's wakeup is not it */
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 1);
	assert_int_equal(f->t.cycles, 2);
}

/* which switch-outs are a wait: sleeping states, not a PREEMPT_RT spinlock's */
static void test_cycle_switch_voluntary_states(void **state)
{
	(void)state;
	assert_false(cycle_switch_voluntary(0));		/* TASK_RUNNING: preempted */
	assert_true(cycle_switch_voluntary(1));			/* TASK_INTERRUPTIBLE */
	assert_true(cycle_switch_voluntary(2));			/* TASK_UNINTERRUPTIBLE */
	assert_true(cycle_switch_voluntary(0x402));		/* TASK_IDLE */
	assert_false(cycle_switch_voluntary(CYC_TASK_RTLOCK_WAIT));
}

/* a wait for a PREEMPT_RT spinlock inside a cycle: no block, no unsafe event */
static void test_cycle_rtlock_wait_in_cycle(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	steady(f, rel(0), 1, 2);
	assert_int_equal(sw_out(f, s + 50 * US, cycle_switch_voluntary(CYC_TASK_RTLOCK_WAIT)), 0);
	cycle_wakeup(&f->t, s + 90 * US);
	assert_int_equal(sw_in(f, s + 100 * US), 0);
	assert_int_equal(enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.blocks, 0);
	assert_int_equal(f->out.preempt, 1);
	assert_int_equal(f->out.cpu, 150 * US);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 0);
}

/* deadline miss with an overrun: exec 1.5 ms in a 1 ms period */
static void test_cycle_miss_overrun(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT, d = s + 1500 * US;
	__u32 ev;

	steady(f, rel(0), 1, 2);
	ev = enter(f, d, rel(3));	/* release 3 is already past */
	assert_int_equal(ev, CYC_EV_CLOSED | CYC_EV_MISS);
	assert_true(f->out.flags & RTSUP_CF_MISS);
	assert_true(f->out.flags & RTSUP_CF_OVERRUN);
	assert_int_equal(f->out.exec, 1500 * US);
	assert_int_equal(f->out.nominal, MS);
	assert_int_equal(f->t.misses, 1);
	assert_int_equal(f->t.overruns, 1);
	/* the delimiter returns at once: the next cycle starts on its exit */
	leave(f, d + 2 * US);
	assert_int_equal(f->t.cs.start, d + 2 * US);
	ev = enter(f, d + 102 * US, rel(4));
	assert_int_equal(ev, CYC_EV_CLOSED);
	assert_int_equal(f->out.start, d + 2 * US);
	assert_int_equal(f->out.period, d + 2 * US - s);
	assert_int_equal(f->out.latency, d + 2 * US - rel(3));
	assert_int_equal(f->out.exec, 100 * US);
	assert_false(f->out.flags & (RTSUP_CF_MISS | RTSUP_CF_OVERRUN));
	assert_int_equal(f->t.misses, 1);
	assert_int_equal(f->t.overruns, 1);
}

/*
 * The cycle's own period judges its overrun: the distance that released it,
 * not the one it asks for next. A loop that ends with a long sleep (a
 * generator's --hold, a loop going idle) had its last overrun hidden.
 */
static void test_cycle_overrun_judged_by_its_own_release(void **state)
{
	struct fx *f = *state;
	__u64 d = rel(2) + LAT + 1500 * US;

	steady(f, rel(0), 1, 2);
	assert_int_equal(enter(f, d, rel(3) + 3600000 * MS), CYC_EV_CLOSED);
	assert_int_equal(f->out.nominal, MS);
	assert_true(f->out.flags & RTSUP_CF_OVERRUN);
	assert_int_equal(f->t.overruns, 1);
	/* the cycle it released has the long one */
	wake_up(f, 3 + 3600000);
	assert_int_equal(enter(f, rel(3 + 3600000) + LAT + 2 * MS, rel(3 + 3600010)),
			 CYC_EV_CLOSED);
	assert_int_equal(f->out.nominal, 3600001 * MS);
	assert_false(f->out.flags & RTSUP_CF_OVERRUN);
}

/* a late start misses the next release without an overrun */
static void test_cycle_miss_without_overrun(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + 900 * US;

	steady(f, rel(0), 1, 1);
	delim_sleep(f, rel(1) + LAT + EXEC, rel(2), rel(2) + 1 * US, s, s + 1 * US);
	assert_int_equal(enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED | CYC_EV_MISS);
	assert_int_equal(f->out.latency, 900 * US);
	assert_true(f->out.flags & RTSUP_CF_MISS);
	assert_false(f->out.flags & RTSUP_CF_OVERRUN);
	assert_int_equal(f->t.misses, 1);
	assert_int_equal(f->t.overruns, 0);
}

/* the miss boundary: entering at the requested release is already late */
static void test_cycle_miss_boundary(void **state)
{
	struct fx *f = *state;

	steady(f, rel(0), 1, 2);
	assert_int_equal(enter(f, rel(3) - 1, rel(3)), CYC_EV_CLOSED);
	assert_false(f->out.flags & RTSUP_CF_MISS);
	wake_up(f, 3);
	assert_int_equal(enter(f, rel(4), rel(4)), CYC_EV_CLOSED | CYC_EV_MISS);
	assert_true(f->out.flags & RTSUP_CF_MISS);
	assert_int_equal(f->t.misses, 1);
}

/*
 * returned done before the requested release (a release converted from
 * another clock a few us off): latency 0, not negative; the cycle starts
 * at the return, not at the switch-in before it
 */
static void test_cycle_early_release(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 1);

	delim_sleep(f, now, rel(2), rel(2) - 20 * US, rel(2) - 10 * US,
		    rel(2) - 9 * US);
	assert_int_equal(enter(f, rel(2) + EXEC, rel(3)), CYC_EV_CLOSED);
	assert_true(f->out.flags & RTSUP_CF_HAS_LATENCY);
	assert_int_equal(f->out.latency, 0);
	assert_int_equal(f->out.exec, EXEC + 9 * US);
}

/* a delimiter that does not sleep: the cycle starts at its exit */
static void test_cycle_delim_no_sleep(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 2);

	/* release 3 requested on time, but the call returns at once */
	assert_int_equal(enter(f, now, rel(3)), CYC_EV_CLOSED);
	leave(f, now + 4 * US);
	assert_int_equal(f->t.cs.start, now + 4 * US);
	assert_int_equal(f->t.cs.run_since, now + 4 * US);
	assert_int_equal(enter(f, now + 54 * US, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, now + 4 * US);
	assert_int_equal(f->out.exec, 50 * US);
	assert_int_equal(f->out.cpu, 50 * US);
	assert_int_equal(f->out.period, now + 4 * US - (rel(2) + LAT));
	assert_int_equal(f->t.cycles, 3);
	assert_int_equal(f->t.vol_cs, 2);
}

/*
 * exit_missed - a hooked syscall's entry: the per-syscall hooks' check that
 * the thread left its delimiter (the kernel may skip the return's stub)
 */
static int exit_missed(struct fx *f)
{
	on_cpu(f);
	return cycle_exit_missed(&f->t, f->minflt, f->majflt);
}

/* a delimiter return the hooks skipped: released at its switch-in all the same */
static void test_cycle_exit_missed_released_at_switch_in(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 2);

	assert_int_equal(exit_missed(f), 0);	/* it returned: nothing missed */
	assert_int_equal(enter(f, now, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
	cycle_wakeup(&f->t, rel(3) + 2 * US);
	assert_int_equal(sw_in(f, rel(3) + LAT), 0);
	/* no leave(): its next syscall is the next delimiter entry */
	now = rel(3) + LAT + EXEC;
	assert_int_equal(exit_missed(f), 1);
	assert_int_equal(enter(f, now, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, rel(3) + LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.cpu, EXEC);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.period, MS);
	assert_int_equal(f->out.blocks, 0);
	assert_int_equal(f->t.cycles, 3);
}

/* a skipped return with no switch-in: that cycle and the next period are lost */
static void test_cycle_exit_missed_without_switch_in(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 2);

	/* release 3 is past at the entry: no sleep, and its return unseen */
	assert_int_equal(enter(f, now, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(exit_missed(f), 1);
	assert_false(f->t.cs.in_delim);
	/* a cycle closes nothing it never began */
	assert_int_equal(enter(f, now + 50 * US, rel(4)), 0);
	wake_up(f, 4);
	assert_int_equal(enter(f, rel(4) + LAT + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_false(f->out.flags & RTSUP_CF_HAS_PERIOD);	/* it would span two */
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->t.cycles, 3);
}

/*
 * Per-syscall hooks whose delimiter entry the kernel skipped (its stub's
 * recursion check, docs/design.md "Runs the kernel skips"). DELIM_NR is
 * the thread's delimiter syscall; the hooks tell the state machine which
 * syscall they saw enter (cycle_sys_seen) and read the one a thread
 * sleeps in from its registers (+ 1).
 */
#define DELIM_NR	230

/* per_enter - the delimiter's entry, seen: as on_sys_enter with per-syscall hooks */
static __u32 per_enter(struct fx *f, __u64 now, __u64 expected)
{
	__u32 ev;

	exit_missed(f);
	ev = enter(f, now, expected);
	cycle_sys_seen(&f->t.cs, DELIM_NR, 1);
	return ev;
}

/* per_out - a voluntary switch-out in syscall 'sys' (+ 1), as switch_out_state judges it */
static __u32 per_out(struct fx *f, __u64 now, __u32 sys)
{
	enum cycle_out_path path;

	settle(f);
	path = cycle_switch_out_path(&f->t.cs, 1);
	if (path == CYC_OUT_BLOCK &&
	    cycle_entry_skipped(&f->t, sys, now, f->minflt, f->majflt))
		path = CYC_OUT_DELIM_SLEEP;
	return cycle_switch_out_on(&f->t, &f->cfg, path, now, 1, f->minflt, f->majflt,
				   &f->out);
}

/*
 * per_leave - the delimiter returns (seen), the requested release read
 * from its arguments: the late entry first if its entry went unseen
 * (on_sys_exit's late_entry). Returns the late entry's CYC_EV_* bits.
 */
static __u32 per_leave(struct fx *f, __u64 now, __u64 expected)
{
	__u32 ev = 0;

	on_cpu(f);
	f->t.cs.cur_sys = 0;
	if (f->t.cs.flags & RTSUP_CS_ENTRY_LATE)
		ev = cycle_late_entry(&f->t, &f->cfg, expected, 1, &f->out);
	leave(f, now);
	return ev;
}

/* per_steady - steady()'s cycles through the per-syscall hooks */
static __u64 per_steady(struct fx *f, __u64 now, int first, int last)
{
	int k;

	for (k = first; k <= last; k++) {
		per_enter(f, now, rel(k));
		assert_int_equal(per_out(f, now + 1 * US, DELIM_NR + 1), 0);
		cycle_wakeup(&f->t, rel(k) + 2 * US);
		assert_int_equal(sw_in(f, rel(k) + LAT), 0);
		assert_int_equal(per_leave(f, rel(k) + LAT + 1 * US, rel(k)), 0);
		now = rel(k) + LAT + EXEC;
	}
	return now;
}

/*
 * the delimiter's entry skipped: its sleep is no block in the cycle but
 * the entry, the cycle closed at it once the return says the release
 * (CI: 1 or 2 such "blocks" in clock_nanosleep a run in the RT guests)
 */
static void test_cycle_entry_skipped_sleep_is_the_entry(void **state)
{
	struct fx *f = *state;
	__u64 now = per_steady(f, rel(0), 1, 2);

	assert_int_equal(f->t.cycles, 1);
	/* release 3's entry unseen: it sleeps in its delimiter, "inside" cycle 2 */
	f->minflt = 7;
	assert_int_equal(per_out(f, now, DELIM_NR + 1), 0);
	assert_true(f->t.cs.in_delim);
	assert_int_equal(f->t.cs.blocks, 0);
	cycle_wakeup(&f->t, rel(3) + 2 * US);
	assert_int_equal(sw_in(f, rel(3) + LAT), 0);
	assert_int_equal(per_leave(f, rel(3) + LAT + 1 * US, rel(3)),
			 CYC_EV_CLOSED | CYC_EV_FAULTS);
	/* cycle 2, closed at its sleep */
	assert_int_equal(f->out.start, rel(2) + LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.cpu, EXEC);
	assert_int_equal(f->out.blocks, 0);
	assert_int_equal(f->out.minflt, 7);
	assert_int_equal(f->out.period, MS);
	assert_int_equal(f->t.cycles, 2);
	assert_false(f->t.cs.flags & RTSUP_CS_ENTRY_LATE);
	/* cycle 3 began at its switch-in */
	assert_int_equal(f->t.cs.start, rel(3) + LAT);
	f->minflt = 9;	/* the next cycle's */
	assert_int_equal(per_enter(f, rel(3) + LAT + EXEC, rel(4)),
			 CYC_EV_CLOSED | CYC_EV_FAULTS);
	assert_int_equal(f->out.start, rel(3) + LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.period, MS);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.minflt, 2);
	assert_int_equal(f->out.blocks, 0);
	assert_int_equal(f->t.cycles, 3);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 0);
}

/* a wait whose entry was seen, or in another syscall, stays a block */
static void test_cycle_entry_seen_block_stays(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	per_steady(f, rel(0), 1, 2);
	/* a futex wait (seen or not: no delimiter) */
	assert_int_equal(per_out(f, s + 50 * US, 202 + 1), CYC_EV_BLOCK);
	assert_int_equal(sw_in(f, s + 100 * US), 0);
	/* a relative sleep inside the absolute loop: seen, no boundary */
	cycle_sys_seen(&f->t.cs, DELIM_NR, 0);
	assert_int_equal(per_out(f, s + 150 * US, DELIM_NR + 1), CYC_EV_BLOCK);
	assert_int_equal(sw_in(f, s + 160 * US), 0);
	assert_int_equal(per_enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.blocks, 2);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 2);
}

/* taken for the entry, no boundary after all (a relative sleep, its arguments say): a block */
static void test_cycle_entry_skipped_no_boundary(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	per_steady(f, rel(0), 1, 2);
	assert_int_equal(per_out(f, s + 50 * US, DELIM_NR + 1), 0);
	assert_int_equal(sw_in(f, s + 100 * US), 0);
	on_cpu(f);
	assert_int_equal(cycle_late_block(&f->t), CYC_EV_BLOCK);
	assert_false(f->t.cs.in_delim);
	assert_int_equal(per_enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, s);
	assert_int_equal(f->out.exec, 200 * US);
	assert_int_equal(f->out.cpu, 150 * US);
	assert_int_equal(f->out.blocks, 1);
	assert_int_equal(f->t.cycles, 2);
}

/* its return skipped as well: the cycle it would close is lost, and the next period */
static void test_cycle_entry_and_exit_skipped(void **state)
{
	struct fx *f = *state;
	__u64 now = per_steady(f, rel(0), 1, 2);

	assert_int_equal(per_out(f, now, DELIM_NR + 1), 0);
	assert_int_equal(sw_in(f, rel(3) + LAT), 0);
	/* no return seen: the next entry finds it in its delimiter, released at its switch-in */
	assert_int_equal(per_enter(f, rel(3) + LAT + EXEC, rel(4)), CYC_EV_CLOSED);
	assert_false(f->t.cs.flags & RTSUP_CS_ENTRY_LATE);
	assert_int_equal(f->out.start, rel(3) + LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_false(f->out.flags & RTSUP_CF_HAS_PERIOD);	/* it would span two */
	assert_int_equal(f->t.cycles, 2);	/* cycle 2 is lost */
	wake_up(f, 4);
	assert_int_equal(per_enter(f, rel(4) + LAT + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->out.period, MS);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 0);
}

/* migration inside a cycle counts as unsafe; at the release it does not */
static void test_cycle_migration(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	steady(f, rel(0), 1, 2);	/* on CPU 0 so far */
	assert_int_equal(f->t.migrations, 0);
	assert_int_equal(sw_out(f, s + 50 * US, 0), 0);
	f->cpu = 1;
	/* held on its CPU (no lookup), applied at the thread's next event */
	assert_int_equal(sw_in(f, s + 60 * US), 0);
	assert_int_equal(f->held, 3);	/* the two steady releases and this one */
	assert_int_equal(f->t.migrations, 0);
	settle(f);
	assert_int_equal(f->settled, CYC_EV_MIGRATE);
	assert_int_equal(f->t.migrations, 1);
	/* unsafe counts are folded in when the cycle is whole */
	assert_int_equal(f->t.unsafe[RTSUP_U_MIGRATE], 0);
	/* woken on CPU 2 for release 3: a migration, not an unsafe one */
	f->cpu = 2;
	assert_int_equal(delim_sleep(f, s + 200 * US, rel(3), rel(3) + 2 * US,
				     rel(3) + LAT, rel(3) + LAT + 1 * US),
			 CYC_EV_CLOSED);
	assert_int_equal(f->out.migrations, 1);
	assert_int_equal(f->out.cpu, 190 * US);
	assert_int_equal(f->t.migrations, 2);
	assert_int_equal(f->t.unsafe[RTSUP_U_MIGRATE], 1);
	assert_int_equal(f->t.cs.last_cpu, 2);
}

/*
 * A move whose switch-in no hook saw: its next syscall finds the thread on
 * another CPU. Inside a cycle it is the cycle's migration; while it slept
 * (found at the delimiter's return), only the thread's, and the cycle after
 * does not count it again.
 */
static void test_cycle_migration_unseen_switch_in(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	steady(f, rel(0), 1, 2);	/* on CPU 0 */
	assert_int_equal(sw_out(f, s + 50 * US, 0), 0);
	unseen_in(f, 1);		/* preempted, moved, back on CPU 1 unseen */
	assert_int_equal(sys(f, 0), 0);
	assert_int_equal(f->moved, CYC_EV_MIGRATE);
	assert_int_equal(f->t.migrations, 1);
	assert_int_equal(f->t.cs.last_cpu, 1);
	f->moved = 0;
	assert_int_equal(sys(f, 0), 0);		/* still there: nothing more */
	assert_int_equal(f->moved, 0);
	/* release 3 on CPU 1: the cycle of release 2 closes with its move */
	f->cpu = 1;
	assert_int_equal(delim_sleep(f, s + 200 * US, rel(3), rel(3) + 2 * US,
				     rel(3) + LAT, rel(3) + LAT + 1 * US),
			 CYC_EV_CLOSED);
	assert_int_equal(f->out.migrations, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_MIGRATE], 1);
	/* it sleeps, wakes on CPU 0 unseen: found at the return, no cycle's */
	assert_int_equal(enter(f, rel(3) + LAT + EXEC, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(f->out.migrations, 0);
	assert_int_equal(sw_out(f, rel(3) + LAT + EXEC + 1 * US, 1), 0);
	cycle_wakeup(&f->t, rel(4) + 2 * US);
	unseen_in(f, 0);
	leave(f, rel(4) + LAT + 1 * US);
	assert_int_equal(f->moved, 0);
	assert_int_equal(f->t.migrations, 2);
	assert_int_equal(f->t.cs.last_cpu, 0);
	assert_int_equal(sys(f, 0), 0);
	assert_int_equal(f->moved, 0);
	assert_int_equal(enter(f, rel(4) + LAT + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->out.migrations, 0);
	assert_int_equal(f->t.unsafe[RTSUP_U_MIGRATE], 1);
}

/* unsafe syscalls count inside a cycle only, never inside the delimiter */
static void test_cycle_unsafe_syscall(void **state)
{
	struct fx *f = *state;
	__u64 now;

	/* before the first cycle: nothing runs, nothing counts */
	assert_int_equal(sys(f, 1), 0);
	now = steady(f, rel(0), 1, 2);
	assert_int_equal(sys(f, 1), CYC_EV_UNSAFE);
	assert_int_equal(sys(f, 0), 0);
	assert_int_equal(enter(f, now, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.syscalls, 2);
	assert_int_equal(f->out.unsafe_sys, 1);
	/* inside the delimiter */
	assert_int_equal(sys(f, 1), 0);
	assert_int_equal(f->t.syscalls, 2);
	assert_int_equal(f->t.unsafe[RTSUP_U_SYSCALL], 1);
	wake_up(f, 3);
	assert_int_equal(enter(f, rel(3) + LAT + EXEC, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(f->out.syscalls, 0);
	assert_int_equal(f->out.unsafe_sys, 0);
}

/* page faults: the difference of the counters at cycle start and end */
static void test_cycle_page_faults(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 1);
	__u32 ev;

	f->minflt = 3;			/* faults of the running cycle */
	ev = enter(f, now, rel(2));
	assert_int_equal(ev, CYC_EV_CLOSED | CYC_EV_FAULTS);
	assert_int_equal(f->out.minflt, 3);
	assert_int_equal(f->out.majflt, 0);
	/* faults inside the delimiter are not a cycle's */
	f->minflt = 10;
	f->majflt = 2;
	wake_up(f, 2);
	f->minflt = 14;
	f->majflt = 3;
	ev = enter(f, rel(2) + LAT + EXEC, rel(3));
	assert_int_equal(ev, CYC_EV_CLOSED | CYC_EV_FAULTS);
	assert_int_equal(f->out.minflt, 4);
	assert_int_equal(f->out.majflt, 1);
	assert_int_equal(f->t.minflt, 7);
	assert_int_equal(f->t.majflt, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_MINFLT], 7);
	assert_int_equal(f->t.unsafe[RTSUP_U_MAJFLT], 1);
	/* counters move while asleep only: the next cycle has none */
	f->minflt = 20;
	wake_up(f, 3);
	ev = enter(f, rel(3) + LAT + EXEC, rel(4));
	assert_int_equal(ev, CYC_EV_CLOSED);
	assert_int_equal(f->out.minflt, 0);
	assert_int_equal(f->t.minflt, 7);
}

/* activation mode: wakeup -> switch-in starts, voluntary switch-out ends */
static void test_cycle_activation_mode(void **state)
{
	struct fx *f = *state;
	__u64 w1 = T0, s1 = w1 + 3 * US, w2 = T0 + 500 * US, s2 = w2 + 4 * US;
	__u64 s3 = T0 + 900 * US;

	cycle_wakeup(&f->t, w1);
	assert_int_equal(sw_in(f, s1), 0);
	assert_int_equal(f->t.cs.mode, RTSUP_MODE_ACT);
	assert_int_equal(sw_out(f, s1 + 100 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, s1);
	assert_int_equal(f->out.exec, 100 * US);
	assert_int_equal(f->out.cpu, 100 * US);
	assert_int_equal(f->out.latency, 3 * US);
	assert_int_equal(f->out.flags, RTSUP_CF_HAS_LATENCY);

	cycle_wakeup(&f->t, w2);
	sw_in(f, s2);
	assert_int_equal(sw_out(f, s2 + 120 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.period, s2 - s1);
	assert_int_equal(f->out.latency, 4 * US);
	assert_int_equal(f->out.flags, RTSUP_CF_HAS_LATENCY | RTSUP_CF_HAS_PERIOD);

	/* a preemption does not end an activation; nominal from cfg.period */
	f->cfg.period = 45 * US;
	cycle_wakeup(&f->t, s3 - 1 * US);
	sw_in(f, s3);
	assert_int_equal(sw_out(f, s3 + 10 * US, 0), 0);
	sw_in(f, s3 + 20 * US);
	assert_int_equal(sw_out(f, s3 + 50 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, 50 * US);
	assert_int_equal(f->out.cpu, 40 * US);
	assert_int_equal(f->out.preempt, 1);
	assert_int_equal(f->out.nominal, 45 * US);
	assert_true(f->out.flags & RTSUP_CF_OVERRUN);
	assert_int_equal(f->t.cycles, 3);
	assert_int_equal(f->t.overruns, 1);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].sum, 3 * US + 4 * US + 1 * US);
}

/*
 * No tracepoint fires while some tasks are current: an activation woken
 * and switched in from one shows only its own syscalls. It begins at the
 * first of them, without a latency, and is counted as unseen.
 */
static void test_cycle_activation_unseen_switch_in(void **state)
{
	struct fx *f = *state;
	__u64 s1 = T0 + 3 * US, x = T0 + 1 * MS + 9 * US;

	cycle_wakeup(&f->t, T0);
	sw_in(f, s1);
	running(f, s1 + 1 * US);	/* seen switched in: nothing to do */
	assert_int_equal(f->t.cs.start, s1);
	assert_int_equal(sw_out(f, s1 + 100 * US, 1), CYC_EV_CLOSED);

	/* no wakeup, no switch-in: its syscall's exit is the first event */
	running(f, x);
	assert_int_equal(f->t.unseen_in, 1);
	assert_int_equal(sys(f, 1), CYC_EV_UNSAFE);
	running(f, x + 5 * US);		/* once only */
	assert_int_equal(sw_out(f, x + 80 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, x);
	assert_int_equal(f->out.exec, 80 * US);
	assert_int_equal(f->out.cpu, 80 * US);
	assert_int_equal(f->out.period, x - s1);
	assert_int_equal(f->out.unsafe_sys, 1);
	assert_int_equal(f->out.flags, RTSUP_CF_HAS_PERIOD);	/* no latency */
	assert_int_equal(f->t.cycles, 2);
	assert_int_equal(f->t.unseen_in, 1);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].count, 1);
}

/* a wakeup from before the previous activation is not this one's release */
static void test_cycle_activation_stale_wakeup(void **state)
{
	struct fx *f = *state;
	__u64 s1 = T0 + 3 * US, s2 = T0 + 1 * MS + 6 * US;

	cycle_wakeup(&f->t, T0);
	sw_in(f, s1);
	sw_out(f, s1 + 100 * US, 1);
	/* its wakeup went unseen, its switch-in did not */
	sw_in(f, s2);
	assert_int_equal(sw_out(f, s2 + 100 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.flags, RTSUP_CF_HAS_PERIOD);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].count, 1);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].sum, 3 * US);
	assert_int_equal(f->t.unseen_in, 0);
}

/* preempted, then switched in unseen: the CPU time counts from its syscall */
static void test_cycle_activation_unseen_resume(void **state)
{
	struct fx *f = *state;
	__u64 s1 = T0 + 3 * US;

	cycle_wakeup(&f->t, T0);
	sw_in(f, s1);
	assert_int_equal(sw_out(f, s1 + 30 * US, 0), 0);
	running(f, s1 + 70 * US);
	assert_int_equal(sw_out(f, s1 + 100 * US, 1), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, s1);
	assert_int_equal(f->out.exec, 100 * US);
	assert_int_equal(f->out.cpu, 30 * US + 30 * US);
	assert_int_equal(f->out.preempt, 1);
	assert_int_equal(f->t.unseen_in, 0);
}

/*
 * A thread found running (no switch-in seen yet) is in no mode: its
 * syscalls begin nothing, its first block ends nothing; and a delimiter
 * thread's syscalls are not activations.
 */
static void test_cycle_unseen_needs_activation_mode(void **state)
{
	struct fx *f = *state;

	running(f, T0);
	assert_int_equal(f->t.cs.start, 0);
	assert_int_equal(sw_out(f, T0 + 10 * US, 1), 0);
	assert_int_equal(f->t.cycles, 0);

	steady(f, T0 + 500 * US, 1, 2);
	assert_int_equal(f->t.cs.mode, RTSUP_MODE_DELIM);
	running(f, rel(2) + 50 * US);
	assert_int_equal(f->t.unseen_in, 0);
	assert_int_equal(f->t.cs.start, rel(2) + LAT);
}

/* the first delimiter after activations drops the start-up statistics */
static void test_cycle_activation_then_delim_resets(void **state)
{
	struct fx *f = *state;
	__u64 s = T0 + 500 * US;
	__u32 ev;

	cycle_wakeup(&f->t, T0);
	sw_in(f, T0 + 3 * US);
	assert_int_equal(sys(f, 1), CYC_EV_UNSAFE);
	sw_out(f, T0 + 100 * US, 1);
	cycle_wakeup(&f->t, s - 1 * US);
	sw_in(f, s);			/* an activation is running */
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_SYSCALL], 1);

	ev = enter(f, s + 50 * US, rel(1));
	assert_int_equal(ev, CYC_EV_RESET);	/* no cycle closed */
	assert_int_equal(f->t.cs.mode, RTSUP_MODE_DELIM);
	assert_int_equal(f->t.cycles, 0);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].count, 0);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].count, 0);
	assert_int_equal(f->t.unsafe[RTSUP_U_SYSCALL], 0);
	assert_int_equal(f->t.syscalls, 0);

	sw_out(f, s + 51 * US, 1);
	cycle_wakeup(&f->t, rel(1) + 2 * US);
	sw_in(f, rel(1) + LAT);
	leave(f, rel(1) + LAT + 1 * US);
	ev = enter(f, rel(1) + LAT + EXEC, rel(2));
	assert_int_equal(ev, CYC_EV_CLOSED);	/* no second reset */
	assert_false(f->out.flags & RTSUP_CF_HAS_PERIOD);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].count, 1);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].count, 0);
}

/* the lifetime min after the start-up statistics were dropped */
static void test_cycle_reset_lifetime_min(void **state)
{
	struct fx *f = *state;
	__u64 now;

	cycle_wakeup(&f->t, T0 - 10 * MS);
	sw_in(f, T0 - 10 * MS + 3 * US);
	sw_out(f, T0 - 10 * MS + 50 * US, 1);
	cycle_wakeup(&f->t, T0 - 5 * MS);
	sw_in(f, T0 - 5 * MS);
	assert_int_equal(enter(f, T0 - 4 * MS, rel(1)), CYC_EV_RESET);
	sw_out(f, T0 - 4 * MS + 1 * US, 1);
	cycle_wakeup(&f->t, rel(1) + 2 * US);
	sw_in(f, rel(1) + LAT);
	leave(f, rel(1) + LAT + 1 * US);
	now = steady(f, rel(1) + LAT + EXEC, 2, 3);
	enter(f, now, rel(4));
	assert_int_equal(f->t.cycles, 3);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].min, EXEC);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].max, EXEC);
}

/* a thread exiting mid-cycle: the cycle is lost, its faults are kept apart */
static void test_cycle_exit_mid_cycle(void **state)
{
	struct fx *f = *state;
	__u64 s = rel(2) + LAT;

	enter(f, steady(f, rel(0), 1, 1), rel(2));
	f->minflt = 10;			/* counters at the start of release 2 */
	wake_up(f, 2);
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.cs.start, s);
	settle(f);
	cycle_exit(&f->t, s + 100 * US, 15, 1);
	assert_int_equal(f->t.exited, s + 100 * US);
	assert_int_equal(f->t.exit_mid_cycle, 1);
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].count, 1);
	/* the teardown is not the loop: not in the totals, but shown apart */
	assert_int_equal(f->t.minflt, 0);
	assert_int_equal(f->t.unsafe[RTSUP_U_MINFLT], 0);
	assert_int_equal(f->t.exit_unsafe[RTSUP_U_MINFLT], 5);
	assert_int_equal(f->t.exit_unsafe[RTSUP_U_MAJFLT], 1);
	assert_int_equal(f->t.cs.start, 0);
}

/* a thread exiting inside its delimiter is not mid-cycle */
static void test_cycle_exit_in_delim(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 2);

	enter(f, now, rel(3));
	settle(f);
	cycle_exit(&f->t, now + 10 * US, 50, 5);
	assert_int_equal(f->t.exit_mid_cycle, 0);
	assert_int_equal(f->t.exited, now + 10 * US);
	assert_int_equal(f->t.cycles, 2);
	assert_int_equal(f->t.minflt, 0);
	assert_int_equal(f->t.cs.in_delim, 0);
}

/* run_exec - one steady-ish cycle of release k with the given exec */
static void run_exec(struct fx *f, int k, __u64 exec)
{
	delim_sleep(f, rel(k - 1) + LAT + exec, rel(k), rel(k) + 2 * US,
		    rel(k) + LAT, rel(k) + LAT + 1 * US);
}

/* interval banks: reset once per new epoch, other bank kept */
static void test_cycle_epoch_banks(void **state)
{
	struct fx *f = *state;
	struct rtsup_metric_stats *e = &f->t.m[RTSUP_M_EXEC];

	steady(f, rel(0), 1, 1);
	f->cfg.epoch = 0;
	run_exec(f, 2, 200 * US);	/* closes release 1: exec 200 */
	run_exec(f, 3, 300 * US);	/* closes release 2: exec 300 */
	assert_int_equal(f->t.epoch, 0);
	assert_int_equal(e->win[0].min, 200 * US);
	assert_int_equal(e->win[0].max, 300 * US);

	f->cfg.epoch = 1;
	run_exec(f, 4, 250 * US);
	assert_int_equal(f->t.epoch, 1);
	assert_int_equal(e->win[1].min, 250 * US);
	assert_int_equal(e->win[1].max, 250 * US);
	run_exec(f, 5, 260 * US);	/* same epoch: no reset */
	assert_int_equal(e->win[1].min, 250 * US);
	assert_int_equal(e->win[1].max, 260 * US);
	assert_int_equal(e->win[0].min, 200 * US);	/* untouched */
	assert_int_equal(e->win[0].max, 300 * US);

	f->cfg.epoch = 2;
	run_exec(f, 6, 400 * US);
	assert_int_equal(e->win[0].min, 400 * US);
	assert_int_equal(e->win[0].max, 400 * US);
	assert_int_equal(e->win[1].min, 250 * US);
	assert_int_equal(e->win[1].max, 260 * US);
	assert_int_equal(e->max, 400 * US);
	/* every metric's bank was reset, not only exec's */
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].win[0].min, LAT);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].win[0].max, MS);
}

/* unknown expected release (epoll-like): latency from the wakeup */
static void test_cycle_unknown_expected_uses_wakeup(void **state)
{
	struct fx *f = *state;
	__u64 now = T0;
	int k;

	for (k = 0; k < 3; k++) {
		__u32 ev = delim_sleep(f, now, 0, now + 700 * US,
				       now + 707 * US, now + 708 * US);

		if (k > 0) {
			assert_int_equal(ev, CYC_EV_CLOSED);
			assert_int_equal(f->out.latency, 7 * US);
			assert_true(f->out.flags & RTSUP_CF_HAS_LATENCY);
			assert_int_equal(f->out.nominal, 0);	/* no cfg.period */
			assert_false(f->out.flags & (RTSUP_CF_MISS | RTSUP_CF_OVERRUN));
			assert_int_equal(f->out.exec, 100 * US);
		}
		now += 807 * US;
	}
	assert_int_equal(f->out.period, 807 * US);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].count, 2);
	/* epoll returning at once (data ready): no wakeup, no latency */
	enter(f, now, 0);
	leave(f, now + 2 * US);
	enter(f, now + 52 * US, 0);
	assert_false(f->out.flags & RTSUP_CF_HAS_LATENCY);
	assert_int_equal(f->out.start, now + 2 * US);
}

/*
 * preempted inside the delimiter after the release switch-in, before the
 * syscall returns: the cycle starts at the release, but the time off CPU
 * is not CPU time.
 */
static void test_cycle_preempt_in_delim_after_release(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 1), s = rel(2) + LAT;

	enter(f, now, rel(2));
	sw_out(f, now + 1 * US, 1);
	cycle_wakeup(&f->t, rel(2) + 2 * US);
	sw_in(f, s);
	sw_out(f, s + 1 * US, 0);		/* preempted before the return */
	sw_in(f, s + 31 * US);
	leave(f, s + 32 * US);
	assert_int_equal(f->t.cs.start, s);	/* release: first switch-in */
	assert_int_equal(enter(f, s + 200 * US, rel(3)), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, 200 * US);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.cpu, 170 * US);
}

/*
 * a periodic thread's steady loop: its switch-out into the delimiter's
 * sleep and the delimiter's return need no clock read, yet every number
 * is exact (the wrappers pass UNTIMED then)
 */
static void test_cycle_steady_loop_reads_clock_once_per_switch_in(void **state)
{
	struct fx *f = *state;
	__u64 now;

	untimed_out = untimed_exit = 0;
	now = steady(f, rel(0), 1, 10);
	assert_int_equal(untimed_out, 10);
	assert_int_equal(untimed_exit, 10);
	assert_int_equal(enter(f, now, rel(11)), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.cpu, EXEC);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.period, MS);
	/* going to sleep in the delimiter: no clock; a return without sleep: clock */
	assert_false(cycle_switch_out_timed(&f->t, 1));
	assert_true(cycle_delim_exit_timed(&f->t, 0));
	leave(f, now + 1 * US);
	/* inside a cycle, a preemption and a block both read the clock */
	assert_true(cycle_switch_out_timed(&f->t, 0));
	assert_true(cycle_switch_out_timed(&f->t, 1));
	assert_false(cycle_delim_exit_timed(&f->t, 0));
}

/*
 * interrupted - the delimiter sleeping for release k is woken by a signal
 * at 'sig' (switched in 3 us later) and returns EINTR or ERESTART*.
 */
static void interrupted(struct fx *f, __u64 sig)
{
	assert_int_equal(sw_out(f, sig - 100 * US, 1), 0);
	cycle_wakeup(&f->t, sig);
	assert_int_equal(sw_in(f, sig + 3 * US), 0);
	settle(f);
	cycle_delim_exit(&f->t, cycle_delim_exit_timed(&f->t, 1) ? sig + 4 * US : UNTIMED, 1,
			 f->minflt, f->majflt);
}

/*
 * a signal interrupts the sleep, its handler runs, the thread sleeps to the
 * same release again (CPython's time.sleep, restart_syscall): one cycle,
 * not two; the handler is no part of it (issue 12 item 1)
 */
static void test_cycle_interrupted_sleep_resumes(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 3), sig = rel(4) - 400 * US;

	assert_int_equal(cycle_ret_interrupted(-4), 1);		/* EINTR */
	assert_int_equal(cycle_ret_interrupted(-514), 1);	/* ERESTARTNOHAND */
	assert_int_equal(cycle_ret_interrupted(-516), 1);	/* ERESTART_RESTARTBLOCK */
	assert_int_equal(cycle_ret_interrupted(-11), 0);
	assert_int_equal(cycle_ret_interrupted(0), 0);
	assert_int_equal(cycle_ret_interrupted(-517), 0);

	assert_int_equal(enter(f, now, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 3);
	interrupted(f, sig);
	/* the handler: a syscall, a page fault, then the same wait again */
	sys(f, 0);
	f->minflt++;
	assert_int_equal(enter(f, sig + 30 * US, rel(4)), 0);
	assert_int_equal(f->t.cycles, 3);
	wake_up(f, 4);
	assert_int_equal(enter(f, rel(4) + LAT + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 4);
	assert_int_equal(f->out.start, rel(4) + LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.period, MS);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.syscalls, 0);
	assert_int_equal(f->out.minflt, 0);
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].min, MS);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].min, LAT);
	assert_int_equal(f->t.misses, 0);
}

/*
 * a signal wakes the sleep just before its release, and the timer expires
 * before the kernel looks at the signal: the sleep returns 0, switched in
 * before its time. The release is the return, not that switch-in: the
 * latency is the return's lateness (it read 0, the cycle began early).
 */
static void test_cycle_woken_early_by_a_signal(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 3), in = rel(4) - 3 * US, back = rel(4) + 9 * US;

	assert_int_equal(enter(f, now, rel(4)), CYC_EV_CLOSED);
	assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
	cycle_wakeup(&f->t, in - 1 * US);
	assert_int_equal(sw_in(f, in), 0);
	settle(f);
	/* an interrupted return still takes the switch-in, tentatively */
	assert_int_equal(cycle_delim_exit_path(&f->t.cs, 1), CYC_EXIT_SWITCHED_IN);
	assert_int_equal(cycle_delim_exit_path(&f->t.cs, 0), CYC_EXIT_WOKEN_EARLY);
	leave(f, back);
	assert_int_equal(enter(f, back + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 4);
	assert_int_equal(f->out.start, back);
	assert_int_equal(f->out.exec, EXEC);
	assert_true(f->out.flags & RTSUP_CF_HAS_LATENCY);
	assert_int_equal(f->out.latency, back - rel(4));
	/* a switch-in after its release is the release */
	wake_up(f, 5);
	assert_int_equal(enter(f, rel(5) + LAT + EXEC, rel(6)), CYC_EV_CLOSED);
	assert_int_equal(f->out.latency, LAT);
}

/* cycle_clock_moved: where a clock's new offset puts an absolute release */
static void test_cycle_clock_moved(void **state)
{
	const __s64 off = 1700000000LL * 1000000000LL;	/* CLOCK_REALTIME - MONOTONIC */

	assert_int_equal(cycle_clock_moved(T0, off, off, MS), T0);
	/* a step back of 1 s: a second more of sleep */
	assert_int_equal(cycle_clock_moved(T0, off, off - 1000 * MS, MS), T0 + 1000 * MS);
	/* a slew, or the offset read again each interval: followed */
	assert_int_equal(cycle_clock_moved(T0, off, off + 100 * US, MS), T0 - 100 * US);
	assert_int_equal(cycle_clock_moved(T0, off, off + CYC_SLEW_SLACK, MS),
			 T0 - CYC_SLEW_SLACK);
	/* a 10 s period may slew 1/1024 of it more */
	assert_int_equal(cycle_clock_moved(T0, off, off + 5 * MS, 10000 * MS), T0 - 5 * MS);
	/* a step forward: released by the step, no release to judge */
	assert_int_equal(cycle_clock_moved(T0, off, off + CYC_SLEW_SLACK + (MS >> 10) + 1, MS), 0);
	assert_int_equal(cycle_clock_moved(T0, off, off + 5000 * MS, MS), 0);
	/* before the clock's start, or none requested */
	assert_int_equal(cycle_clock_moved(MS / 2, off, off + MS - 1, MS), 0);
	assert_int_equal(cycle_clock_moved(0, off, off - MS, MS), 0);
	(void)state;
}

/* enter_on_clock - enter(), the release converted from a clock with offset 'off' */
static __u32 enter_on_clock(struct fx *f, __u64 now, __u64 expected, __s64 off)
{
	__u32 ev = enter(f, now, expected);

	cycle_sleep_clock(&f->t.cs, 1, 0, off);
	return ev;
}

/* leave_on_clock - leave(), that clock's offset now 'off_now' */
static void leave_on_clock(struct fx *f, __u64 now, __s64 off_now)
{
	settle(f);
	cycle_clock_at_exit(&f->t.cs, off_now);
	leave(f, now);
}

/*
 * CLOCK_REALTIME stepped back 1 s while the thread sleeps to a realtime
 * release: it sleeps a second more, as the kernel's timer follows the
 * clock. That second is no latency, and the next release, requested a
 * period later on the clock, is no new period (issue 16).
 */
static void test_cycle_clock_step_back_in_sleep(void **state)
{
	struct fx *f = *state;
	const __s64 off = 50000 * MS, back = 1000 * MS;
	__u64 now = rel(0) + 300 * US, r;
	int k;

	for (k = 1; k <= 4; k++) {
		enter_on_clock(f, now, rel(k), off);
		assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
		if (k < 4) {
			wake_up_rest(f, k, rel(k), off);
			now = rel(k) + LAT + EXEC;
			continue;
		}
		/* release 4: the clock steps back during the sleep */
		r = rel(4) + back;
		cycle_wakeup(&f->t, r + 2 * US);
		assert_int_equal(sw_in(f, r + LAT), 0);
		leave_on_clock(f, r + LAT + 1 * US, off - back);
	}
	/* the next release, on the clock a period later: rel(5) + 1 s in monotonic */
	assert_int_equal(enter_on_clock(f, r + LAT + EXEC, rel(5) + back, off - back),
			 CYC_EV_CLOSED);
	assert_int_equal(f->out.start, r + LAT);
	assert_int_equal(f->out.latency, LAT);
	assert_int_equal(f->out.exec, EXEC);
	assert_false(f->out.flags & (RTSUP_CF_MISS | RTSUP_CF_OVERRUN));
	assert_int_equal(f->t.cs.nominal, MS);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].max, LAT);
	assert_int_equal(f->t.misses, 0);
	assert_int_equal(f->t.overruns, 0);
}

/*
 * CLOCK_REALTIME stepped forward 5 s while the thread sleeps: the step
 * releases it early in monotonic time, at a moment no hook saw. That
 * release has no latency (not the 5 s of the step); the loop then starts
 * its schedule again from its clock's new time.
 */
static void test_cycle_clock_step_forward_in_sleep(void **state)
{
	struct fx *f = *state;
	const __s64 off = 50000 * MS, fwd = 5000 * MS;
	__u64 now = rel(0) + 300 * US, step = rel(4) - 600 * US;
	int k;

	for (k = 1; k <= 3; k++) {
		enter_on_clock(f, now, rel(k), off);
		assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
		wake_up_rest(f, k, rel(k), off);
		now = rel(k) + LAT + EXEC;
	}
	enter_on_clock(f, now, rel(4), off);
	assert_int_equal(sw_out(f, now + 1 * US, 1), 0);
	/* as the kernel side: a sleep with a requested release reads no wakeup */
	assert_false(cycle_wakeup_read(&f->t));
	assert_int_equal(sw_in(f, step + LAT), 0);
	leave_on_clock(f, step + LAT + 1 * US, off + fwd);
	/* the loop sees its clock 5 s on and sleeps a period from now */
	assert_int_equal(enter_on_clock(f, step + LAT + EXEC, step + LAT + EXEC + MS, off + fwd),
			 CYC_EV_CLOSED);
	assert_int_equal(f->out.start, step + LAT);
	assert_false(f->out.flags & RTSUP_CF_HAS_LATENCY);
	assert_false(f->out.flags & RTSUP_CF_MISS);
	assert_int_equal(f->t.m[RTSUP_M_LATENCY].max, LAT);
	assert_int_equal(f->t.misses, 0);
}

/*
 * the offset userspace writes moves a little each interval: a wait given
 * again after a signal, converted with the new offset, is still the same
 */
static void test_cycle_interrupted_sleep_resumes_across_offsets(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 3), sig = rel(4) - 400 * US;

	assert_int_equal(enter(f, now, rel(4)), CYC_EV_CLOSED);
	interrupted(f, sig);
	assert_int_equal(enter(f, sig + 30 * US, rel(4) + 150), 0);
	assert_int_equal(f->t.cycles, 3);
	wake_up(f, 4);
	assert_int_equal(enter(f, rel(4) + LAT + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 4);
	assert_int_equal(f->out.start, rel(4) + LAT);
	/* a release a period away is a new cycle, never the same wait */
	interrupted(f, rel(5) - 400 * US);
	assert_int_equal(enter(f, rel(5) - 300 * US, rel(5) + CYC_ABS_SAME + 1), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 5);
}

/*
 * SIGSTOP/SIGCONT, ptrace: the stopped thread is no block, and the
 * restarted sleep (restart_syscall: the same release) no overrun
 */
static void test_cycle_stopped_sleep_restarts(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 3), stop = rel(4) - 600 * US;

	f->cfg.period = MS;
	enter(f, now, rel(4));
	interrupted(f, stop);
	/* stopped: off CPU for 800 us, past its release, a voluntary switch */
	assert_int_equal(sw_out(f, stop + 5 * US, 1), 0);
	cycle_wakeup(&f->t, stop + 800 * US);
	sw_in(f, stop + 800 * US + 2 * US);
	/* restart_syscall: the kernel side passes the interrupted release */
	assert_int_equal(enter(f, stop + 800 * US + 3 * US, f->t.cs.abs_expected), 0);
	assert_int_equal(f->t.cs.flags & RTSUP_CS_INTR, 0);
	/* the release is past: it returns at once */
	leave(f, stop + 800 * US + 4 * US);
	assert_int_equal(enter(f, stop + 800 * US + 4 * US + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(f->out.blocks, 0);
	assert_false(f->out.flags & RTSUP_CF_OVERRUN);
	assert_int_equal(f->t.overruns, 0);
	assert_int_equal(f->t.unsafe[RTSUP_U_BLOCK], 0);
	assert_int_equal(f->t.cycles, 4);
}

/*
 * a loop that ignores EINTR and starts its work early: that cycle is real,
 * from the interrupted return, with no latency (released before its time)
 */
static void test_cycle_interrupted_sleep_abandoned(void **state)
{
	struct fx *f = *state;
	__u64 now = steady(f, rel(0), 1, 3), sig = rel(4) - 400 * US;

	enter(f, now, rel(4));
	interrupted(f, sig);
	assert_int_equal(enter(f, sig + 3 * US + EXEC, rel(5)), CYC_EV_CLOSED);
	assert_int_equal(f->out.start, sig + 3 * US);
	assert_int_equal(f->out.exec, EXEC);
	assert_false(f->out.flags & RTSUP_CF_HAS_LATENCY);
	assert_int_equal(f->t.cycles, 4);
}

/* a relative sleep interrupted, re-entered with the remainder: the same wait */
static void test_cycle_interrupted_relative_sleep(void **state)
{
	struct fx *f = *state;
	const __u64 dur = 800 * US;
	__u64 now = T0, sig;

	f->relative = 1;
	delim_sleep(f, now, now + dur, now + dur, now + dur + 3 * US, now + dur + 4 * US);
	now += dur + 3 * US + EXEC;
	enter(f, now, now + dur);
	sig = now + 300 * US;
	interrupted(f, sig);
	/* the handler ran 40 us; the remainder is what was left at the signal */
	assert_int_equal(enter(f, sig + 43 * US, sig + 43 * US + (now + dur - sig - 3 * US)), 0);
	assert_int_equal(f->t.cycles, 1);
	/* a full period again after an interruption is a new wait */
	f->t.cs.flags |= RTSUP_CS_INTR;
	f->t.cs.start = sig + 3 * US;
	assert_true(cycle_delim_resumes(&f->t.cs, sig + 43 * US, f->t.cs.expected, 0));
	assert_false(cycle_delim_resumes(&f->t.cs, sig + 43 * US, sig + 43 * US + dur, 0));
}

/*
 * once a thread sleeps to absolute releases, a relative sleep inside its
 * cycle (usleep) is no delimiter (issue 12 item 2); before, it is
 */
static void test_cycle_relative_sleep_inside_abs_loop(void **state)
{
	struct fx *f = *state;
	const __u32 sleep_cls = RTSUP_SC_ABSSLEEP | RTSUP_SC_UNSAFE;

	assert_false(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	steady(f, rel(0), 1, 1);
	assert_true(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	assert_true(cycle_rel_sleep_in_loop(&f->t, RTSUP_SC_RELSLEEP, 0));
	assert_false(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 1));
	assert_false(cycle_rel_sleep_in_loop(&f->t, RTSUP_SC_DELIM, 0));	/* epoll */
}

/*
 * a relative loop that slept to an absolute release once (in start-up) is
 * a relative loop again after CYC_REL_LOOP relative sleeps in a row
 */
static void test_cycle_relative_loop_after_one_abs_sleep(void **state)
{
	struct fx *f = *state;
	const __u32 sleep_cls = RTSUP_SC_RELSLEEP | RTSUP_SC_UNSAFE;
	int k;

	steady(f, rel(0), 1, 1);
	for (k = 1; k < CYC_REL_LOOP; k++)
		assert_true(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	assert_false(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	assert_false(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	/* an absolute loop with two usleeps per cycle stays one */
	fx_teardown(state);
	fx_setup(state);
	f = *state;
	for (k = 1; k <= 3 * CYC_REL_LOOP; k++) {
		steady(f, rel(k - 1), k, k);
		assert_true(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
		assert_true(cycle_rel_sleep_in_loop(&f->t, sleep_cls, 0));
	}
}

/*
 * start-up with a relative sleep, then an absolute loop: the start-up cycle
 * (with its mmap) is dropped when the period settles, and its unsafe
 * counts stay apart by key mode; the settled loop's cycles are all there
 */
static void test_cycle_startup_dropped_when_settled(void **state)
{
	struct fx *f = *state;
	__u64 now = T0 - 300 * MS;
	__u32 ev;
	int k;

	f->relative = 1;
	delim_sleep(f, now, now + 100 * MS, now + 100 * MS, now + 100 * MS + 3 * US,
		    now + 100 * MS + 4 * US);
	assert_int_equal(sys(f, 1), CYC_EV_UNSAFE);	/* mmap of the start-up */
	f->relative = 0;
	assert_int_equal(cycle_sys_mode(&f->t.cs), RTSUP_MODE_DELIM);
	/* the first absolute sleep closes the start-up cycle */
	assert_int_equal(enter(f, rel(0) - 500 * US, rel(0)), CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_SYSCALL], 1);
	wake_up(f, 0);
	for (k = 1; k < CYC_SETTLE_RUNS; k++) {
		assert_int_equal(enter(f, rel(k - 1) + LAT + EXEC, rel(k)), CYC_EV_CLOSED);
		wake_up(f, k);
	}
	assert_int_equal(f->t.cycles, CYC_SETTLE_RUNS);
	assert_int_equal(f->t.resets, 1);
	/* the run is complete: start-up dropped, this cycle is the loop's first */
	ev = enter(f, rel(k - 1) + LAT + EXEC, rel(k));
	assert_int_equal(ev, CYC_EV_RESET | CYC_EV_CLOSED);
	assert_int_equal(f->t.resets, 2);
	assert_int_equal(f->t.cycles, 1);
	assert_int_equal(f->t.unsafe[RTSUP_U_SYSCALL], 0);
	assert_int_equal(f->out.exec, EXEC);
	assert_int_equal(cycle_sys_mode(&f->t.cs), RTSUP_MODE_DELIM | RTSUP_MODE_SETTLED);
	wake_up(f, k);
	steady(f, rel(k) + LAT + EXEC, k + 1, k + 10);
	assert_int_equal(f->t.cycles, 11);
	assert_int_equal(f->t.resets, 2);	/* settled once */
	assert_int_equal(f->t.m[RTSUP_M_PERIOD].min, MS);
	assert_int_equal(f->t.m[RTSUP_M_EXEC].max, EXEC);
}

/*
 * a loop that runs steady from its first sleep keeps all its cycles: the
 * period settles without a reset (the steady tests count them exactly)
 */
static void test_cycle_steady_settles_without_reset(void **state)
{
	struct fx *f = *state;

	steady(f, rel(0), 1, 8);
	assert_true(f->t.cs.flags & RTSUP_CS_SETTLED);
	assert_int_equal(f->t.resets, 1);
	assert_int_equal(f->t.cycles, 7);
	assert_int_equal(cycle_sys_mode(&f->t.cs), RTSUP_MODE_DELIM);
	/* an overrun skips a release later: the distance changes, nothing resets */
	steady(f, rel(8) + LAT + EXEC, 10, 14);
	assert_int_equal(f->t.resets, 1);
	assert_int_equal(f->t.cycles, 12);
	assert_int_equal(cycle_sys_mode(&f->t.cs), RTSUP_MODE_DELIM);
}

/* warmup: start-up lasts at least that long, and is dropped then */
static void test_cycle_warmup(void **state)
{
	struct fx *f = *state;

	f->cfg.warmup = 10 * MS;
	f->t.first_seen = rel(0);
	steady(f, rel(0), 1, 10);
	assert_false(f->t.cs.flags & RTSUP_CS_SETTLED);
	assert_int_equal(f->t.cycles, 9);
	/* the entry for release 11 is the first after rel(0) + 10 ms */
	assert_int_equal(enter(f, rel(10) + LAT + EXEC, rel(11)), CYC_EV_RESET | CYC_EV_CLOSED);
	assert_int_equal(f->t.cycles, 1);
	assert_true(f->t.cs.flags & RTSUP_CS_SETTLED);

	/* a relative loop settles at its first delimiter after the warmup */
	fx_teardown(state);
	fx_setup(state);
	f = *state;
	f->relative = 1;
	f->cfg.warmup = 2 * MS;
	f->t.first_seen = T0;
	delim_sleep(f, T0, T0 + MS, T0 + MS, T0 + MS, T0 + MS + 1 * US);
	assert_int_equal(enter(f, T0 + MS + EXEC, T0 + 2 * MS + EXEC), CYC_EV_CLOSED);
	assert_false(f->t.cs.flags & RTSUP_CS_SETTLED);
}

/*
 * a keyed delimiter (read, epoll, futex) ends a cycle only on the wait the
 * thread slept in first; the same syscall on another fd is a plain call
 * (issue 12 item 3)
 */
static void test_cycle_keyed_delimiter(void **state)
{
	struct fx *f = *state;
	const __u64 timerfd = 7 | 1ULL << 63, sock = 9 | 1ULL << 63;

	/* a read of the socket that does not sleep: a delimiter, nothing learned */
	assert_true(cycle_delim_key(&f->t.cs, sock));
	enter(f, T0, 0);
	leave(f, T0 + 2 * US);
	assert_int_equal(f->t.cs.delim_key, 0);
	/* the read of the timerfd sleeps: that is the cycle's wait */
	assert_true(cycle_delim_key(&f->t.cs, timerfd));
	enter(f, T0 + 100 * US, 0);
	assert_int_equal(sw_out(f, T0 + 101 * US, 1), 0);
	assert_int_equal(f->t.cs.delim_key, timerfd);
	cycle_wakeup(&f->t, T0 + MS);
	sw_in(f, T0 + MS + 3 * US);
	leave(f, T0 + MS + 4 * US);
	/* reads of the socket inside the cycle are no boundary now */
	assert_false(cycle_delim_key(&f->t.cs, sock));
	assert_true(cycle_delim_key(&f->t.cs, timerfd));
	assert_true(cycle_delim_key(&f->t.cs, 0));	/* clock_nanosleep: no key */
}

/*
 * set_bits - one combination of what the clock decisions look at: in the
 * delimiter, switched in there, on a CPU, a cycle running, delimiter mode,
 * an interrupted sleep
 */
static void set_bits(struct rtsup_thread *t, unsigned int bits)
{
	struct rtsup_cycle_state *cs = &t->cs;

	cs->in_delim = bits & 1;
	cs->in_ts = bits & 2 ? 5 * MS : 0;
	cs->run_since = bits & 4 ? 6 * MS : 0;
	cs->start = bits & 8 ? 4 * MS : 0;
	cs->mode = bits & 16 ? RTSUP_MODE_DELIM : RTSUP_MODE_ACT;
	cs->flags = bits & 32 ? RTSUP_CS_INTR : 0;
	cs->expected = bits & 64 ? 7 * MS : 0;	/* after in_ts: a switch-in before it */
	cs->last_start = 3 * MS;
	cs->minflt0 = 0;
	cs->majflt0 = 0;
}

/*
 * The masks of the clock-reading paths are exact, over every combination
 * of set_bits: a path whose CYC_*_TIMED bit is clear gives the same state
 * whatever 'now' is (the hooks pass 0 there), a path whose bit is set
 * uses 'now' in some state, and every path is taken.
 */
static void test_cycle_timed_masks_exact(void **state)
{
	struct fx *f = *state;
	__u32 out_taken = 0, out_used = 0, exit_taken = 0, exit_used = 0;
	unsigned int bits;
	int vol;

	for (bits = 0; bits < 128; bits++) {
		for (vol = 0; vol < 2; vol++) {
			struct rtsup_thread a = f->t, b;
			struct rtsup_cycle oa = { 0 }, ob = { 0 };
			enum cycle_out_path path;
			__u32 eva, evb;
			bool same;

			set_bits(&a, bits);
			b = a;
			path = cycle_switch_out_path(&a.cs, vol);
			assert_int_equal(cycle_switch_out_timed(&a, vol),
					 CYC_PATH_TIMED(CYC_OUT_TIMED, path));
			eva = cycle_switch_out(&a, &f->cfg, 10 * MS, vol, 0, 0, &oa);
			evb = cycle_switch_out(&b, &f->cfg, 20 * MS, vol, 0, 0, &ob);
			same = eva == evb && !memcmp(&a, &b, sizeof(a)) &&
			       !memcmp(&oa, &ob, sizeof(oa));
			out_taken |= 1u << path;
			if (!same)
				out_used |= 1u << path;
			if (!CYC_PATH_TIMED(CYC_OUT_TIMED, path))
				assert_true(same);
		}
		{
			struct rtsup_thread a = f->t, b;
			enum cycle_exit_path path;

			set_bits(&a, bits);
			b = a;
			path = cycle_delim_exit_path(&a.cs, bits & 32);
			assert_int_equal(cycle_delim_exit_timed(&a, bits & 32),
					 CYC_PATH_TIMED(CYC_EXIT_TIMED, path));
			cycle_delim_exit(&a, 10 * MS, bits & 32, 0, 0);
			cycle_delim_exit(&b, 20 * MS, bits & 32, 0, 0);
			exit_taken |= 1u << path;
			if (memcmp(&a, &b, sizeof(a)))
				exit_used |= 1u << path;
		}
	}
	assert_int_equal(out_taken, (1u << (CYC_OUT_ACT_END + 1)) - 1);
	assert_int_equal(out_used, CYC_OUT_TIMED);
	assert_int_equal(exit_taken, (1u << (CYC_EXIT_WOKEN_EARLY + 1)) - 1);
	assert_int_equal(exit_used, CYC_EXIT_TIMED);
}

#define T(fn) cmocka_unit_test_setup_teardown(fn, fx_setup, fx_teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(test_cycle_steady_abs_sleep),
		T(test_cycle_clock_step_back_in_sleep),
		T(test_cycle_clock_step_forward_in_sleep),
		T(test_cycle_interrupted_sleep_resumes_across_offsets),
		cmocka_unit_test(test_cycle_clock_moved),
		T(test_cycle_steady_lifetime_minmax),
		T(test_cycle_relative_sleep),
		T(test_cycle_preempt_in_cycle),
		T(test_cycle_block_in_cycle),
		T(test_cycle_exit_missed_released_at_switch_in),
		T(test_cycle_exit_missed_without_switch_in),
		T(test_cycle_entry_skipped_sleep_is_the_entry),
		T(test_cycle_entry_seen_block_stays),
		T(test_cycle_entry_skipped_no_boundary),
		T(test_cycle_entry_and_exit_skipped),
		T(test_cycle_switch_voluntary_states),
		T(test_cycle_rtlock_wait_in_cycle),
		T(test_cycle_miss_overrun),
		T(test_cycle_overrun_judged_by_its_own_release),
		T(test_cycle_miss_without_overrun),
		T(test_cycle_miss_boundary),
		T(test_cycle_early_release),
		T(test_cycle_delim_no_sleep),
		T(test_cycle_migration),
		T(test_cycle_migration_unseen_switch_in),
		T(test_cycle_unsafe_syscall),
		T(test_cycle_page_faults),
		T(test_cycle_activation_mode),
		T(test_cycle_activation_then_delim_resets),
		T(test_cycle_activation_unseen_switch_in),
		T(test_cycle_activation_stale_wakeup),
		T(test_cycle_activation_unseen_resume),
		T(test_cycle_unseen_needs_activation_mode),
		T(test_cycle_reset_lifetime_min),
		T(test_cycle_exit_mid_cycle),
		T(test_cycle_exit_in_delim),
		T(test_cycle_epoch_banks),
		T(test_cycle_unknown_expected_uses_wakeup),
		T(test_cycle_preempt_in_delim_after_release),
		T(test_cycle_steady_loop_reads_clock_once_per_switch_in),
		T(test_cycle_interrupted_sleep_resumes),
		T(test_cycle_woken_early_by_a_signal),
		T(test_cycle_stopped_sleep_restarts),
		T(test_cycle_interrupted_sleep_abandoned),
		T(test_cycle_interrupted_relative_sleep),
		T(test_cycle_relative_sleep_inside_abs_loop),
		T(test_cycle_relative_loop_after_one_abs_sleep),
		T(test_cycle_startup_dropped_when_settled),
		T(test_cycle_steady_settles_without_reset),
		T(test_cycle_warmup),
		T(test_cycle_keyed_delimiter),
		T(test_cycle_timed_masks_exact),
	};

	return cmocka_run_group_tests_name("cycle", tests, NULL, NULL);
}
