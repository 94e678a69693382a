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
void iter_buf_free(struct iter_buf *b);

#endif
