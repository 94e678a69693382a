// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * mapprune.c - delete the entries of a BPF hash map that are gone, in two
 * passes: read them all, then delete. Deleting while walking is quadratic:
 * a next-key call whose key is gone, or that has none because every key
 * before was deleted, starts again at bucket 0 and scans all the empty
 * buckets the deletes left. Both passes go by batches where the kernel has
 * them (5.6): a storm's ~5000 dead untracked threads an interval were
 * ~15000 syscalls one by one. The kernel side only inserts into the maps
 * pruned here: nothing read is deleted under the walk.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <bpf/bpf.h>
#include "collect/mapprune.h"

#ifndef ENOTSUPP
#define ENOTSUPP 524	/* the kernel's own "operation not supported" */
#endif

/* entries of one walk: n keys of ksz bytes and their values of vsz */
struct entries {
	char *k, *v;
	size_t n, cap, ksz, vsz;
};

/* room for want more entries */
static int entries_room(struct entries *e, size_t want)
{
	size_t cap = e->cap ? e->cap : 256;
	char *k, *v;

	while (cap < e->n + want)
		cap *= 2;
	if (cap == e->cap)
		return 0;
	k = realloc(e->k, cap * e->ksz);
	if (!k)
		return -ENOMEM;
	e->k = k;
	v = realloc(e->v, cap * e->vsz);
	if (!v)
		return -ENOMEM;
	e->v = v;
	e->cap = cap;
	return 0;
}

bool map_batch_unsupported(int err)
{
	return err == EINVAL || err == ENOTSUP || err == ENOTSUPP;
}

/* read_batched - every entry, a chunk a syscall; -ENOTSUP: no batch ops */
static int read_batched(int fd, struct entries *e)
{
	__u64 in = 0, out = 0;
	__u32 chunk = 256, n;
	bool first = true;
	int err;

	do {
		if (entries_room(e, chunk))
			return -ENOMEM;
		n = chunk;
		err = bpf_map_lookup_batch(fd, first ? NULL : &in, &out, e->k + e->n * e->ksz,
					   e->v + e->n * e->vsz, &n, NULL);
		if (err && errno == ENOSPC && !n) {
			chunk *= 2;	/* one bucket holds more than a chunk */
			continue;
		}
		if (err && errno != ENOENT)
			return first && map_batch_unsupported(errno) ? -ENOTSUP : -errno;
		e->n += n;
		in = out;
		first = false;
	} while (!err);
	return 0;
}

/* read_walk - every key by next-key calls (kernels < 5.6), values after */
static int read_walk(int fd, struct entries *e)
{
	char key[64];
	void *prev = NULL;
	size_t i;

	if (e->ksz > sizeof(key))
		return -EINVAL;
	for (;;) {
		if (entries_room(e, 1))
			return -ENOMEM;
		if (bpf_map_get_next_key(fd, prev, e->k + e->n * e->ksz))
			break;
		memcpy(key, e->k + e->n++ * e->ksz, e->ksz);
		prev = key;
	}
	if (errno != ENOENT)
		return -errno;
	for (i = 0; i < e->n; i++)
		if (bpf_map_lookup_elem(fd, e->k + i * e->ksz, e->v + i * e->vsz))
			return -errno;
	return 0;
}

/* delete_keys - the n keys at k: one syscall where the kernel has it */
static void delete_keys(int fd, const char *k, __u32 n, size_t ksz)
{
	__u32 done = n, i = 0;

	if (!n || !bpf_map_delete_batch(fd, k, &done, NULL))
		return;
	if (!map_batch_unsupported(errno))
		i = done;	/* it stopped at one already gone: the rest one by one */
	for (; i < n; i++)
		bpf_map_delete_elem(fd, k + i * ksz);
}

int map_prune(int fd, size_t ksz, size_t vsz, prune_gone gone, void *ctx)
{
	struct entries e = { .ksz = ksz, .vsz = vsz };
	__u32 ngone = 0;
	size_t i;
	int err;

	err = read_batched(fd, &e);
	if (err == -ENOTSUP) {
		e.n = 0;
		err = read_walk(fd, &e);
	}
	/* gone keys moved to the front of e.k */
	for (i = 0; !err && i < e.n; i++)
		if (gone(e.k + i * ksz, e.v + i * vsz, ctx))
			memmove(e.k + ngone++ * ksz, e.k + i * ksz, ksz);
	if (!err)
		delete_keys(fd, e.k, ngone, ksz);
	free(e.k);
	free(e.v);
	return err;
}
