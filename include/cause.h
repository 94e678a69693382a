/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * cause.h - why a cycle was late: cause attribution, shared by BPF and
 * userspace (the unit tests feed it synthetic event sequences).
 *
 * A target that is runnable but not running "waits" for its CPU: after a
 * wakeup (its release, or the end of a block inside its cycle) or after a
 * preemption. One slot per CPU (struct why_slot) holds the target waiting
 * there; while it is armed, every switch on that CPU charges the time
 * since the previous switch to the task that ran (prev). A CPU with no
 * waiting target costs one load per switch. When the target runs, the
 * slot is folded into the thread's running cycle (why_take) at its next
 * event, as the held switch-in is (cycle.h).
 *
 * A cycle's time from its expected release to its end is made of parts:
 * timer (release to wakeup: the machine), wait (woken to running: other
 * tasks), preemption, blocks, backlog (released after its time because
 * the previous cycle ended late) and its own CPU time. Under a hypervisor
 * a part of what looks like its CPU time may be another vCPU's: the time
 * the host stole while the target ran (steal, why_steal_in/out) is a part
 * of its own, taken out of the CPU time. When a cycle misses its deadline,
 * the biggest part is its cause (cause_pick), named with the task behind it.
 */
#ifndef RTSUP_CAUSE_H
#define RTSUP_CAUSE_H

#include "rtsup.h"
#include "cycle.h"

/*
 * A wait longer than this is no scheduling wait (a slot armed for a target
 * that was woken there but ran elsewhere): the slot is dropped.
 */
#define WHY_STALE_NS	(1000ULL * 1000 * 1000)

#define WHY_SCHED_FIFO	1
#define WHY_SCHED_RR	2
#define WHY_SCHED_DEADLINE	6
#define WHY_TASK_UNINTERRUPTIBLE	2

/* why_rt - a real-time policy: its rt_priority orders it */
RTSUP_INLINE int why_rt(__u32 policy)
{
	return policy == WHY_SCHED_FIFO || policy == WHY_SCHED_RR ||
	       policy == WHY_SCHED_DEADLINE;
}

/* Futex commands (block_op - 1) that wait with no priority inheritance. */
#define WHY_FUTEX_WAIT		0
#define WHY_FUTEX_WAIT_BITSET	9

/*
 * why_inversion - was a target of (policy, prio) woken from a futex wait
 * (op: the futex command + 1) by a task below it? The kernel's rtapp
 * monitor allows FUTEX_WAIT only when woken by an equal or higher priority:
 * an RT target woken by a lower RT priority or by a non-RT task waited for
 * it (a priority inversion). A PI lock (FUTEX_LOCK_PI) boosted its owner:
 * no inversion.
 */
/* why_below - is a task below an RT target of (policy, prio)? (idle: no) */
RTSUP_INLINE int why_below(__u32 policy, __s32 prio, const struct rtsup_who *w)
{
	if (!why_rt(policy) || !w->tid)
		return 0;
	return !why_rt(w->policy) || w->prio < prio;
}

RTSUP_INLINE int why_inversion(__u32 op, __u32 policy, __s32 prio,
			       const struct rtsup_who *waker)
{
	if (op != WHY_FUTEX_WAIT + 1 && op != WHY_FUTEX_WAIT_BITSET + 1)
		return 0;
	return why_below(policy, prio, waker);
}

/* why_who_clear - no task named */
RTSUP_INLINE void why_who_clear(struct rtsup_who *who)
{
	who->tid = 0;
	who->tgid = 0;
	who->policy = 0;
	who->prio = 0;
	who->comm[0] = '\0';
}

/*
 * why_reset - a new cycle: nothing attributed yet. Field by field, at every
 * cycle: what a field's emptiness does not tell (names) is written before
 * it is read (an empty top entry has ns 0, the waker comes with block_max).
 */
RTSUP_INLINE void why_reset(struct rtsup_cause *c)
{
	__u32 i;

	c->kind = 0;
	c->flags = 0;
	c->ns = 0;
	c->timer_ns = 0;
	c->wait_ns = 0;
	c->preempt_ns = 0;
	c->block_ns = 0;
	c->backlog_ns = 0;
	c->cpu_ns = 0;
	c->steal_ns = 0;
	c->preempts = 0;
	c->blocks = 0;
	c->block_nr = 0;
	c->block_op = 0;
	c->block_max = 0;
	why_who_clear(&c->who);
	for (i = 0; i < RTSUP_CAUSE_TOP; i++)
		c->top[i].ns = 0;
	/* held_* and mig_* are read when these say there is one */
	c->held_from = 0;
	c->held_to = 0;
	c->migrations = 0;
}

/* why_arm - the target 'tid' waits for this CPU since 'now' */
RTSUP_INLINE void why_arm(struct why_slot *s, __u32 tid, __u32 state, __u64 now)
{
	s->tid = tid;
	s->state = state;
	s->armed = now;
	s->since = now;
	s->ran = 0;
	s->top_ns = 0;
	s->top.tid = 0;
}

/*
 * why_armable - may a wait of 'tid' take this slot? Not from another
 * target still waiting there, nor from one that ran and whose next event
 * has not folded the wait yet (the preempted prev of the very switch that
 * ran it): their waits stay whole.
 */
RTSUP_INLINE int why_armable(const struct why_slot *s, __u32 tid, __u64 now)
{
	return !s->tid || s->tid == tid || now - s->armed > WHY_STALE_NS;
}

/*
 * why_pick - the slot of a CPU's WHY_WAITERS for a wait of 'tid': its own,
 * else a free one; -1 when both hold other targets' waits (counted).
 */
RTSUP_INLINE int why_pick(const struct why_slot *s, __u32 tid, __u64 now)
{
	int i;

	for (i = 0; i < WHY_WAITERS; i++)
		if (s[i].tid == tid)
			return i;
	for (i = 0; i < WHY_WAITERS; i++)
		if (why_armable(&s[i], tid, now))
			return i;
	return -1;
}

/*
 * why_switch_holder - a switch on the slot's CPU while its target waits:
 * prev ran since s->since. Returns 1 when prev held the CPU longer than
 * anyone so far (the caller copies prev into s->top); the holder kept adds
 * up its stretches (a hog interrupted by a kernel thread is one holder).
 * 'next_tid' is the target: it runs now (WHY_RAN).
 */
RTSUP_INLINE int why_switch_holder(struct why_slot *s, __u32 prev_tid, __u32 next_tid,
				   __u64 now)
{
	__u64 held = now > s->since ? now - s->since : 0;
	int top = 0;

	if (prev_tid == s->tid) {
		/* the target itself (woken, ran unseen): no holder */
	} else if (s->top_ns && prev_tid == s->top.tid) {
		s->top_ns += held;
	} else if (held > s->top_ns) {
		s->top_ns = held;
		top = 1;
	}
	s->since = now;
	if (next_tid == s->tid) {
		s->state |= WHY_RAN;
		s->ran = now;
	}
	return top;
}

/* why_stale - a slot whose target waits too long to be a scheduling wait */
RTSUP_INLINE int why_stale(const struct why_slot *s, __u64 now)
{
	return !(s->state & WHY_RAN) && now - s->armed > WHY_STALE_NS;
}

/* why_culprit - add ns of a task holding the target's CPU to the cycle's top list */
RTSUP_SUBPROG void why_culprit(struct rtsup_cause *c, const struct rtsup_who *who, __u64 ns)
{
	struct rtsup_culprit tmp;
	__u32 i, min = 0;

	if (!ns)
		return;
	for (i = 0; i < RTSUP_CAUSE_TOP; i++) {
		if (c->top[i].ns && c->top[i].who.tid == who->tid)
			break;
		if (c->top[i].ns < c->top[min].ns)
			min = i;
	}
	if (i == RTSUP_CAUSE_TOP) {
		/* a new one replaces the smallest, if it is bigger */
		if (c->top[min].ns >= ns)
			return;
		i = min;
		c->top[i].who = *who;
		c->top[i].ns = 0;
		c->top[i].count = 0;
	}
	c->top[i].ns += ns;
	c->top[i].count++;
	/* longest first: bubble up (three entries) */
	for (; i > 0 && c->top[i].ns > c->top[i - 1].ns; i--) {
		tmp = c->top[i - 1];
		c->top[i - 1] = c->top[i];
		c->top[i] = tmp;
	}
}

/*
 * why_is_block - does a thread that leaves its CPU (voluntary: to wait) at
 * 'now' start a block inside its cycle, outside its delimiter?
 */
RTSUP_INLINE int why_is_block(const struct rtsup_cycle_state *cs, __u64 now, int voluntary)
{
	return voluntary && cs->start && !cs->in_delim && now;
}

/*
 * why_switch_out - the thread leaves its CPU inside a cycle: a block
 * (voluntary) starts at 'now', to be ended by a wakeup (why_take).
 */
RTSUP_INLINE void why_switch_out(struct rtsup_why *w, const struct rtsup_cycle_state *cs,
				 __u64 now, int voluntary, __u32 state)
{
	if (!why_is_block(cs, now, voluntary))
		return;
	w->out_ts = now;
	w->out_dstate = (state & WHY_TASK_UNINTERRUPTIBLE) != 0;
}

/* why_syscall - a syscall inside the cycle: the block it may cause is in it */
RTSUP_INLINE void why_syscall(struct rtsup_why *w, __u32 nr, __u32 futex_op)
{
	w->sys_nr = nr + 1;
	w->sys_op = futex_op;
}

/*
 * why_take - the thread ran after waiting on slot s (WHY_RAN): fold the
 * wait into its running cycle. A wakeup ends its delimiter's sleep (the
 * release: timer part) or a block inside the cycle (block part).
 */
RTSUP_SUBPROG void why_take(struct rtsup_why *w, const struct rtsup_cycle_state *cs,
			   const struct why_slot *s, __u32 cpu)
{
	struct rtsup_cause *c = &w->cur;
	__u64 span = s->ran > s->armed ? s->ran - s->armed : 0, b;

	why_culprit(c, &s->top, s->top_ns);
	/* the cycle's longest wait: when, where, behind whom (Perfetto) */
	if (span > c->held_to - c->held_from) {
		c->held_from = s->armed;
		c->held_to = s->ran;
		c->held_cpu = cpu;
		c->held_tid = s->top_ns ? s->top.tid : 0;
	}
	/*
	 * the cycle's longest holder is below the target: the scheduler could
	 * not take the CPU from it (a non-preemptible kernel section, softirq
	 * work in its context, interrupts off)
	 */
	if (s->top_ns && c->top[0].who.tid == s->top.tid)
		c->flags = (c->flags & ~RTSUP_CAUSE_F_BELOW) |
			   (why_below(s->policy, s->prio, &s->top) ? RTSUP_CAUSE_F_BELOW : 0);
	if (s->state & WHY_PREEMPTED) {
		c->preempt_ns += span;
		c->preempts++;
		return;
	}
	c->wait_ns += span;
	if (cs->in_delim) {
		/*
		 * the release: how late the wakeup came after the requested
		 * time, or after the delimiter's entry when that time was past
		 * already (a backlog, why_delim): a sleep on a past time still
		 * goes through its timer, which fires at once
		 */
		__u64 from = cs->expected + c->backlog_ns;

		if (cs->expected && s->armed > from) {
			c->timer_ns = s->armed - from;
			if (!s->waker.tid)
				c->flags |= RTSUP_CAUSE_F_IDLE;
		}
		w->out_ts = 0;
		return;
	}
	if (!w->out_ts || s->armed < w->out_ts)
		return;
	b = s->armed - w->out_ts;
	w->out_ts = 0;
	c->block_ns += b;
	c->blocks++;
	if (b <= c->block_max)
		return;
	c->block_max = b;
	c->block_nr = w->sys_nr;
	c->block_op = w->sys_op;
	c->waker = s->waker;
	c->block_woke = s->armed;
	c->block_ran = s->ran;
	c->flags &= ~(RTSUP_CAUSE_F_DSTATE | RTSUP_CAUSE_F_INVERSION);
	if (w->out_dstate)
		c->flags |= RTSUP_CAUSE_F_DSTATE;
	if (why_inversion(w->sys_op, s->policy, s->prio, &s->waker))
		c->flags |= RTSUP_CAUSE_F_INVERSION;
}

/*
 * why_migrate - sched_migrate_task of a target, from CPU 'from' to 'to':
 * why, as far as the kernel tells. A task whose CPU left its affinity mask
 * is moved by that change (sched_setaffinity, cpuset), also when the move
 * waits for its wakeup (a task that slept in the change, e.g. waiting for
 * the stopper that moves it, is placed at its wakeup); else a task being
 * woken (TASK_WAKING) is placed by its wakeup; else the scheduler moved it
 * where it was allowed to stay: load balance, RT push/pull.
 */
RTSUP_INLINE void why_migrate(struct rtsup_why *w, __u32 from, __u32 to, int waking,
			      int allowed)
{
	w->mig_from = from;
	w->mig_to = to;
	w->mig_why = !allowed ? RTSUP_MIG_AFFINITY : waking ? RTSUP_MIG_WAKEUP :
		     RTSUP_MIG_BALANCE;
}

/*
 * why_migrated - the thread runs on CPU 'cpu', another than before, inside
 * its cycle: the migration joins the cycle's cause, from the hook's record
 * when it is this one's. Returns the event's arg2 (RTSUP_MIG_ARG).
 */
RTSUP_SUBPROG __u64 why_migrated(struct rtsup_why *w, __u32 cpu)
{
	struct rtsup_cause *c = &w->cur;
	__u32 from = RTSUP_MIG_NOCPU, why = RTSUP_MIG_UNKNOWN;

	if (w->mig_why && w->mig_to == cpu) {
		from = w->mig_from;
		why = w->mig_why;
	}
	w->mig_why = 0;
	c->migrations++;
	c->mig_from = from;
	c->mig_to = cpu;
	c->mig_why = why;
	return RTSUP_MIG_ARG(from, cpu, why);
}

/*
 * why_move - a target waiting for CPU src (its slots 's') is moved to the
 * CPU of slots 'd' before it ran: its wait goes on there, from its start,
 * and the old CPU's slot is free (else it stayed armed, charging that
 * CPU's switches, until stale). 1 moved, 0 no wait to move, -1 both slots
 * there hold other targets' waits (the wait is dropped, counted).
 */
RTSUP_INLINE int why_move(struct why_slot *s, struct why_slot *d, __u32 tid, __u64 now)
{
	int i, j;

	for (i = 0; i < WHY_WAITERS; i++)
		if (s[i].tid == tid && !(s[i].state & WHY_RAN))
			break;
	if (i >= WHY_WAITERS)
		return 0;
	j = why_pick(d, tid, now);
	if (j >= 0 && j < WHY_WAITERS) {
		d[j] = s[i];
		d[j].since = now;
	}
	s[i].tid = 0;
	return j >= 0 ? 1 : -1;
}

/*
 * why_steal_in - the target runs on 'cpu' from now, whose steal counter
 * (the time its hypervisor ran something else on this vCPU, in ns) reads
 * 'steal'; a kernel that tells no steal reads 0 throughout.
 */
RTSUP_INLINE void why_steal_in(struct rtsup_why *w, __u32 cpu, __u64 steal)
{
	w->steal_cpu = cpu + 1;
	w->steal_in = steal;
}

/*
 * why_steal_out - the target leaves 'cpu' (or its cycle ends there): what
 * the host stole since its switch-in is the running cycle's. A switch-in
 * no hook marked, or one on another CPU (a counter of its own), adds nothing.
 */
RTSUP_INLINE void why_steal_out(struct rtsup_why *w, __u32 cpu, __u64 steal)
{
	if (w->steal_cpu == cpu + 1 && steal > w->steal_in)
		w->cur.steal_ns += steal - w->steal_in;
	w->steal_cpu = 0;
}

/*
 * cause_pick - the cause of a late cycle: its biggest part (ties go to the
 * first: the machine, then other tasks), and the task behind it; for a
 * wait or a preemption 'ns' is that task's share of it. Its own
 * CPU time ('cpu', less what the host stole while it ran) is the cause
 * only when it alone does not fit the nominal period, or when nothing
 * else took any time: a cycle released late by a backlog whose work fits
 * its period is late for that backlog; a part below 1/WHY_MINOR of its
 * CPU time is too small to be the cause.
 */
#define WHY_MINOR	8

RTSUP_INLINE void cause_pick(struct rtsup_cause *c, __u64 cpu, __u64 nominal)
{
	__u64 stolen = c->steal_ns < cpu ? c->steal_ns : cpu;
	__u64 part[RTSUP_CAUSE_NR] = {
		[RTSUP_CAUSE_TIMER] = c->timer_ns,
		[RTSUP_CAUSE_WAIT] = c->wait_ns,
		[RTSUP_CAUSE_PREEMPT] = c->preempt_ns,
		[RTSUP_CAUSE_BLOCK] = c->block_ns,
		[RTSUP_CAUSE_BACKLOG] = c->backlog_ns,
		[RTSUP_CAUSE_STEAL] = stolen,
	};
	/* the machine first: steal, then the timer, then other tasks */
	__u32 k, best = RTSUP_CAUSE_STEAL;

	cpu -= stolen;
	part[RTSUP_CAUSE_EXEC] = cpu;
	c->steal_ns = stolen;
	c->cpu_ns = cpu;
	for (k = RTSUP_CAUSE_TIMER; k < RTSUP_CAUSE_EXEC; k++)
		if (part[k] > part[best])
			best = k;
	if (!part[best] || (nominal && cpu > nominal) || part[best] < cpu / WHY_MINOR)
		best = RTSUP_CAUSE_EXEC;
	c->kind = best;
	c->ns = part[best];
	switch (best) {
	case RTSUP_CAUSE_WAIT:
	case RTSUP_CAUSE_PREEMPT:
		/* the culprit with its own share: others may have held the CPU too */
		c->who = c->top[0].who;
		if (c->top[0].ns)
			c->ns = c->top[0].ns;
		break;
	case RTSUP_CAUSE_BLOCK:
		c->who = c->waker;
		break;
	case RTSUP_CAUSE_BACKLOG:
		break;	/* inherited at the release (why_delim) */
	default:
		why_who_clear(&c->who);
	}
}

/*
 * why_delim - the thread enters its delimiter: a cycle that closed late
 * (CYC_EV_MISS in 'ev') gets its cause in w->out, and the next cycle
 * starts with nothing. Its release is already past (it will not sleep):
 * it starts late, its backlog, whose culprit is the late cycle's.
 */
RTSUP_INLINE void why_delim(struct rtsup_why *w, __u32 ev, __u64 cpu, __u64 nominal,
			    __u64 now, __u64 expected)
{
	int miss = (ev & CYC_EV_MISS) && expected && expected <= now;

	if (miss) {
		w->out = w->cur;
		cause_pick(&w->out, cpu, nominal);
	}
	why_reset(&w->cur);
	w->out_ts = 0;
	if (!miss)
		return;
	w->cur.backlog_ns = now - expected;
	w->cur.flags = RTSUP_CAUSE_F_INHERIT;
	w->cur.who = w->out.who;
	/* what made the first of a chain of late cycles late: the machine, a task */
	w->cur.after = w->out.kind == RTSUP_CAUSE_BACKLOG ? w->out.after : w->out.kind;
}

#endif /* RTSUP_CAUSE_H */
