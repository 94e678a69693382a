/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * rtfollow.h - --rt: which threads are RT, decided when the kernel changes
 * a policy, not at every context switch. Shared by BPF and userspace (the
 * unit tests feed it policy changes).
 *
 * A thread's policy changes in two places only: __sched_setscheduler (the
 * syscalls sched_setscheduler, sched_setparam and sched_setattr, and the
 * kernel's own sched_set_fifo() and friends for kernel threads) and fork
 * (the child inherits it, unless SCHED_RESET_ON_FORK). exec keeps it. So
 * the start-up scan, the fork hook and a hook after __sched_setscheduler
 * see every thread that becomes RT and every one that leaves.
 *
 * Priority inheritance boosts a task's priority, not its policy: a
 * SCHED_OTHER lock holder boosted by an RT waiter is no target (its boost
 * is the waiter's cause, cause.h).
 */
#ifndef RTSUP_RTFOLLOW_H
#define RTSUP_RTFOLLOW_H

#include "rtsup.h"

/* the kernel function every policy change goes through: fexit attaches to it */
#define RTSUP_RT_HOOK_FN	"__sched_setscheduler"

#define RTF_SCHED_FIFO		1
#define RTF_SCHED_RR		2
#define RTF_SCHED_DEADLINE	6

/* rtsup_thread.rt: how --rt holds a thread */
#define RTSUP_RT_ONLY	1	/* a target because it is RT, nothing else */
#define RTSUP_RT_LEFT	2	/* left RT: userspace reports it once, then drops it */

/* rt_policy - a policy --rt follows: SCHED_FIFO, SCHED_RR, SCHED_DEADLINE */
RTSUP_INLINE int rt_policy(__u32 policy)
{
	return policy == RTF_SCHED_FIFO || policy == RTF_SCHED_RR ||
	       policy == RTF_SCHED_DEADLINE;
}

/*
 * rt_entry_stale - an entry that belongs to no running target: its thread
 * exited (the tid is reused) or left RT. Whoever adds the tid again starts
 * it anew, with a new first_seen, so userspace never drops the new one for
 * the old one (collector.c, same_thread).
 */
RTSUP_INLINE int rt_entry_stale(const struct rtsup_thread *t)
{
	return t->exited || (t->rt & RTSUP_RT_LEFT);
}

enum rt_change {
	RT_KEEP,	/* nothing to do */
	RT_ADOPT,	/* a new target; an entry that left RT starts anew (rt_entry_stale) */
	RT_LET_GO,	/* mark it RTSUP_RT_LEFT */
};

/*
 * rt_on_policy - a thread's policy is now 'policy'; t is its entry (NULL:
 * none). Only a thread that --rt alone made a target is let go: a -p,
 * --comm or --cgroup target stays one whatever its policy.
 */
RTSUP_INLINE enum rt_change rt_on_policy(__u32 policy, const struct rtsup_thread *t)
{
	if (rt_policy(policy))
		return !t || rt_entry_stale(t) ? RT_ADOPT : RT_KEEP;
	if (t && !rt_entry_stale(t) && (t->rt & RTSUP_RT_ONLY))
		return RT_LET_GO;
	return RT_KEEP;
}

/* PF_EXITING in task_struct.flags: set by exit_signals() early in do_exit */
#define RTF_PF_EXITING		0x00000004

/*
 * rt_on_switch_in - --rt without the policy hook: the policy read at a
 * task's switch-in stands in for it. A task in do_exit is never adopted:
 * its exit event is past, and once userspace has reaped its exited entry
 * it can still block and switch in (freeing its memory, closing files).
 * Adopted, it was a new thread of the same tid that no exit ended, and the
 * model dropped the old one for it (rt-6.12: 498 cycles reported as 8).
 * An exited entry stays as it is, whatever the policy.
 */
RTSUP_INLINE enum rt_change rt_on_switch_in(__u32 policy, __u32 task_flags,
					    const struct rtsup_thread *t)
{
	if ((task_flags & RTF_PF_EXITING) || (t && t->exited))
		return RT_KEEP;
	return rt_on_policy(policy, t);
}

/*
 * rt_mark_left - carry out an RT_LET_GO on entry t: marked RTSUP_RT_LEFT,
 * unless its process is a target (--comm, exec or -- CMD made it one after
 * --rt took the thread): such a thread stays. Returns 1 when marked. The
 * hook, the per-switch fallback and userspace's policy read all let go here.
 */
RTSUP_INLINE int rt_mark_left(struct rtsup_thread *t, int process_is_target)
{
	if (!t || process_is_target)
		return 0;
	t->rt |= RTSUP_RT_LEFT;
	return 1;
}

#endif
