/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * iterread.h - one run of a BPF iterator, its whole output in one buffer
 * that is kept (and grown) from one sample to the next
 */
#ifndef RTSUP_ITERREAD_H
#define RTSUP_ITERREAD_H

#include <stddef.h>

struct iter_buf {
	char *p;
	size_t cap;
	size_t len;	/* bytes of the last run */
};

/* iter_read - run the iterator of link 'link_fd' once into b; -errno */
int iter_read(struct iter_buf *b, int link_fd);
/*
 * iter_read_each - the same, given to 'take' as it comes, read by read: b
 * holds a read's bytes and what the last take left (a record cut between
 * two reads), never the whole output, as long as a record is smaller than
 * a read (32 KiB). 'take' returns the bytes it used from the front (whole
 * records), or -errno to stop. Bytes left at the end: -EPROTO. Without
 * 'take' (iter_read), b keeps it all.
 */
int iter_read_each(struct iter_buf *b, int link_fd,
		   long (*take)(void *ctx, char *p, size_t len), void *ctx);
void iter_buf_free(struct iter_buf *b);

#endif
