/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * core_fixes.bpf.h - CO-RE shims for kernel structure changes, each naming
 * the kernel commit that made it necessary.
 */
#ifndef RTSUP_CORE_FIXES_BPF_H
#define RTSUP_CORE_FIXES_BPF_H

#include <vmlinux.h>
#include <bpf/bpf_core_read.h>

/*
 * Kernel commit 2f064a59a11f ("sched: Change task_struct::state") renamed
 * task_struct::state to __state (v5.14).
 */
struct task_struct___o {
	volatile long int state;
} __attribute__((preserve_access_index));

/* get_task_state - the scheduler state word of a task */
static __always_inline __s64 get_task_state(void *task)
{
	struct task_struct___o *t = task;

	if (bpf_core_field_exists(t->state))
		return BPF_CORE_READ(t, state);
	return BPF_CORE_READ((struct task_struct *)task, __state);
}

/* get_task_state_btf - the same with plain loads, for a BTF pointer (tp_btf) */
static __always_inline __s64 get_task_state_btf(struct task_struct *task)
{
	struct task_struct___o *t = (void *)task;

	if (bpf_core_field_exists(t->state))
		return t->state;
	return task->__state;
}

#endif /* RTSUP_CORE_FIXES_BPF_H */
