/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * movedset.h - the thread map's entries a read copies when it does not
 * walk the whole map (threadread.h): those the hooks named in the ring
 * "moved" since the last read, and those named the read before (the
 * second copy of a change, taken when every hook that wrote it returned).
 */
#ifndef RTSUP_MOVEDSET_H
#define RTSUP_MOVEDSET_H

#include <linux/types.h>
#include "threadread.h"

struct ring_buffer;

/* the entries named: tid, and the slot it was at (THREAD_NO_SLOT: look it up) */
struct tid_list {
	struct rtsup_moved_rec *at;
	__u32 n, cap;
};

struct movedset {
	struct ring_buffer *rb;	/* NULL: no ring, every read is whole */
	struct tid_list now;	/* named since the last read, or written by userspace */
	struct tid_list again;	/* named for the last read: copied once more */
	int err;		/* out of memory while named: the read is whole */
};

/* movedset_open - read the ring of map fd ring_fd; -errno */
int movedset_open(struct movedset *ms, int ring_fd);
/* movedset_note - userspace wrote tid's entry (the start-up scan): due at the next read */
void movedset_note(struct movedset *ms, __u32 tid, __u32 slot);
/*
 * movedset_begin - a read starts: *read_seq moves first (a hook that looks
 * an entry up from now on names it again), then the ring is drained;
 * -errno when the tids named cannot all be kept (the read must be whole)
 */
int movedset_begin(struct movedset *ms, volatile __u32 *read_seq);
/* movedset_due - the entries due at this read, with repeats */
static inline __u32 movedset_due(const struct movedset *ms)
{
	return ms->now.n + ms->again.n;
}
/* movedset_end - the read is over: those named for it are copied again at the next */
void movedset_end(struct movedset *ms);
void movedset_free(struct movedset *ms);

#endif
