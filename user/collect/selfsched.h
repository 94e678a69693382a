/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * selfsched.h - the main loop's own time: the CPU time it ran (its thread's
 * CPU clock) and the time it was runnable but waited for a CPU (the kernel's
 * schedstat of the thread). A late interval is one or the other (or blocking
 * I/O): the second names the machine, not the supervisor, as the cause.
 */
#ifndef RTSUP_SELFSCHED_H
#define RTSUP_SELFSCHED_H

#include <stdbool.h>
#include <linux/types.h>

struct self_sched {
	__u64 cpu_ns;		/* ran on a CPU, since the thread began */
	__u64 wait_ns;		/* runnable, waiting on a run queue, since the thread began */
};

/* The span of one report: negative when the kernel does not keep schedstat. */
struct self_span {
	double cpu_s;
	double wait_s;
};

#define SELF_SPAN_UNKNOWN ((struct self_span){ -1.0, -1.0 })

/* self_sched_parse - "cpu_ns wait_ns slices\n" (/proc/<tid>/schedstat); 0 or -EINVAL */
int self_sched_parse(const char *text, struct self_sched *out);
/*
 * self_sched_read - the calling thread's; 0, or -errno (no CONFIG_SCHED_INFO:
 * -ENOENT). The CPU time is the thread's CPU clock: schedstat's runs a tick
 * behind for the thread that reads it.
 */
int self_sched_read(struct self_sched *out);
/* self_span_since - from 'then' to 'now', both read (ok) or not */
struct self_span self_span_since(const struct self_sched *then, const struct self_sched *now,
				 bool ok);

#endif
