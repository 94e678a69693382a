// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* threadmem.c - the thread map's entries, read in place (threadmem.h) */
#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/mman.h>
#include <bpf/bpf.h>
#include "threadread.h"
#include "collect/threadmem.h"

int threadmem_fill(int free_fd, __u32 n)
{
	__u32 slot;

	for (slot = 0; slot < n; slot++)
		if (bpf_map_update_elem(free_fd, NULL, &slot, BPF_ANY))
			return -errno;
	return 0;
}

/* map_len - what the kernel maps of an array of n elements of size bytes */
static size_t map_len(size_t stride, __u32 n)
{
	size_t page = (size_t)sysconf(_SC_PAGESIZE), len = stride * n;

	return (len + page - 1) / page * page;
}

int threadmem_open(struct threadmem *m, int mem_fd, int slot_fd, int free_fd, __u32 n)
{
	/* the kernel's element: the value rounded up to 8 bytes */
	size_t stride = (sizeof(struct rtsup_thread) + 7) & ~(size_t)7;
	void *p;

	memset(m, 0, sizeof(*m));
	m->mem_fd = mem_fd;
	m->slot_fd = slot_fd;
	m->free_fd = free_fd;
	m->len = map_len(stride, n);
	m->nchunks = (m->len + THREADMEM_CHUNK - 1) / THREADMEM_CHUNK;
	m->mapped = calloc(m->nchunks, sizeof(*m->mapped));
	if (!m->mapped)
		return -ENOMEM;
	/* addresses for all of it, no memory: chunks are mapped over them when used */
	p = mmap(NULL, m->len, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
	if (p == MAP_FAILED)
		return -errno;
	m->base = p;
	m->stride = stride;
	m->n = n;
	return 0;
}

void threadmem_close(struct threadmem *m)
{
	if (m->base)
		munmap(m->base, m->len);
	free(m->mapped);
	m->base = NULL;
	m->mapped = NULL;
}

/* chunk_map - chunk k of thread_mem mapped at its place; false if the kernel refused */
static bool chunk_map(struct threadmem *m, size_t k)
{
	size_t off = k * THREADMEM_CHUNK, len = m->len - off < THREADMEM_CHUNK ?
					      m->len - off : THREADMEM_CHUNK;

	if (m->mapped[k])
		return true;
	if (mmap(m->base + off, len, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_FIXED, m->mem_fd,
		 (off_t)off) == MAP_FAILED)
		return false;
	m->mapped[k] = true;
	return true;
}

const struct rtsup_thread *threadmem_at(struct threadmem *m, __u32 slot)
{
	size_t first, last;

	if (!m->base || !thread_slot_ok(slot, m->n))
		return NULL;
	first = (size_t)slot * m->stride;
	last = first + sizeof(struct rtsup_thread) - 1;
	if (!chunk_map(m, first / THREADMEM_CHUNK) || !chunk_map(m, last / THREADMEM_CHUNK))
		return NULL;
	return (const void *)(m->base + first);
}

/* slot_of - the slot the thread map names for tid, THREAD_NO_SLOT if none */
static __u32 slot_of(const struct threadmem *m, __u32 tid)
{
	__u32 slot;

	return bpf_map_lookup_elem(m->slot_fd, &tid, &slot) ? THREAD_NO_SLOT : slot;
}

void threadmem_prefetch(struct threadmem *m, __u32 slot)
{
	const char *p = (const char *)threadmem_at(m, slot);
	size_t o;
	int i;

	if (!p)
		return;
	for (o = 0; o < offsetof(struct rtsup_thread, m); o += 64)
		__builtin_prefetch(p + o);
	for (i = 0; i < RTSUP_M_NR; i++) {
		const char *s = p + offsetof(struct rtsup_thread, m) + i * sizeof(struct rtsup_metric_stats);

		__builtin_prefetch(s);
		__builtin_prefetch(s + offsetof(struct rtsup_metric_stats, hist) - 1);
	}
}

/* entry_of - tid's entry, at slot when it holds tid's, else where the thread map says */
static const struct rtsup_thread *entry_of(struct threadmem *m, __u32 tid, __u32 slot)
{
	const struct rtsup_thread *t = threadmem_at(m, slot);

	/* a slot given back has tid 0; one taken again, another tid */
	if (t && __atomic_load_n(&t->tid, __ATOMIC_RELAXED) == tid)
		return t;
	return threadmem_at(m, slot_of(m, tid));
}

int threadmem_copy(struct threadmem *m, __u32 tid, __u32 slot, struct rtsup_thread *out)
{
	const struct rtsup_thread *t = entry_of(m, tid, slot);

	if (!t)
		return -ENOENT;
	memcpy(out, t, sizeof(*out));
	/* a slot given back and taken again between the look-up and the copy */
	return out->tid == tid ? 0 : -ENOENT;
}

int threadmem_copy_short(struct threadmem *m, __u32 tid, __u32 slot,
			 struct rtsup_thread *out)
{
	const struct rtsup_thread *t = entry_of(m, tid, slot);

	if (!t)
		return -ENOENT;
	thread_copy_short(out, t);
	return out->tid == tid ? 0 : -ENOENT;
}

int threadmem_gen(struct threadmem *m, __u32 tid, __u32 slot, __u32 *gen, __u64 *first_seen)
{
	const struct rtsup_thread *t = entry_of(m, tid, slot);

	if (!t)
		return -ENOENT;
	*gen = __atomic_load_n(&t->gen, __ATOMIC_RELAXED);
	*first_seen = __atomic_load_n(&t->first_seen, __ATOMIC_RELAXED);
	/* a slot given back and taken again between the look-up and the reads */
	return __atomic_load_n(&t->tid, __ATOMIC_RELAXED) == tid ? 0 : -ENOENT;
}

int threadmem_add(struct threadmem *m, __u32 tid, const struct rtsup_thread *t)
{
	struct rtsup_thread *at;
	__u32 slot;
	int err;

	/*
	 * a hook may have added it since attach (--rt: at its first switch-in),
	 * and taken the last slot: that is no thread the map could not hold
	 */
	if (slot_of(m, tid) != THREAD_NO_SLOT)
		return -EEXIST;
	if (bpf_map_lookup_and_delete_elem(m->free_fd, NULL, &slot)) {
		if (errno != ENOENT)
			return -errno;
		return slot_of(m, tid) != THREAD_NO_SLOT ? -EEXIST : -E2BIG;
	}
	at = (struct rtsup_thread *)threadmem_at(m, slot);
	if (!at) {
		err = -ENOMEM;	/* its chunk could not be mapped */
	} else {
		memcpy(at, t, sizeof(*t));
		/* the syscall orders the copy before the name: a hook finds it whole */
		err = bpf_map_update_elem(m->slot_fd, &tid, &slot, BPF_NOEXIST) ? -errno : 0;
		if (err)
			memset(at, 0, sizeof(*at));
	}
	if (err)
		bpf_map_update_elem(m->free_fd, NULL, &slot, BPF_ANY);
	return err;
}

void threadmem_remove(struct threadmem *m, __u32 tid)
{
	struct rtsup_thread *t;
	__u32 slot;

	/* only we delete: the slot looked up is the one deleted */
	if (bpf_map_lookup_elem(m->slot_fd, &tid, &slot) || bpf_map_delete_elem(m->slot_fd, &tid))
		return;
	t = (struct rtsup_thread *)threadmem_at(m, slot);
	if (t)
		__atomic_store_n(&t->tid, 0, __ATOMIC_RELAXED);
	bpf_map_update_elem(m->free_fd, NULL, &slot, BPF_ANY);
}
