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
 * move (a short record when it read its task, thread_rec_skipped), and the
 * whole entry for one whose did.
 *
 * A hook moves the generation before it writes (at the lookup), so a copy
 * taken while a hook runs may miss that hook's last writes. Every change
 * is therefore copied twice: once when the generation moved, and once more
 * at the next read, an interval later, when every hook that moved it has
 * long returned (hooks run for microseconds, intervals last 100 ms or
 * more). No barrier is needed, on any architecture.
 */
#ifndef RTSUP_THREADREAD_H
#define RTSUP_THREADREAD_H

#include "rtsup.h"

/*
 * What the iterator writes for each entry: this, then the task's attributes
 * when 'task' is THREAD_TASK_ATTRS, then the entry when 'full'.
 */
struct rtsup_thread_rec {
	__u32 tid;
	__u16 full;	/* 1: a struct rtsup_thread follows */
	__u16 task;	/* enum thread_task */
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
 * thread_task_due - does the iterator read the task of an entry (of
 * generation gen, reader fields seen and again) at read 'seq'? The pid
 * lookup costs about as much as the rest of the visit: an entry that moved
 * since its last copy is read every time, one that did not (a parked
 * thread: only another thread can change its attributes) every
 * THREAD_TASK_EVERY reads, spread over the tids, and whenever it moves again.
 */
#define THREAD_TASK_EVERY	8

RTSUP_INLINE int thread_task_due(__u32 gen, __u32 seen, __u32 again, __u32 tid, __u32 seq)
{
	return seen != gen + 1 || again || (tid + seq) % THREAD_TASK_EVERY == 0;
}

/* thread_rec_len - the bytes of a record with its followers */
RTSUP_INLINE __u32 thread_rec_len(const struct rtsup_thread_rec *r)
{
	return sizeof(*r) + (r->task == THREAD_TASK_ATTRS ? sizeof(struct rtsup_task_attrs) : 0) +
	       (r->full ? sizeof(struct rtsup_thread) : 0);
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
}

#endif
