/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * stackagg.h - where in the code: the user stacks captured at RT-unsafe
 * events (--stacks), symbolized, counted per (thread, reason, stack). Plain
 * C, no kernel, no libdw: the unit tests cover the counting and the text.
 */
#ifndef RTSUP_STACKAGG_H
#define RTSUP_STACKAGG_H

#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"

#define STACK_MAX_FRAMES	RTSUP_STACK_DEPTH
#define STACKAGG_MAX		1024	/* distinct stacks kept (up to 18 KiB each); more are counted */

/* Frame flags. */
#define FRAME_REPLACED	0x01	/* the module's file on disk is another build now */
#define FRAME_DELETED	0x02	/* the module's file was deleted */

/* One frame, as much as is known: function and line, or module and offset. */
struct stack_frame {
	__u64 pc;		/* the address in the process */
	__u64 offset;		/* address in the module's ELF file (its vaddr) */
	int line;		/* 0: unknown */
	__u32 flags;		/* FRAME_* */
	char func[96];		/* "" unknown */
	char file[128];		/* source file, "" unknown */
	char module[256];	/* the module's path, "" outside any module ([unknown]) */
	char build_id[41];	/* hex, "" unknown */
};

/* The events of one thread and reason that came from one stack. */
struct stack_entry {
	__u32 tid;
	__u32 tgid;
	__u32 reason;		/* enum rtsup_unsafe */
	__u32 nr;		/* the syscall, RTSUP_U_SYSCALL only */
	__u64 hash;		/* stack_hash of the frames */
	__u64 total;		/* events over the run */
	__u64 prev;		/* total at the end of the previous interval */
	__u32 kinds;		/* 1 << enum rtsup_stacks of each unwinder that took it */
	char comm[RTSUP_COMM_LEN];
	int nframes;
	struct stack_frame *frames;
};

struct stackagg {
	struct stack_entry *e;
	int n, cap;
	__u64 not_kept;		/* events of stacks beyond STACKAGG_MAX, or no memory */
	__u64 records;		/* stack records taken */
	/* the kernel side's counters (RTSUP_STK_*): records never sent */
	__u64 kernel[RTSUP_STK_NR];
};

/* stack_hash - what tells two stacks apart: each frame's module and offset */
__u64 stack_hash(const struct stack_frame *f, int n);
/* stackagg_add - one event from this stack; 0, or -1 when it was only counted */
int stackagg_add(struct stackagg *a, __u32 tid, __u32 tgid, const char *comm, __u32 reason,
		 __u32 nr, const struct stack_frame *f, int n);
/* stackagg_add_kind - the same, taken by the unwinder kind (0: not known) */
int stackagg_add_kind(struct stackagg *a, __u32 tid, __u32 tgid, const char *comm,
		      __u32 reason, __u32 nr, __u32 kind, const struct stack_frame *f, int n);
/* stackagg_interval_end - the interval's counts start again from here */
void stackagg_interval_end(struct stackagg *a);
/* stack_entry_interval - the entry's events in the interval */
static inline __u64 stack_entry_interval(const struct stack_entry *e)
{
	return e->total - e->prev;
}
/* stackagg_free - every entry and its frames */
void stackagg_free(struct stackagg *a);

/*
 * frame_format - one frame: "ctrl_update() ctrl.c:88", "mmap64()
 * (libc.so.6+0x10a2f0)", "libfoo.so+0x1234 (build-id 1a2b...)", "[unknown]
 * 0x7f..."; a module replaced on disk says so
 */
void frame_format(const struct stack_frame *f, char *buf, size_t len);
/* stack_format - innermost first, joined by " <- " (sep) */
void stack_format(const struct stack_frame *f, int n, const char *sep, char *buf, size_t len);

#endif
