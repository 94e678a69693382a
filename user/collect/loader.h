/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* loader.h - open, configure, load and attach the BPF programs */
#ifndef RTSUP_LOADER_H
#define RTSUP_LOADER_H

#include <stdbool.h>
#include "options.h"
#include "model/syshooks.h"

struct rtsup_bpf;
struct rtsup_empty_bpf;
struct rtsup_tasks_bpf;

struct loader {
	struct rtsup_bpf *skel;
	struct rtsup_empty_bpf *floor;	/* --floor: the empty programs attached instead */
	struct rtsup_tasks_bpf *tasks;	/* map_attrs: the thread map's iterator, its own object */
	bool tp_btf;		/* which program set is attached */
	bool fault_stacks;	/* --stacks: the user page fault hook is attached */
	bool rt_hook;		/* --rt: the policy hook is attached (rtfollow.h) */
	bool attrs_iter;	/* the task iterator is loaded (taskattrs.h) */
	bool threads_iter;	/* the thread map's iterator is attached (threadread.h) */
	bool map_attrs;		/* ... and reads the tasks' attributes: 'tasks' (no task iterator) */
	bool sys_per;		/* per-syscall hooks, on the syscalls in hooks; else raw_syscalls */
	struct sys_hookset hooks;
	/* hooks by the prototype of their function: [0] with arguments, [1] without */
	struct sys_hookset by_proto[2];
	int cgroup_fd;
	int stats_fd;		/* holds BPF run-time statistics on, -1 = off */
};

/*
 * loader_start - check privileges and BTF, load and attach; on error print
 * one line and return -1.
 */
int loader_start(struct loader *l, const struct options *o);
void loader_stop(struct loader *l);
/*
 * loader_run_sums - total run time of our programs in ns and their runs,
 * from the kernel's BPF statistics (switched on while we run); -1 when
 * one program's could not be read.
 */
int loader_run_sums(const struct loader *l, __u64 *run_ns, __u64 *runs);
/*
 * loader_runs_missed - runs of our programs the kernel skipped because the
 * same program was already running on that CPU (a wakeup from an interrupt
 * inside its own hook): each is an event not seen. The kernel counts them
 * whether or not statistics are on; before 6.7 tracepoint programs ran
 * nested instead, and this is 0.
 */
__u64 loader_runs_missed(const struct loader *l);
/*
 * loader_stats - switch the kernel's BPF run-time statistics on or off
 * (they count while any holder keeps them on); -1 when they cannot be
 * switched on (no CAP_SYS_ADMIN).
 */
int loader_stats(struct loader *l, bool on);

#endif
