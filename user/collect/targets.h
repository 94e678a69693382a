/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* targets.h - which threads to supervise: what the user asked for */
#ifndef RTSUP_TARGETS_H
#define RTSUP_TARGETS_H

#include <stdbool.h>
#include <stdio.h>
#include <sys/types.h>
#include "rtsup.h"

#define TARGETS_MAX 64

struct targets {
	pid_t pids[TARGETS_MAX];	/* -p: processes, all their threads */
	int npids;
	pid_t tids[TARGETS_MAX];	/* -t: single threads */
	int ntids;
	char comms[RTSUP_MAX_COMMS][RTSUP_COMM_LEN];	/* -c */
	int ncomms;
	bool rt;			/* --rt */
	const char *cgroup;		/* --cgroup, a cgroup v2 directory */
};

/* how a thread matched: its whole process, or only as an RT thread (--rt) */
#define TARGET_PROCESS	1
#define TARGET_RT	2

/* Called for every thread found that matches; how: TARGET_* or 0. */
typedef int (*target_cb)(void *ctx, pid_t tgid, pid_t tid, const char *comm,
			 unsigned int how);

/* targets_any - did the user name any target? */
bool targets_any(const struct targets *t);
/*
 * targets_scan - walk /proc (and the cgroup) once and call cb for each
 * matching thread; returns 0 or a negative errno from the callback.
 */
int targets_scan(const struct targets *t, target_cb cb, void *ctx);
/* thread_comm - read /proc/<tgid>/task/<tid>/comm, 0 on success */
int thread_comm(pid_t tgid, pid_t tid, char *buf, size_t len);
/* PF_KTHREAD of include/linux/sched.h: the task is a kernel thread */
#define TARGETS_PF_KTHREAD 0x00200000U
/* stat_flags - the flags field of a /proc/<pid>/stat line; 0 if unreadable */
unsigned long stat_flags(const char *line);
/* thread_is_kernel - is this a kernel thread (PF_KTHREAD)? false if unknown */
bool thread_is_kernel(pid_t tgid, pid_t tid);
/*
 * The /proc and cgroup text, parsed from an open file (the fuzz target
 * tests/fuzz/fuzz_proc.c feeds them anything):
 * comm_read - a comm file's first line without its newline, 0 or -EIO
 */
int comm_read(FILE *f, char *buf, size_t len);
/* status_tgid - the Tgid: line of /proc/<tid>/status, -1 when none */
pid_t status_tgid(FILE *f);
/* cgroup_threads - fn for each thread id of cgroup.threads until it returns nonzero */
int cgroup_threads(FILE *f, int (*fn)(void *, pid_t), void *arg);
/* targets_parse_errors - text the three above and stat_flags skipped, since the start */
__u64 targets_parse_errors(void);
/*
 * comm_sanitize - a thread name is any bytes: keep printable ASCII only, so
 * tables stay aligned and JSON stays valid UTF-8
 */
void comm_sanitize(char *s, size_t len);
/* process_exists - is there a process with this pid? */
bool process_exists(pid_t pid);
/* comm_matches - is this name one of the --comm targets? */
bool comm_matches(const struct targets *t, const char *comm);
/* cpu_list - format a thread's allowed CPUs as "0-3,6" */
void cpu_list(pid_t tid, char *buf, size_t len);
/* cpu_list_mask - the same for a CPU bit mask of nbits bits */
void cpu_list_mask(const unsigned long *bits, int nbits, char *buf, size_t len);
/*
 * cpu_list_parse - the reverse, for the kernel's lists ("0-3,6\n", as in
 * /sys/devices/system/cpu/online): bits of nbits set, CPUs past them
 * ignored; -EINVAL for text that is not such a list
 */
int cpu_list_parse(const char *text, unsigned long *bits, int nbits);

#endif
