// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* taskattrs.c - the task iterator's records of the targets (taskattrs.h) */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "collect/iterread.h"
#include "taskattrs.h"
#include "targets.h"

void task_attrs_online(struct task_attrs *ta)
{
	unsigned long before[RTSUP_ATTR_CPU_WORDS];
	bool ok = ta->online_ok;
	char text[4096];
	ssize_t n = procfile_read(&ta->online_file, "/sys/devices/system/cpu/online", text,
				  sizeof(text));

	memcpy(before, ta->online, sizeof(before));
	ta->online_ok = false;
	if (n > 0) {
		ta->online_ok = !cpu_list_parse(text, ta->online, RTSUP_ATTR_CPU_WORDS * 64);
	}
	ta->online_moved = ta->online_ok != ok || memcmp(before, ta->online, sizeof(before));
}

static int by_tid(const void *a, const void *b)
{
	__u32 x = ((const struct rtsup_task_attrs *)a)->tid;
	__u32 y = ((const struct rtsup_task_attrs *)b)->tid;

	return x < y ? -1 : x > y;
}

int task_attrs_parse(struct task_attrs *ta, const void *buf, size_t len)
{
	size_t n = len / sizeof(struct rtsup_task_attrs);

	ta->n = 0;
	ta->torn = len % sizeof(struct rtsup_task_attrs);
	if (n > ta->cap) {
		void *p = realloc(ta->a, n * sizeof(*ta->a));

		if (!p)
			return -ENOMEM;
		ta->a = p;
		ta->cap = n;
	}
	if (n)
		memcpy(ta->a, buf, n * sizeof(*ta->a));
	ta->n = n;
	/* the iterator walks tids in order; sorted here whatever the kernel did */
	qsort(ta->a, n, sizeof(*ta->a), by_tid);
	return 0;
}

int task_attrs_read(struct task_attrs *ta, int link_fd)
{
	int err = iter_read(&ta->out, link_fd);

	ta->n = 0;
	task_attrs_online(ta);
	return err ?: task_attrs_parse(ta, ta->out.p, ta->out.len);
}

const struct rtsup_task_attrs *task_attrs_of(const struct task_attrs *ta, __u32 tid)
{
	struct rtsup_task_attrs key = { .tid = tid };

	return ta->n ? bsearch(&key, ta->a, ta->n, sizeof(*ta->a), by_tid) : NULL;
}

bool task_attrs_cpus(struct task_attrs *ta, const struct rtsup_task_attrs *a,
		     char *buf, size_t len)
{
	unsigned long bits[RTSUP_ATTR_CPU_WORDS] = { 0 };
	size_t n;
	__u32 i;

	if (!ta->online_ok)
		return false;
	for (i = 0; i < a->cpu_words && i < RTSUP_ATTR_CPU_WORDS; i++)
		bits[i] = a->cpus[i] & ta->online[i];
	if (!ta->last_ok || memcmp(bits, ta->last_bits, sizeof(bits))) {
		cpu_list_mask(bits, RTSUP_ATTR_CPU_WORDS * 64, ta->last_list,
			      sizeof(ta->last_list));
		memcpy(ta->last_bits, bits, sizeof(bits));
		ta->last_ok = true;
	}
	n = strlen(ta->last_list);
	if (n >= len || n + 1 >= sizeof(ta->last_list)) {	/* cut: as cpu_list_mask cuts */
		cpu_list_mask(bits, RTSUP_ATTR_CPU_WORDS * 64, buf, len);
		return true;
	}
	strcpy(buf, ta->last_list);
	return true;
}

void task_attrs_free(struct task_attrs *ta)
{
	free(ta->a);
	iter_buf_free(&ta->out);
	procfile_close(&ta->online_file);
	memset(ta, 0, sizeof(*ta));
}
