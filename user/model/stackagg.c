// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* stackagg.c - user stacks at RT-unsafe events, counted per thread, reason, stack */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "model/stackagg.h"

__u64 stack_hash(const struct stack_frame *f, int n)
{
	__u64 h = 1469598103934665603ULL;	/* FNV-1a */
	const char *s;
	int i, k;

	for (i = 0; i < n; i++) {
		/* a module and an offset, or the bare address outside any */
		for (s = f[i].module; *s; s++)
			h = (h ^ (unsigned char)*s) * 1099511628211ULL;
		for (k = 0; k < 8; k++)
			h = (h ^ ((f[i].module[0] ? f[i].offset : f[i].pc) >> (k * 8) & 0xff)) *
			    1099511628211ULL;
	}
	return h;
}

/* find - the entry of (tid, reason, nr, hash), or NULL */
static struct stack_entry *find(struct stackagg *a, __u32 tid, __u32 reason, __u32 nr,
				__u64 hash)
{
	int i;

	/* distinct stacks are few (one per call site): a scan is enough */
	for (i = 0; i < a->n; i++) {
		struct stack_entry *e = &a->e[i];

		if (e->tid == tid && e->reason == reason && e->nr == nr && e->hash == hash)
			return e;
	}
	return NULL;
}

int stackagg_add(struct stackagg *a, __u32 tid, __u32 tgid, const char *comm, __u32 reason,
		 __u32 nr, const struct stack_frame *f, int n)
{
	return stackagg_add_kind(a, tid, tgid, comm, reason, nr, 0, f, n);
}

int stackagg_add_kind(struct stackagg *a, __u32 tid, __u32 tgid, const char *comm,
		      __u32 reason, __u32 nr, __u32 kind, const struct stack_frame *f, int n)
{
	__u32 bit = kind && kind < 32 ? 1u << kind : 0;
	__u64 hash;
	struct stack_entry *e;

	if (n > STACK_MAX_FRAMES)
		n = STACK_MAX_FRAMES;
	if (n < 0)
		n = 0;
	hash = stack_hash(f, n);
	e = find(a, tid, reason, nr, hash);
	if (e) {
		e->total++;
		e->kinds |= bit;
		return 0;
	}
	if (a->n >= STACKAGG_MAX) {
		a->not_kept++;
		return -1;
	}
	if (a->n == a->cap) {
		int cap = a->cap ? a->cap * 2 : 16;
		struct stack_entry *ne = realloc(a->e, cap * sizeof(*ne));

		if (!ne) {
			a->not_kept++;
			return -1;
		}
		a->e = ne;
		a->cap = cap;
	}
	e = &a->e[a->n];
	memset(e, 0, sizeof(*e));
	e->frames = n ? malloc(n * sizeof(*f)) : NULL;
	if (n && !e->frames) {
		a->not_kept++;
		return -1;
	}
	if (n)
		memcpy(e->frames, f, n * sizeof(*f));
	e->nframes = n;
	e->tid = tid;
	e->tgid = tgid;
	e->reason = reason;
	e->nr = nr;
	e->hash = hash;
	e->total = 1;
	e->kinds = bit;
	snprintf(e->comm, sizeof(e->comm), "%s", comm ? comm : "");
	a->n++;
	return 0;
}

void stackagg_interval_end(struct stackagg *a)
{
	int i;

	for (i = 0; i < a->n; i++)
		a->e[i].prev = a->e[i].total;
}

void stackagg_free(struct stackagg *a)
{
	int i;

	for (i = 0; i < a->n; i++)
		free(a->e[i].frames);
	free(a->e);
	memset(a, 0, sizeof(*a));
}

/* base - the last part of a path */
static const char *base(const char *path)
{
	const char *s = strrchr(path, '/');

	return s ? s + 1 : path;
}

void frame_format(const struct stack_frame *f, char *buf, size_t len)
{
	const char *note = f->flags & FRAME_REPLACED ? " [replaced on disk]" :
			   f->flags & FRAME_DELETED ? " [deleted]" : "";

	/* a demangled C++ name has its parameters already */
	const char *call = strchr(f->func, '(') ? "" : "()";

	if (f->func[0] && f->line)
		snprintf(buf, len, "%s%s %s:%d%s", f->func, call, base(f->file), f->line, note);
	else if (f->func[0])
		snprintf(buf, len, "%s%s (%s+0x%llx)%s", f->func, call, base(f->module),
			 (unsigned long long)f->offset, note);
	else if (f->module[0] && f->build_id[0])
		snprintf(buf, len, "%s+0x%llx (build-id %.12s)%s", base(f->module),
			 (unsigned long long)f->offset, f->build_id, note);
	else if (f->module[0])
		snprintf(buf, len, "%s+0x%llx%s", base(f->module), (unsigned long long)f->offset,
			 note);
	else if (f->pc)
		snprintf(buf, len, "[unknown] 0x%llx", (unsigned long long)f->pc);
	else
		snprintf(buf, len, "[unknown]");
}

void stack_format(const struct stack_frame *f, int n, const char *sep, char *buf, size_t len)
{
	char one[512];
	size_t used = 0;
	int i, w;

	if (len)
		buf[0] = '\0';
	if (!n) {
		snprintf(buf, len, "[no user stack]");
		return;
	}
	for (i = 0; i < n && used < len; i++) {
		frame_format(&f[i], one, sizeof(one));
		w = snprintf(buf + used, len - used, "%s%s", i ? sep : "", one);
		if (w < 0)
			break;
		used += w;
	}
}
