/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * taskattrs.h - every target's scheduling attributes and cgroup in one read
 * per sample, from the kernel's task iterator (attrs_task in rtsup.bpf.c):
 * what the collector otherwise asks with three syscalls and a /proc read
 * per thread per interval. Absent (an old kernel, --raw-tp, a thread born
 * after the read): the collector asks the kernel as before.
 */
#ifndef RTSUP_TASKATTRS_H
#define RTSUP_TASKATTRS_H

#include <stdbool.h>
#include <stddef.h>
#include "rtsup.h"
#include "collect/iterread.h"
#include "collect/procfile.h"

struct task_attrs {
	struct rtsup_task_attrs *a;	/* sorted by tid */
	size_t n, cap;
	size_t torn;			/* bytes of a record cut short, dropped (never seen) */
	struct iter_buf out;		/* the iterator's output, kept between reads */
	/*
	 * the CPUs online at the read: the kernel's mask may hold any bits
	 * past them, and sched_getaffinity shows a mask and'ed with them
	 */
	unsigned long online[RTSUP_ATTR_CPU_WORDS];
	bool online_ok;
	bool online_moved;		/* not the mask of the read before */
	struct procfile online_file;	/* /sys/devices/system/cpu/online, kept open */
	/* the last mask task_attrs_cpus wrote out: a process's threads mostly share one */
	unsigned long last_bits[RTSUP_ATTR_CPU_WORDS];
	char last_list[512];
	bool last_ok;
};

/* task_attrs_parse - records as the iterator wrote them, sorted by tid; -ENOMEM */
int task_attrs_parse(struct task_attrs *ta, const void *buf, size_t len);
/* task_attrs_read - run the iterator of link 'link_fd' once; -errno */
int task_attrs_read(struct task_attrs *ta, int link_fd);
/* task_attrs_online - the CPUs online now (the reads of task_attrs_cpus) */
void task_attrs_online(struct task_attrs *ta);
/* task_attrs_of - tid's record of the last read, NULL if none */
const struct rtsup_task_attrs *task_attrs_of(const struct task_attrs *ta, __u32 tid);
/* task_attrs_cpus - a record's allowed CPUs as cpu_list writes them (the last list kept:
 * threads mostly share one); false if unknown */
bool task_attrs_cpus(struct task_attrs *ta, const struct rtsup_task_attrs *a,
		     char *buf, size_t len);
void task_attrs_free(struct task_attrs *ta);

#endif
