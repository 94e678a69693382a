// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* iterread.c - one run of a BPF iterator into a kept buffer (iterread.h) */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <bpf/bpf.h>
#include "collect/iterread.h"

/* the kernel's read of an iterator returns at most its 32 KiB buffer at a time */
#define ITER_MIN_ROOM	(64 * 1024)

/* room_for_a_read - ITER_MIN_ROOM free at b's end at least; -ENOMEM */
static int room_for_a_read(struct iter_buf *b)
{
	size_t ncap;
	char *p;

	if (b->cap - b->len >= ITER_MIN_ROOM)
		return 0;
	ncap = b->cap ? b->cap * 2 : 2 * ITER_MIN_ROOM;
	p = realloc(b->p, ncap);
	if (!p)
		return -ENOMEM;
	b->p = p;
	b->cap = ncap;
	return 0;
}

int iter_read_each(struct iter_buf *b, int link_fd,
		   long (*take)(void *ctx, char *p, size_t len), void *ctx)
{
	int fd = bpf_iter_create(link_fd), err = 0;
	ssize_t r;
	long used;

	b->len = 0;
	if (fd < 0)
		return -errno;
	for (;;) {
		err = room_for_a_read(b);
		if (err)
			break;
		r = read(fd, b->p + b->len, b->cap - b->len);
		if (r < 0 && errno == EINTR)
			continue;
		if (r <= 0) {
			err = r < 0 ? -errno : take && b->len ? -EPROTO : 0;
			break;
		}
		b->len += r;
		if (!take)
			continue;
		used = take(ctx, b->p, b->len);
		if (used < 0) {
			err = (int)used;
			break;
		}
		/* what is left is less than a record: to the front, where records align */
		memmove(b->p, b->p + used, b->len - used);
		b->len -= used;
	}
	close(fd);
	return err;
}

int iter_read(struct iter_buf *b, int link_fd)
{
	return iter_read_each(b, link_fd, NULL, NULL);
}

void iter_buf_free(struct iter_buf *b)
{
	free(b->p);
	b->p = NULL;
	b->cap = b->len = 0;
}
