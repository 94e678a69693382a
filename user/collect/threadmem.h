/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * threadmem.h - the thread map's entries, read in place: "threads" names
 * each tid's slot of "thread_mem", which this maps into our memory, and
 * "thread_free" holds the slots not in use (threadread.h). A copy from
 * here costs a memcpy; the lookup it replaces was a syscall and the
 * kernel's two copies of 7 KiB.
 */
#ifndef RTSUP_THREADMEM_H
#define RTSUP_THREADMEM_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"

/*
 * thread_mem is mapped a chunk at a time, when a slot in it is first read:
 * all of it (--max-threads slots of 6 KiB, 24 MiB by default) would count
 * in rtsup-trace's RSS however few threads it follows
 */
#define THREADMEM_CHUNK	(1u << 20)

struct threadmem {
	char *base;		/* thread_mem's addresses, NULL until open */
	size_t len;		/* bytes of them */
	bool *mapped;		/* chunk k is mapped at base + k * THREADMEM_CHUNK */
	size_t nchunks;
	int mem_fd;		/* thread_mem */
	size_t stride;		/* bytes between two slots (the kernel's element size) */
	__u32 n;		/* slots */
	int slot_fd;		/* threads: tid -> slot */
	int free_fd;		/* thread_free */
};

/* threadmem_fill - every slot of n into the free queue at free_fd; -errno */
int threadmem_fill(int free_fd, __u32 n);
/* threadmem_open - map thread_mem (mem_fd, n slots); -errno */
int threadmem_open(struct threadmem *m, int mem_fd, int slot_fd, int free_fd, __u32 n);
void threadmem_close(struct threadmem *m);
/* threadmem_at - the entry at slot (its chunk mapped), NULL when slot is none of ours */
const struct rtsup_thread *threadmem_at(struct threadmem *m, __u32 slot);
/*
 * threadmem_prefetch - ask the CPU for the lines of the entry at slot that
 * threadmem_copy_short reads first (its fields, each metric's counts),
 * while the one before is taken: the entries are out of the cache by the
 * next interval, and each waited for its misses one after the other
 */
void threadmem_prefetch(struct threadmem *m, __u32 slot);
/*
 * threadmem_copy - tid's entry into *out, from slot when it holds tid's
 * (THREAD_NO_SLOT, or a slot given back since: the thread map says
 * where); -ENOENT when tid has none
 */
int threadmem_copy(struct threadmem *m, __u32 tid, __u32 slot, struct rtsup_thread *out);
/*
 * threadmem_copy_short - threadmem_copy of tid's fields, and of its
 * buckets only those between the lowest and highest values of each
 * metric's interval banks (metric_banks_range): ~15 cache lines, not 95.
 * The others are left as they were in *out (model_takes_short).
 */
int threadmem_copy_short(struct threadmem *m, __u32 tid, __u32 slot,
			 struct rtsup_thread *out);
/*
 * threadmem_gen - the generation and first_seen of tid's entry, read in
 * place (its first cache lines, no copy): 0, -ENOENT when tid has none
 */
int threadmem_gen(struct threadmem *m, __u32 tid, __u32 slot, __u32 *gen, __u64 *first_seen);
/*
 * threadmem_add - an entry for tid, t written to a free slot before the
 * thread map names it: 0, -EEXIST when tid has one, -E2BIG when no slot
 * is free, or -errno
 */
int threadmem_add(struct threadmem *m, __u32 tid, const struct rtsup_thread *t);
/* threadmem_remove - tid's entry gone, its slot free again (its tid zeroed first) */
void threadmem_remove(struct threadmem *m, __u32 tid);

#endif
