/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * threadread.bpf.h - the thread map iterator's visit of one entry and the
 * task attributes it may write, shared by rtsup.bpf.c (threads_read,
 * attrs_task) and rtsup_tasks.bpf.c (threads_read_attrs): the record
 * format is include/threadread.h.
 */
#ifndef RTSUP_THREADREAD_BPF_H
#define RTSUP_THREADREAD_BPF_H

#include <vmlinux.h>
#include <bpf/bpf_helpers.h>
#include "threadread.h"

/* task_attrs_fill - a task's policy, RT priority, cgroup v2 id and allowed CPUs */
static __always_inline int task_attrs_fill(struct task_struct *task, struct rtsup_task_attrs *a)
{
	__u32 sz = bpf_core_field_size(task->cpus_mask);

	a->tid = task->pid;
	a->policy = task->policy;
	a->rt_priority = task->rt_priority;
	/* BTF pointers: plain loads, not a helper call per pointer */
	a->cgroup_id = task->cgroups->dfl_cgrp->kn->id;
	if (sz > sizeof(a->cpus))
		sz = sizeof(a->cpus);
	if (bpf_probe_read_kernel(a->cpus, sz, &task->cpus_mask))
		return -1;
	a->cpu_words = sz / 8;
	return 0;
}

/*
 * thread_rec_write - an entry's record: its task's attributes a when task
 * says so (enum thread_task), and whether the collector copies the entry
 * (at slot of thread_mem) because it changed (threadread.h), unless
 * no_copy (a batch read copies them); nothing when neither
 * (thread_rec_skipped). When the read's buffer is full the entry is shown
 * again by the next read: its reader fields go back.
 */
static __always_inline int thread_rec_write(struct seq_file *seq, __u32 tid, __u32 slot,
					    struct rtsup_thread *t, __u16 task,
					    const struct rtsup_task_attrs *a, bool no_copy)
{
	struct rtsup_thread_rec r = { .tid = tid, .slot = slot, .task = task };
	__u32 seen = t->read_seen, again = t->read_again;

	r.full = !no_copy && thread_copy_due(t->gen, &t->read_seen, &t->read_again);
	if (thread_rec_skipped(r.full, task))
		return 0;
	if (bpf_seq_write(seq, &r, sizeof(r)) ||
	    (task == THREAD_TASK_ATTRS && bpf_seq_write(seq, a, sizeof(*a)))) {
		t->read_seen = seen;
		t->read_again = again;
	}
	return 0;
}

#endif
