/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * pidns.h - does rtsup-trace run in the initial PID namespace? Its BPF
 * programs see the kernel's tids (those of the initial namespace); inside
 * a container /proc, --pid and --tid use the container's own numbers, and
 * every tid would be wrong. So it refuses to trace there.
 */
#ifndef RTSUP_PIDNS_H
#define RTSUP_PIDNS_H

#include <stdbool.h>

/* PROC_PID_INIT_INO (include/linux/proc_ns.h): the initial PID namespace's inode */
#define PIDNS_INIT_INO 0xEFFFFFFCU

/* nspid_levels - fields of the "NSpid:" line of a /proc/<pid>/status text, 0 if none */
int nspid_levels(const char *status);
/* pidns_is_initial - true in the initial PID namespace (or when nothing says otherwise) */
bool pidns_is_initial(void);

#endif
