// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * rtsup_tasks.bpf.c - the thread map's iterator that reads each entry's
 * task too (threadread.h): its own object, loaded only where the kernel
 * has the bpf_task_from_pid kfunc (6.2+). In rtsup.bpf.c, even a weak
 * extern it does not have stopped libbpf from loading anything without
 * CAP_SYS_ADMIN (the service's capabilities): libbpf 1.1 then looks for it
 * in the modules' BTF, which it may not list.
 */
#include <vmlinux.h>
#include <bpf/bpf_helpers.h>
#include <bpf/bpf_tracing.h>
#include <bpf/bpf_core_read.h>

#define RTSUP_INLINE static __always_inline
#include "rtsup.h"
#include "threadread.bpf.h"

extern struct task_struct *bpf_task_from_pid(s32 pid) __ksym;
extern void bpf_task_release(struct task_struct *p) __ksym;

/* rtsup.bpf.c's entries (threadread.h): the loader gives this object its fd. */
struct {
	__uint(type, BPF_MAP_TYPE_ARRAY);
	__uint(map_flags, BPF_F_MMAPABLE);
	__uint(max_entries, RTSUP_DEFAULT_THREADS);
	__type(key, __u32);
	__type(value, struct rtsup_thread);
} thread_mem SEC(".maps");

/* Written by the collector before each read. */
__u32 threads_read_tasks_only;	/* copy no entry: a batch read does */
__u32 threads_read_seq;		/* its sample: which parked entries' tasks (thread_task_due) */
__u32 threads_read_tasks;	/* whose tasks: enum thread_tasks_read */

/*
 * task_of_entry - the attributes of the task with the entry's tid; enum
 * thread_task
 */
static __always_inline __u16 task_of_entry(__u32 tid, struct rtsup_task_attrs *a)
{
	struct task_struct *task = bpf_task_from_pid(tid);
	int err;

	if (!task)
		return THREAD_TASK_GONE;
	__builtin_memset(a, 0, sizeof(*a));
	err = task_attrs_fill(task, a);
	bpf_task_release(task);
	/* unreadable: as the task iterator, no record (the collector asks the kernel) */
	return err ? THREAD_TASK_UNREAD : THREAD_TASK_ATTRS;
}

/* the collector's read of the thread map a sample, changed entries whole, and their tasks */
SEC("iter/bpf_map_elem")
int threads_read_attrs(struct bpf_iter__bpf_map_elem *ctx)
{
	__u32 *tid = ctx->key, *at = ctx->value, slot;
	struct rtsup_task_attrs a;	/* written when read (task_of_entry) */
	__u16 task = THREAD_TASK_UNREAD;
	struct rtsup_thread *t;

	if (!tid || !at)
		return 0;
	slot = *at;
	t = bpf_map_lookup_elem(&thread_mem, &slot);
	if (!t)
		return 0;
	if (thread_task_due(t->gen, t->read_seen, t->read_again, *tid, threads_read_seq,
			    threads_read_tasks))
		task = task_of_entry(*tid, &a);
	return thread_rec_write(ctx->meta->seq, *tid, slot, t, task, &a, threads_read_tasks_only);
}

char LICENSE[] SEC("license") = "Dual BSD/GPL";
