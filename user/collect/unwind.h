/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * unwind.h - a stack record of the kernel side (struct rtsup_stack_rec) to
 * symbolized frames: frame pointers as the kernel walked them, or DWARF
 * unwinding of the copied registers and stack with elfutils' libdwfl; then
 * function, file:line where debug info exists, module+offset otherwise.
 * The mappings of a process are read when it is first seen
 * (unwind_note_process) and kept after it is gone.
 */
#ifndef RTSUP_UNWIND_H
#define RTSUP_UNWIND_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"
#include "model/stackagg.h"

struct unwinder;
struct procmap;

/* The mappings a process's stacks are symbolized with, for the recorded trace. */
struct stack_maps {
	__u32 gen;		/* changes when they are read again */
	int n;
	const struct procmap *maps;
	const __u32 *flags;	/* FRAME_* */
	const char (*bids)[48];	/* build-ids, hex */
};

/* unwinder_new - an empty cache of processes; NULL without memory */
struct unwinder *unwinder_new(void);
/* unwind_note_process - read a target process's mappings now, if not yet */
void unwind_note_process(struct unwinder *u, __u32 tgid);
/*
 * unwinder_set_auto - --stacks auto: judge each process's frame pointers
 * (fpcheck.h) whenever its mappings are read
 */
void unwinder_set_auto(struct unwinder *u, bool on);
/*
 * unwind_take_verdicts - fn(ctx, tgid, RTSUP_STACKS_FP or _DWARF) for each
 * process whose verdict is new since the last call
 */
void unwind_take_verdicts(struct unwinder *u, void (*fn)(void *ctx, __u32 tgid, __u32 kind),
			  void *ctx);
/*
 * unwind_record - the frames of one stack record, innermost first: how
 * many (0: none could be read), at most max; -1 for an exec mark, which
 * has no stack (RTSUP_STACK_EXEC)
 */
int unwind_record(struct unwinder *u, const struct rtsup_stack_rec *r, size_t len,
		  struct stack_frame *out, int max);
/*
 * unwind_maps - the mappings a process's stacks were symbolized with, and
 * their set's generation (it changes when they are read again): for the
 * recorded trace (REC_MODULE). Their count, 0 for a process not known.
 */
int unwind_maps(struct unwinder *u, __u32 tgid, struct stack_maps *m);
/* unwind_offline_map - replay: one recorded mapping; a new gen replaces the set */
void unwind_offline_map(struct unwinder *u, __u32 tgid, __u32 gen, const struct procmap *m,
			__u32 flags, const char *build_id);
/* unwind_offline_pcs - replay: recorded pcs (the first exact) to frames */
int unwind_offline_pcs(struct unwinder *u, __u32 tgid, const __u64 *pcs, int n,
		       struct stack_frame *out, int max);
void unwinder_free(struct unwinder *u);

#endif
