// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * test_cause.c - cause attribution (include/cause.h) fed synthetic
 * sequences of the hooks' events: a target's wakeup and preemption arm a
 * CPU's wait slot, switches on that CPU charge its holders, the target's
 * next event folds the wait into its cycle, and a late cycle's cause is
 * its biggest part. Every number is checked exactly.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "cause.h"

#define US	1000ULL
#define MS	1000000ULL
#define RT	100	/* the target's tid */

static const struct rtsup_who idle = { .tid = 0, .comm = "swapper/1" };
static const struct rtsup_who hog = { .tid = 812, .tgid = 812, .policy = 1, .prio = 99,
				      .comm = "noise-hog" };
static const struct rtsup_who owner = { .tid = 900, .tgid = 899, .policy = 1, .prio = 10,
					.comm = "owner" };
static const struct rtsup_who boss = { .tid = 901, .tgid = 899, .policy = 1, .prio = 80,
				       .comm = "boss" };

/* A target, one CPU's wait slots, and the task running on that CPU. */
struct fx {
	struct rtsup_why w;
	struct rtsup_cycle_state cs;
	struct why_slot s[WHY_WAITERS];
	struct rtsup_who cur;	/* running on the CPU */
};

static void fx_init(struct fx *f)
{
	memset(f, 0, sizeof(*f));
	f->cur = idle;
}

/* wake - sched_wakeup of the target at 'now', by the task running (as on_wakeup) */
static int wake(struct fx *f, __u64 now)
{
	int i = why_pick(f->s, RT, now);

	if (i < 0)
		return i;
	why_arm(&f->s[i], RT, WHY_WOKEN, now);
	f->s[i].policy = WHY_SCHED_FIFO;
	f->s[i].prio = 50;
	f->s[i].waker = f->cur;
	return i;
}

/* sw - sched_switch on the CPU at 'now' from the running task to 'next' (as on_switch) */
static void sw(struct fx *f, __u64 now, const struct rtsup_who *next)
{
	int i;

	for (i = 0; i < WHY_WAITERS; i++)
		if (f->s[i].tid && !(f->s[i].state & WHY_RAN) &&
		    why_switch_holder(&f->s[i], f->cur.tid, next->tid, now))
			f->s[i].top = f->cur;
	f->cur = *next;
}

/* settle - the target's next event: fold a wait that ran (as why_settle) */
static void settle(struct fx *f)
{
	int i;

	for (i = 0; i < WHY_WAITERS; i++)
		if (f->s[i].tid == RT && (f->s[i].state & WHY_RAN)) {
			why_take(&f->w, &f->cs, &f->s[i], 1);
			f->s[i].tid = 0;
		}
}

static const struct rtsup_who target = { .tid = RT, .tgid = RT, .policy = 1, .prio = 50,
					 .comm = "lg-0" };

/* woken on time, then 3.1 ms behind a FIFO 99 hog: "wait", the hog named */
static void test_cause_wait_behind_hog(void **state)
{
	struct fx f;

	fx_init(&f);
	f.cs.in_delim = 1;
	f.cs.expected = 10 * MS;
	sw(&f, 10 * MS - 50 * US, &hog);	/* the hog took the idle CPU */
	assert_int_equal(wake(&f, 10 * MS + 5 * US), 0);
	sw(&f, 13 * MS + 105 * US, &target);
	assert_true(f.s[0].state & WHY_RAN);
	settle(&f);
	assert_int_equal(f.s[0].tid, 0);
	assert_int_equal(f.w.cur.timer_ns, 5 * US);
	assert_int_equal(f.w.cur.wait_ns, 3100 * US);
	assert_int_equal(f.w.cur.top[0].who.tid, 812);
	assert_int_equal(f.w.cur.top[0].ns, 3100 * US);
	/* a hog interrupted by a short kernel thread: one holder, its stretches summed */
	f.cs.in_delim = 1;
	why_reset(&f.w.cur);
	sw(&f, 20 * MS, &hog);
	wake(&f, 20 * MS + 10 * US);
	sw(&f, 21 * MS, &boss);
	sw(&f, 21 * MS + 20 * US, &hog);
	sw(&f, 22 * MS + 10 * US, &target);
	settle(&f);
	assert_int_equal(f.w.cur.wait_ns, 2 * MS);
	assert_int_equal(f.w.cur.top[0].who.tid, 812);
	assert_int_equal(f.w.cur.top[0].ns, 1980 * US);
	f.cs.expected = 10 * MS;
	why_reset(&f.w.cur);
	f.w.cur.wait_ns = 3100 * US;
	f.w.cur.timer_ns = 5 * US;
	why_culprit(&f.w.cur, &hog, 3100 * US);
	/* the cycle ends past its next release (1 ms period): a miss */
	f.cs.in_delim = 0;
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 13 * MS + 205 * US,
		  11 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_WAIT);
	assert_int_equal(f.w.out.ns, 3100 * US);
	/* a FIFO 99 hog above a FIFO 50 target: the scheduler's choice, not the kernel's */
	assert_false(f.w.out.flags & RTSUP_CAUSE_F_BELOW);
	assert_string_equal(f.w.out.who.comm, "noise-hog");
	assert_int_equal(f.w.out.who.prio, 99);
	/* the next cycle starts late without sleeping: backlog, same culprit */
	assert_int_equal(f.w.cur.backlog_ns, 2205 * US);
	assert_int_equal(f.w.cur.who.tid, 812);
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 13 * MS + 305 * US,
		  12 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_BACKLOG);
	assert_int_equal(f.w.out.who.tid, 812);
	assert_true(f.w.out.flags & RTSUP_CAUSE_F_INHERIT);
}

/* a SCHED_OTHER task held the CPU from a woken FIFO 50 target: not preemptible */
static void test_cause_holder_below_target(void **state)
{
	static const struct rtsup_who vm = { .tid = 777, .tgid = 777, .policy = 0, .prio = 0,
					     .comm = "qemu" };
	struct fx f;

	fx_init(&f);
	f.cs.in_delim = 1;
	f.cs.expected = 10 * MS;
	sw(&f, 9 * MS, &vm);
	wake(&f, 10 * MS);
	sw(&f, 14 * MS, &target);
	settle(&f);
	assert_true(f.w.cur.flags & RTSUP_CAUSE_F_BELOW);
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 14 * MS + 100 * US,
		  11 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_WAIT);
	assert_int_equal(f.w.out.who.tid, 777);
	assert_true(f.w.out.flags & RTSUP_CAUSE_F_BELOW);
}

/* the wakeup itself came 2 ms late to an idle CPU: the machine, no task */
static void test_cause_timer_on_idle_cpu(void **state)
{
	struct fx f;

	fx_init(&f);
	f.cs.in_delim = 1;
	f.cs.expected = 10 * MS;
	wake(&f, 12 * MS);
	sw(&f, 12 * MS + 3 * US, &target);
	settle(&f);
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 12 * MS + 103 * US,
		  11 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_TIMER);
	assert_int_equal(f.w.out.ns, 2 * MS);
	assert_true(f.w.out.flags & RTSUP_CAUSE_F_IDLE);
	assert_int_equal(f.w.out.who.tid, 0);
	assert_int_equal(f.w.out.who.comm[0], '\0');
}

/*
 * the releases a late cycle swallowed: the next sleep asks for a time
 * already past, and the kernel still goes through its timer, which fires
 * at once (a wakeup 7 us after the delimiter's entry). That cycle is late
 * for its backlog, not for its timer: only the 7 us are the timer's.
 */
static void test_cause_backlog_sleep_is_no_timer(void **state)
{
	struct fx f;

	fx_init(&f);
	f.cs.in_delim = 1;
	f.cs.expected = 10 * MS;
	wake(&f, 12 * MS);
	sw(&f, 12 * MS + 3 * US, &target);
	settle(&f);
	/* it ends at 12.103 ms, its next release was 11 ms: it enters the sleep late */
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 12 * MS + 103 * US,
		  11 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_TIMER);
	assert_int_equal(f.w.cur.backlog_ns, 1103 * US);
	f.cs.expected = 11 * MS;
	sw(&f, 12 * MS + 105 * US, &idle);
	wake(&f, 12 * MS + 110 * US);
	sw(&f, 12 * MS + 113 * US, &target);
	settle(&f);
	assert_int_equal(f.w.cur.timer_ns, 7 * US);
	/* 100 us of work, past its next release (12 ms) again */
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 12 * MS + 213 * US,
		  12 * MS);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_BACKLOG);
	assert_int_equal(f.w.out.ns, 1103 * US);
	assert_int_equal(f.w.out.timer_ns, 7 * US);
	assert_int_equal(f.w.out.who.tid, 0);
	/* it follows the timer's late cycle, and so does the next of the chain */
	assert_int_equal(f.w.out.after, RTSUP_CAUSE_TIMER);
	assert_int_equal(f.w.cur.after, RTSUP_CAUSE_TIMER);
}

/*
 * where and when for Perfetto: the longest wait of the cycle (its window,
 * CPU and holder), the longest block's wakeup and the switch-in after it
 */
static void test_cause_longest_wait_and_wake_times(void **state)
{
	struct fx f;

	fx_init(&f);
	f.cs.in_delim = 1;
	f.cs.expected = 10 * MS;
	sw(&f, 9 * MS, &hog);
	wake(&f, 10 * MS);
	sw(&f, 11 * MS, &target);	/* 1 ms behind the hog */
	settle(&f);
	assert_int_equal(f.w.cur.held_from, 10 * MS);
	assert_int_equal(f.w.cur.held_to, 11 * MS);
	assert_int_equal(f.w.cur.held_cpu, 1);
	assert_int_equal(f.w.cur.held_tid, 812);
	/* in the cycle: it blocks, the owner wakes it, it runs 10 us later */
	f.cs.in_delim = 0;
	f.cs.start = 11 * MS;
	why_syscall(&f.w, 202, 0 + 1);
	why_switch_out(&f.w, &f.cs, 11 * MS + 100 * US, 1, 1);
	sw(&f, 11 * MS + 100 * US, &owner);
	wake(&f, 13 * MS);
	sw(&f, 13 * MS + 10 * US, &target);
	settle(&f);
	assert_int_equal(f.w.cur.block_woke, 13 * MS);
	assert_int_equal(f.w.cur.block_ran, 13 * MS + 10 * US);
	assert_int_equal(f.w.cur.waker.tid, 900);
	/* a shorter wait does not replace the longest */
	assert_int_equal(f.w.cur.held_from, 10 * MS);
	assert_int_equal(f.w.cur.held_tid, 812);
	why_reset(&f.w.cur);
	assert_int_equal(f.w.cur.held_to - f.w.cur.held_from, 0);
}

/*
 * sched_migrate_task: why, as the kernel tells; the switch-in on the new
 * CPU inside the cycle takes it into the cycle's cause and the event
 */
static void test_cause_migration_why(void **state)
{
	struct fx f;
	__u64 arg;

	fx_init(&f);
	why_migrate(&f.w, 0, 1, 0, 0);
	assert_int_equal(f.w.mig_why, RTSUP_MIG_AFFINITY);
	why_migrate(&f.w, 0, 1, 1, 1);
	assert_int_equal(f.w.mig_why, RTSUP_MIG_WAKEUP);
	/* placed at its wakeup because its CPU left its mask while it slept */
	why_migrate(&f.w, 0, 1, 1, 0);
	assert_int_equal(f.w.mig_why, RTSUP_MIG_AFFINITY);
	why_migrate(&f.w, 2, 3, 0, 1);
	assert_int_equal(f.w.mig_why, RTSUP_MIG_BALANCE);
	arg = why_migrated(&f.w, 3);
	assert_int_equal(RTSUP_MIG_FROM(arg), 2);
	assert_int_equal(RTSUP_MIG_TO(arg), 3);
	assert_int_equal(RTSUP_MIG_WHY(arg), RTSUP_MIG_BALANCE);
	assert_int_equal(f.w.cur.migrations, 1);
	assert_int_equal(f.w.cur.mig_from, 2);
	/* taken: a second switch-in elsewhere that the hook did not see is unknown */
	arg = why_migrated(&f.w, 0);
	assert_int_equal(RTSUP_MIG_FROM(arg), RTSUP_MIG_NOCPU);
	assert_int_equal(RTSUP_MIG_WHY(arg), RTSUP_MIG_UNKNOWN);
	assert_int_equal(f.w.cur.migrations, 2);
	/* a record for another CPU is not this migration's */
	why_migrate(&f.w, 0, 1, 0, 1);
	arg = why_migrated(&f.w, 2);
	assert_int_equal(RTSUP_MIG_WHY(arg), RTSUP_MIG_UNKNOWN);
	why_reset(&f.w.cur);
	assert_int_equal(f.w.cur.migrations, 0);
}

/*
 * a target woken on CPU 0 and moved to CPU 1 before it ran: its wait goes
 * on at CPU 1 from its wakeup, CPU 0's slot is free (it charged CPU 0's
 * switches until stale before)
 */
static void test_cause_wait_moves_with_the_target(void **state)
{
	struct fx a, b;

	fx_init(&a);
	fx_init(&b);
	a.cs.in_delim = 1;
	a.cs.expected = 10 * MS;
	sw(&a, 9 * MS, &hog);
	wake(&a, 10 * MS);
	sw(&b, 9 * MS, &boss);
	assert_int_equal(why_move(a.s, b.s, RT, 10 * MS + 100 * US), 1);
	assert_int_equal(a.s[0].tid, 0);
	assert_int_equal(b.s[0].tid, RT);
	assert_int_equal(b.s[0].armed, 10 * MS);
	assert_int_equal(b.s[0].since, 10 * MS + 100 * US);
	/* boss holds CPU 1 until 12 ms: the wait is 2 ms, boss its holder */
	sw(&b, 12 * MS, &target);
	b.w = a.w;
	b.cs = a.cs;
	settle(&b);
	assert_int_equal(b.w.cur.wait_ns, 2 * MS);
	assert_int_equal(b.w.cur.top[0].who.tid, 901);
	assert_int_equal(b.w.cur.top[0].ns, 1900 * US);
	/* nothing to move: no wait of it there */
	assert_int_equal(why_move(a.s, b.s, RT, 13 * MS), 0);
}

/* preempted twice inside the cycle: the longest holder first, sums kept */
static void test_cause_preemptions_summed(void **state)
{
	struct fx f;

	fx_init(&f);
	f.cs.start = 10 * MS;
	f.cur = target;
	/* on_switch: the target leaves involuntarily, its slot armed for it */
	why_switch_out(&f.w, &f.cs, 10 * MS + 100 * US, 0, 0);
	why_arm(&f.s[why_pick(f.s, RT, 10 * MS + 100 * US)], RT, WHY_PREEMPTED, 10 * MS + 100 * US);
	sw(&f, 10 * MS + 100 * US, &boss);
	sw(&f, 10 * MS + 400 * US, &hog);
	sw(&f, 11 * MS + 400 * US, &target);
	settle(&f);
	why_arm(&f.s[why_pick(f.s, RT, 12 * MS)], RT, WHY_PREEMPTED, 12 * MS);
	f.cur = boss;
	sw(&f, 12 * MS + 500 * US, &target);
	settle(&f);
	assert_int_equal(f.w.cur.preempts, 2);
	assert_int_equal(f.w.cur.preempt_ns, 1800 * US);
	assert_int_equal(f.w.cur.top[0].who.tid, 812);
	assert_int_equal(f.w.cur.top[0].ns, 1 * MS);
	assert_int_equal(f.w.cur.top[1].who.tid, 901);
	/* a slot keeps its wait's longest holder: boss's 300 us under the hog's 1 ms is not */
	assert_int_equal(f.w.cur.top[1].ns, 500 * US);
	assert_int_equal(f.w.cur.top[1].count, 1);
	why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 1 * MS, 5 * MS, 13 * MS, 12 * MS + 900 * US);
	assert_int_equal(f.w.out.kind, RTSUP_CAUSE_PREEMPT);
	assert_int_equal(f.w.out.who.tid, 812);
}

/* blocked on a plain futex, woken by a FIFO 10 owner: inversion; by PI: none */
static void test_cause_block_inversion(void **state)
{
	static const __u32 ops[] = { WHY_FUTEX_WAIT + 1, 6 + 1 /* FUTEX_LOCK_PI */ };
	struct fx f;
	int i;

	for (i = 0; i < 2; i++) {
		fx_init(&f);
		f.cs.start = 10 * MS;
		f.cur = target;
		why_syscall(&f.w, 202, ops[i]);
		why_switch_out(&f.w, &f.cs, 10 * MS + 50 * US, 1, 0);
		sw(&f, 10 * MS + 50 * US, &owner);
		wake(&f, 12 * MS);	/* the owner unlocks */
		sw(&f, 12 * MS + 10 * US, &target);
		settle(&f);
		assert_int_equal(f.w.cur.block_ns, 1950 * US);
		assert_int_equal(f.w.cur.wait_ns, 10 * US);
		assert_int_equal(f.w.cur.block_nr, 203);
		assert_int_equal(f.w.cur.block_op, ops[i]);
		assert_int_equal(f.w.cur.waker.tid, 900);
		assert_int_equal(!!(f.w.cur.flags & RTSUP_CAUSE_F_INVERSION), i == 0);
		why_delim(&f.w, CYC_EV_CLOSED | CYC_EV_MISS, 100 * US, 1 * MS, 12 * MS + 110 * US,
			  11 * MS);
		assert_int_equal(f.w.out.kind, RTSUP_CAUSE_BLOCK);
		assert_int_equal(f.w.out.who.tid, 900);
	}
	/* a higher priority waker is no inversion */
	assert_false(why_inversion(WHY_FUTEX_WAIT + 1, WHY_SCHED_FIFO, 50, &boss));
	/* nor a wake from interrupt context on an idle CPU */
	assert_false(why_inversion(WHY_FUTEX_WAIT + 1, WHY_SCHED_FIFO, 50, &idle));
}

/* its own CPU time wins only when it alone does not fit the period */
static void test_cause_exec_only_when_it_does_not_fit(void **state)
{
	struct rtsup_cause c;

	memset(&c, 0, sizeof(c));
	c.timer_ns = 13 * US;	/* too small beside 2.4 ms of work */
	cause_pick(&c, 2400 * US, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_EXEC);
	memset(&c, 0, sizeof(c));
	c.backlog_ns = 2 * MS;	/* 3 ms of work fits 5 ms: the backlog */
	cause_pick(&c, 3 * MS, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_BACKLOG);
	cause_pick(&c, 6 * MS, 5 * MS);	/* does not fit: itself */
	assert_int_equal(c.kind, RTSUP_CAUSE_EXEC);
	assert_int_equal(c.ns, 6 * MS);
}

/*
 * the hypervisor's steal while the target ran: its own part, out of the
 * CPU time; only across a switch-in and a switch-out on one CPU
 */
static void test_cause_steal_is_the_machines(void **state)
{
	struct rtsup_why w;
	struct rtsup_cause c;

	memset(&w, 0, sizeof(w));
	why_steal_in(&w, 1, 100 * MS);
	why_steal_out(&w, 1, 102 * MS);
	assert_int_equal(w.cur.steal_ns, 2 * MS);
	assert_int_equal(w.steal_cpu, 0);
	why_steal_out(&w, 1, 109 * MS);	/* off CPU: no switch-in marked */
	why_steal_in(&w, 1, 110 * MS);
	why_steal_out(&w, 0, 900 * MS);	/* another CPU's counter: nothing */
	why_steal_in(&w, 0, 900 * MS);
	why_steal_out(&w, 0, 901 * MS);
	assert_int_equal(w.cur.steal_ns, 3 * MS);
	why_reset(&w.cur);
	assert_int_equal(w.cur.steal_ns, 0);

	/* 3 ms of work, 2.5 ms stolen inside it: 5.5 ms "on CPU" in a 5 ms period */
	memset(&c, 0, sizeof(c));
	c.steal_ns = 2500 * US;
	c.timer_ns = 20 * US;
	cause_pick(&c, 5500 * US, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_STEAL);
	assert_int_equal(c.ns, 2500 * US);
	assert_int_equal(c.cpu_ns, 3 * MS);
	assert_int_equal(c.who.tid, 0);
	/* without the steal the same cycle is its own */
	memset(&c, 0, sizeof(c));
	c.timer_ns = 20 * US;
	cause_pick(&c, 5500 * US, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_EXEC);
	/* a preemption longer than the steal wins */
	memset(&c, 0, sizeof(c));
	c.steal_ns = 1 * MS;
	c.preempt_ns = 4 * MS;
	cause_pick(&c, 3 * MS, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_PREEMPT);
	assert_int_equal(c.cpu_ns, 2 * MS);
	/* a tie goes to the machine; no more is stolen than its time on CPU */
	memset(&c, 0, sizeof(c));
	c.steal_ns = 9 * MS;
	c.timer_ns = 1 * MS;
	cause_pick(&c, 1 * MS, 5 * MS);
	assert_int_equal(c.kind, RTSUP_CAUSE_STEAL);
	assert_int_equal(c.ns, 1 * MS);
	assert_int_equal(c.steal_ns, 1 * MS);
	assert_int_equal(c.cpu_ns, 0);
}

/* a second target may wait on the same CPU; a third is counted, not mixed in */
static void test_cause_slots_keep_each_wait(void **state)
{
	struct why_slot s[WHY_WAITERS];

	memset(s, 0, sizeof(s));
	why_arm(&s[why_pick(s, 7, 1 * MS)], 7, WHY_WOKEN, 1 * MS);
	assert_int_equal(why_pick(s, RT, 1 * MS), 1);
	why_arm(&s[1], RT, WHY_WOKEN, 1 * MS);
	assert_int_equal(why_pick(s, 9, 1 * MS), -1);
	/* one that ran keeps its slot until its next event folds it */
	why_switch_holder(&s[0], 0, 7, 2 * MS);
	assert_int_equal(why_pick(s, 9, 2 * MS), -1);
	/* a wait longer than WHY_STALE_NS is no scheduling wait: dropped */
	assert_true(why_stale(&s[1], 1 * MS + WHY_STALE_NS + 1));
	assert_int_equal(why_pick(s, 9, 1 * MS + WHY_STALE_NS + 1), 0);
}

/* only a wait inside a running cycle, outside the delimiter, is a block */
static void test_cause_is_block(void **state)
{
	struct rtsup_cycle_state cs = { .start = 1 * MS };

	(void)state;
	assert_true(why_is_block(&cs, 2 * MS, 1));
	assert_false(why_is_block(&cs, 2 * MS, 0));	/* preempted */
	assert_false(why_is_block(&cs, 0, 1));		/* no clock read: not timed */
	cs.in_delim = 1;
	assert_false(why_is_block(&cs, 2 * MS, 1));	/* its delimiter's sleep */
	cs.in_delim = 0;
	cs.start = 0;
	assert_false(why_is_block(&cs, 2 * MS, 1));	/* no cycle running */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_cause_wait_behind_hog),
		cmocka_unit_test(test_cause_timer_on_idle_cpu),
		cmocka_unit_test(test_cause_backlog_sleep_is_no_timer),
		cmocka_unit_test(test_cause_longest_wait_and_wake_times),
		cmocka_unit_test(test_cause_migration_why),
		cmocka_unit_test(test_cause_wait_moves_with_the_target),
		cmocka_unit_test(test_cause_holder_below_target),
		cmocka_unit_test(test_cause_preemptions_summed),
		cmocka_unit_test(test_cause_block_inversion),
		cmocka_unit_test(test_cause_exec_only_when_it_does_not_fit),
		cmocka_unit_test(test_cause_steal_is_the_machines),
		cmocka_unit_test(test_cause_slots_keep_each_wait),
		cmocka_unit_test(test_cause_is_block),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
