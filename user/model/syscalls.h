/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/* syscalls.h - syscall names and the RT-safety class of each syscall */
#ifndef RTSUP_SYSCALLS_H
#define RTSUP_SYSCALLS_H

#include <stddef.h>
#include <linux/types.h>

#define SYSCALLS_MAX_DELIMS 8

/* syscall_nr - number of a syscall name on this architecture, -1 if none */
int syscall_nr(const char *name);
/* syscall_name - name of a syscall number, NULL if unknown */
const char *syscall_name(int nr);
/* syscall_category - why a syscall is RT-unsafe ("memory", ...) or NULL */
const char *syscall_category(const char *name);

/*
 * sysclass_build - fill the per-number class table (RTSUP_SC_* bits) from
 * the unsafe table and the delimiter names; on error write why into err.
 */
int sysclass_build(__u32 *table, size_t n, const char *const *delims,
		   int ndelims, char *err, size_t errlen);

#endif
