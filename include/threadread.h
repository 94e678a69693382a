/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * threadread.h - the collector's read of the thread map copies out only
 * the entries that changed. Shared by BPF and userspace (unit tested).
 *
 * A robot's many threads are mostly parked: copying each one's 7 KiB entry
 * every interval to find it unchanged was most of rtsup-trace's CPU time
 * with 900 parked threads. Every hook that looks an entry up to write it
 * moves the entry's generation (thread_touch); the map iterator of the
 * sample (threads_read) sends nothing for an entry whose generation did not
 * move (a short record when it read its task, thread_rec_skipped), and a
 * record that asks for a copy for one whose did.
 *
 * A hook moves the generation before it writes (at the lookup), so a copy
 * taken while a hook runs may miss that hook's last writes. Every change
 * is therefore copied twice: once when the generation moved, and once more
 * at the next read, an interval later, when every hook that moved it has
 * long returned (hooks run for microseconds, intervals last 100 ms or
 * more). No barrier is needed, on any architecture.
 *
 * Walking the map still visits every entry: with 900 parked threads that
 * visit (a cache miss each) was the largest cost left. So the hooks also
 * say which entries moved: the first time a hook looks an entry up after
 * the collector began a read (threads_moved_seq), it sends the tid and
 * slot to the ring "moved" (thread_moved_due). Most samples the collector copies only
 * those entries, and the ones it copied at the sample before (the second
 * copy), a copy from its memory each, and visits no other (thread_read_whole says when
 * the iterator reads the whole map instead).
 */
#ifndef RTSUP_THREADREAD_H
#define RTSUP_THREADREAD_H

#include "rtsup.h"

/*
 * Where the entries are: the map "threads" holds tid -> slot, and the
 * entry is slot's element of "thread_mem", an array the collector maps
 * into its memory and copies from in place, without a syscall or the
 * kernel's two copies of a lookup (a quarter of rtsup-trace's CPU with
 * 1000 running threads). A slot not in use waits in the queue
 * "thread_free": the hooks take one for a thread they add, the collector
 * for one its start-up scan adds, and gives it back when it reaps the
 * entry (after zeroing its tid, so a stale slot is never taken for it).
 */
#define THREAD_NO_SLOT	(~0U)	/* a record that names no slot: look the tid up */

/* thread_slot_ok - is slot an element of thread_mem's n? */
RTSUP_INLINE int thread_slot_ok(__u32 slot, __u32 n)
{
	return slot < n;
}

/*
 * What the iterator writes for each entry: this, then the task's attributes
 * when 'task' is THREAD_TASK_ATTRS. 'full' asks the collector to copy the
 * entry at 'slot' now (thread_copy_due).
 */
struct rtsup_thread_rec {
	__u32 tid;
	__u32 slot;	/* of thread_mem */
	__u16 full;	/* 1: copy the entry */
	__u16 task;	/* enum thread_task */
	__u32 pad;	/* the attributes that follow start 8-byte aligned */
};

/* What a hook sends to the ring "moved": the entry it looked up. */
struct rtsup_moved_rec {
	__u32 tid;
	__u32 slot;
};

/*
 * Where bpf_task_from_pid is (6.2+), the iterator reads the task of each
 * entry too (threads_read_attrs): its attributes every sample for the cost
 * of one pid lookup, not a walk of every task on the machine (attrs_task).
 */
enum thread_task {
	THREAD_TASK_UNREAD,	/* threads_read: the task iterator reads them */
	THREAD_TASK_GONE,	/* no task has the tid any more */
	THREAD_TASK_ATTRS,	/* a struct rtsup_task_attrs follows */
};

/*
 * Which entries' tasks a read of the iterator reads (threads_read_tasks),
 * thread_read_tasks says: without the ring, those thread_task_due picks;
 * with it, every entry's at the reads that must see them all, and none at
 * a walk taken only because it costs less than the lookups (1000 running
 * threads: their switch-outs say when their attributes move,
 * thread_sched_seen, and the pid lookups were a sixth of the read).
 */
enum thread_tasks_read {
	THREAD_TASKS_DUE,
	THREAD_TASKS_ALL,
	THREAD_TASKS_NONE,
};

/*
 * thread_task_due - does the iterator read the task of an entry (of
 * generation gen, reader fields seen and again) at read 'seq', in mode
 * 'which' (enum thread_tasks_read)? The pid lookup costs about as much as
 * the rest of the visit: an entry that moved since its last copy is read
 * every time, one that did not (a parked thread: only another thread can
 * change its attributes) every THREAD_TASK_EVERY reads, spread over the
 * tids, and whenever it moves again.
 */
#define THREAD_TASK_EVERY	8

RTSUP_INLINE int thread_task_due(__u32 gen, __u32 seen, __u32 again, __u32 tid, __u32 seq,
				 __u32 which)
{
	if (which != THREAD_TASKS_DUE)
		return which == THREAD_TASKS_ALL;
	return seen != gen + 1 || again || (tid + seq) % THREAD_TASK_EVERY == 0;
}

/*
 * thread_moved_due - must a hook that just looked an entry up send its tid
 * to the ring "moved"? Once per read: moved_seq is the read (of
 * threads_moved_seq, never 0) it was last sent for. A send that failed
 * (the ring full) leaves moved_seq, so the next lookup tries again, and
 * threads_moved_lost makes the collector's next read whole.
 */
RTSUP_INLINE int thread_moved_due(__u32 moved_seq, __u32 read_seq)
{
	return moved_seq != read_seq;
}

/*
 * thread_sched_seen - at a target's switch-out, its policy, RT priority and
 * number of allowed CPUs (every switch-out looks its entry up, not every
 * switch-in: rtsup.h): not those of the last one, they changed
 * (whoever changed them: the thread, another one, chrt, taskset), and the
 * collector reads its attributes at the next sample (setsched), not at the
 * next whole read. A move to another cgroup makes the next read whole
 * (threads_attrs_moved); only a new mask of as many CPUs waits for the
 * whole read of every THREAD_TASK_EVERY-th sample. Three loads of fields
 * the scheduler just read, for targets only. A parked thread has no
 * switch-out: its changes wait for the whole read, as before.
 */
/* thread_sched_word - what thread_sched_seen keeps of a switch-out's attributes */
RTSUP_INLINE __u32 thread_sched_word(__u32 policy, __u32 rt_priority, __u32 nr_cpus)
{
	return policy << 28 | (rt_priority & 0xff) << 20 | (nr_cpus & 0xfffff);
}

RTSUP_INLINE void thread_sched_seen(struct rtsup_thread *t, __u32 policy, __u32 rt_priority,
				    __u32 nr_cpus)
{
	__u32 v = thread_sched_word(policy, rt_priority, nr_cpus);

	if (t->sched_seen != v) {
		t->sched_seen = v;
		t->setsched++;
	}
}

/*
 * thread_moved_ring_bytes - the ring "moved" for max_threads entries: each
 * is sent at most once a read (a record of 16 bytes: its header, tid and slot),
 * and twice between two reads of the collector at most (once before it
 * moved threads_moved_seq, once after); a power of 2 of pages, as the
 * kernel wants
 */
RTSUP_INLINE __u32 thread_moved_ring_bytes(__u32 max_threads, __u32 page)
{
	__u64 need = (__u64)max_threads * 2 * 16, n = page;

	while (n < need)
		n *= 2;
	return (__u32)n;
}

/*
 * thread_read_whole - does the collector's read of sample 'seq' walk the
 * whole map (the iterator, or batches) rather than copy only the entries
 * the ring named? Whole when:
 * - there is no ring (moved_ok false);
 * - the first two samples (entries the start-up scan wrote; their second copy);
 * - every THREAD_TASK_EVERY-th sample: the tasks' attributes of every entry
 *   (only another thread changes a parked one's), and a net under the ring;
 * - forced: a send to the ring failed, or a task moved to another cgroup
 *   (threads_attrs_moved: the tasks of every entry are read);
 * - the lookups of the entries due (ndue, a tid named twice counted
 *   twice) would cost more than the walk: THREAD_LOOKUP_VISITS visits of
 *   an entry that did not move each, and the walk's fixed part costs
 *   THREAD_WALK_LOOKUPS lookups (a lookup and its copy ~1 us, a visit
 *   0.26 us, the walk's buckets and file ~100 us: docs/performance.md).
 *   The copies from thread_mem took the syscall out of a lookup, yet all
 *   1000 threads running, read by name, still cost more than the walk
 *   (5.6 against 4.7 % of a CPU at 100 ms intervals): the rule stays.
 */
#define THREAD_LOOKUP_VISITS	4
#define THREAD_WALK_LOOKUPS	100

/* thread_read_all - a read with the ring that must see every entry and its task */
RTSUP_INLINE int thread_read_all(__u64 seq, int forced)
{
	return seq <= 2 || seq % THREAD_TASK_EVERY == 0 || forced;
}

RTSUP_INLINE int thread_read_whole(int moved_ok, __u64 seq, int forced, __u32 ndue,
				   __u32 nentries)
{
	__u64 walk = (__u64)nentries + THREAD_WALK_LOOKUPS * THREAD_LOOKUP_VISITS;

	return !moved_ok || thread_read_all(seq, forced) ||
	       (__u64)ndue * THREAD_LOOKUP_VISITS > walk;
}

/*
 * thread_read_tasks - the tasks a whole read of sample seq reads (enum
 * thread_tasks_read). A walk only cheaper than the lookups reads none: a
 * task whose attributes the collector holds from an earlier read keeps
 * them (the switch-outs and the cgroup hook say when they move), and one
 * it holds none for is asked of the kernel, as in a read of the named.
 */
RTSUP_INLINE __u32 thread_read_tasks(int moved_ok, __u64 seq, int forced)
{
	if (!moved_ok)
		return THREAD_TASKS_DUE;
	return thread_read_all(seq, forced) ? THREAD_TASKS_ALL : THREAD_TASKS_NONE;
}

/*
 * Without bpf_task_from_pid (before 6.2), or where the kernel refuses the
 * thread map's iterator (EPERM at load on some kernels, an empty one too),
 * the targets' attributes come from the task iterator (attrs_task): a walk
 * of every task on the machine. thread_walk_tasks - does the sample seq
 * take that walk? As the thread map's iterator reads every task's
 * (thread_read_tasks): at the reads that must see every entry
 * (thread_read_all, forced: a send to the ring lost, a cgroup move), and
 * between them the attributes last read are kept until the thread's
 * switch-outs say they moved (thread_sched_seen). Also when more threads
 * had none to keep at the last sample than THREAD_WALK_ASKS (a storm of
 * new ones, each asked of the kernel: three syscalls and a /proc read),
 * and at every sample without the ring. The walk every sample was a third
 * of rtsup-trace's CPU with 100 running and 900 parked threads.
 */
#define THREAD_WALK_ASKS	64

RTSUP_INLINE int thread_walk_tasks(int moved_ok, __u64 seq, int forced, __u32 asked)
{
	return !moved_ok || thread_read_all(seq, forced) || asked > THREAD_WALK_ASKS;
}

#ifndef __bpf__
#include <stddef.h>
#include <string.h>
#include "stats.h"

/*
 * thread_copy_short - t's fields into *out, and of its buckets only those
 * between the lowest and highest values of each metric's interval banks,
 * read from the counts copied (metric_banks_range): the buckets the
 * values since the last read went to, ~15 cache lines of 95. The others
 * stay as they were in *out (the model's check: model_set_sent).
 * Userspace only.
 */
static inline void thread_copy_short(struct rtsup_thread *out, const struct rtsup_thread *t)
{
	int i, a, b;

	memcpy(out, t, offsetof(struct rtsup_thread, m));
	for (i = 0; i < RTSUP_M_NR; i++) {
		memcpy(&out->m[i], &t->m[i], offsetof(struct rtsup_metric_stats, hist));
		metric_banks_range(&out->m[i], &a, &b);
		if (a <= b)
			memcpy(&out->m[i].hist[a], &t->m[i].hist[a],
			       (size_t)(b - a + 1) * sizeof(t->m[i].hist[0]));
	}
}
#endif

#ifndef __bpf__
/*
 * thread_attrs_as_seen - attributes a, read of the task, are what its
 * last switch-out saw (sched_seen): a setsched that moved since they were
 * read moved nothing they hold. A thread's first switch-out under the
 * tracer moves it from unknown (0), its attributes as they were: a thread
 * parked when the tracer started and woken later was asked of the kernel
 * at each sample until the next whole read. Userspace only.
 */
static inline int thread_attrs_as_seen(__u32 sched_seen, const struct rtsup_task_attrs *a)
{
	__u32 i, n = 0;

	for (i = 0; i < a->cpu_words && i < RTSUP_ATTR_CPU_WORDS; i++)
		n += (__u32)__builtin_popcountll(a->cpus[i]);
	return sched_seen == thread_sched_word((__u32)a->policy, a->rt_priority, n);
}
#endif

/* thread_rec_len - the bytes of a record with its followers */
RTSUP_INLINE __u32 thread_rec_len(const struct rtsup_thread_rec *r)
{
	return sizeof(*r) + (r->task == THREAD_TASK_ATTRS ? sizeof(struct rtsup_task_attrs) : 0);
}

/* thread_touch - a hook may write t: its generation moves */
RTSUP_INLINE void thread_touch(struct rtsup_thread *t)
{
	t->gen++;
}

/*
 * thread_copy_due - must the reader copy an entry of generation gen out?
 * seen and again are the reader's own fields of the entry (hooks never
 * write them): seen is gen + 1 as last copied (0: never copied, so a new
 * entry is copied whatever its generation), again asks for the second copy.
 */
RTSUP_INLINE int thread_copy_due(__u32 gen, __u32 *seen, __u32 *again)
{
	if (*seen != gen + 1) {
		*seen = gen + 1;
		*again = 1;
		return 1;
	}
	if (*again) {
		*again = 0;
		return 1;
	}
	return 0;
}

/*
 * thread_copied - the reader copied an entry of generation gen (a read
 * the iterator had no say in): its fields as thread_copy_due leaves them,
 * so that the rule says when the next copy is due
 */
RTSUP_INLINE void thread_copied(__u32 gen, __u32 *seen, __u32 *again)
{
	*again = *seen != gen + 1;
	*seen = gen + 1;
}

/*
 * thread_rec_skipped - no record at all for an entry that is not copied
 * and whose task was not read: the collector keeps what it holds of it
 * (collector.c, take_kept). That is right only because entries leave the
 * map by the collector alone, after it reported them: an entry the read
 * did not show is one it did not copy, not one that went away.
 */
RTSUP_INLINE int thread_rec_skipped(__u16 full, __u16 task)
{
	return !full && task == THREAD_TASK_UNREAD;
}

/*
 * thread_rec_normalize - the reader's fields of a copy zeroed: two copies
 * of an entry no hook wrote in between are the same bytes (the model
 * takes such an interval as empty without reading it)
 */
RTSUP_INLINE void thread_rec_normalize(struct rtsup_thread *t)
{
	t->read_seen = 0;
	t->read_again = 0;
	t->moved_seq = 0;
}

#endif
