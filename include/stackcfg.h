/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * stackcfg.h - which unwinder captures a thread's stack at an RT-unsafe
 * event (--stacks, a rule's stacks:), shared by BPF and the unit tests.
 *
 * Three places say it, the narrowest wins: --stacks and --stack-size (rodata),
 * the thread's configuration rule (map "stack_cfg", by tid), and for auto
 * its process's verdict (map "stack_auto", by tgid: frame pointers when every
 * module of the process keeps them, user/collect/fpcheck.c). Until userspace
 * has looked at a process, auto is DWARF: it unwinds code with and without
 * frame pointers, a frame-pointer walk only the first. Looked up only at a
 * captured event, never on a clean cycle's path.
 */
#ifndef RTSUP_STACKCFG_H
#define RTSUP_STACKCFG_H

#include "rtsup.h"

/* stack_rule - a thread's unwinder and size: its rule's (rc), else the command line's */
RTSUP_INLINE struct rtsup_stack_cfg stack_rule(__u32 kind, __u32 size,
					       const struct rtsup_stack_cfg *rc)
{
	struct rtsup_stack_cfg c = { .kind = kind, .size = size };

	if (rc)
		c = *rc;
	return c;
}

/* stack_auto_kind - auto's unwinder for a process: its verdict (pk), DWARF without one */
RTSUP_INLINE __u32 stack_auto_kind(const __u32 *pk)
{
	return pk && *pk == RTSUP_STACKS_FP ? RTSUP_STACKS_FP : RTSUP_STACKS_DWARF;
}

/*
 * stack_dump_size - bytes of user stack to copy: the thread's size, within
 * the record's room (max, what every DWARF record reserves), 8-aligned
 */
RTSUP_INLINE __u32 stack_dump_size(__u32 size, __u32 max)
{
	if (size > max)
		size = max;
	return size & ~7U;
}

#endif
