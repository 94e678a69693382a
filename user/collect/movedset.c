// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* movedset.c - the entries named by the ring "moved" (movedset.h) */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <bpf/libbpf.h>
#include "collect/movedset.h"

static int tid_push(struct tid_list *l, __u32 tid, __u32 slot)
{
	if (l->n == l->cap) {
		__u32 cap = l->cap ? l->cap * 2 : 256;
		struct rtsup_moved_rec *t = realloc(l->at, cap * sizeof(*t));

		if (!t)
			return -ENOMEM;
		l->at = t;
		l->cap = cap;
	}
	l->at[l->n++] = (struct rtsup_moved_rec){ .tid = tid, .slot = slot };
	return 0;
}

static int on_moved(void *ctx, void *data, size_t len)
{
	struct rtsup_moved_rec r;

	if (len < sizeof(r))
		return 0;
	memcpy(&r, data, sizeof(r));
	movedset_note(ctx, r.tid, r.slot);
	return 0;
}

int movedset_open(struct movedset *ms, int ring_fd)
{
	memset(ms, 0, sizeof(*ms));
	ms->rb = ring_buffer__new(ring_fd, on_moved, ms, NULL);
	return ms->rb ? 0 : -errno;
}

void movedset_note(struct movedset *ms, __u32 tid, __u32 slot)
{
	if (tid_push(&ms->now, tid, slot))
		ms->err = -ENOMEM;
}

int movedset_begin(struct movedset *ms, volatile __u32 *read_seq)
{
	__u32 seq = *read_seq + 1;
	int err;

	/* never 0: a new entry's moved_seq, which must differ */
	*read_seq = seq ? seq : 1;
	err = ring_buffer__consume(ms->rb);
	if (err < 0 && !ms->err)
		ms->err = err;
	err = ms->err;
	ms->err = 0;
	return err;
}

void movedset_end(struct movedset *ms)
{
	struct tid_list t = ms->again;

	ms->again = ms->now;
	ms->now = t;
	ms->now.n = 0;
}

void movedset_free(struct movedset *ms)
{
	ring_buffer__free(ms->rb);
	free(ms->now.at);
	free(ms->again.at);
	memset(ms, 0, sizeof(*ms));
}
