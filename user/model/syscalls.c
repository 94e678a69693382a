// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * syscalls.c - syscall names and the RT-safety classification.
 *
 * The classification is data: one table of names, so a configuration can
 * later add or remove entries without touching code.
 */
#include <stdio.h>
#include <string.h>
#include "model/syscalls.h"
#include "rtsup.h"
#include "syscall_table.h"

#define ARRAY_SIZE(a) (sizeof(a) / sizeof((a)[0]))

_Static_assert(SYSCALLS_MAX_DELIMS <= RTSUP_CFG_DELIMS,
	       "every --cycle-syscall name must fit a thread's settings in the kernel");

/* Syscalls that break real-time behaviour inside a cycle, by category. */
static const struct {
	const char *name;
	const char *category;
	__u32 flags;
} unsafe_table[] = {
	/* memory: may allocate, fault, or take mmap_lock */
	{ "mmap", "memory", 0 },
	{ "munmap", "memory", 0 },
	{ "mremap", "memory", 0 },
	{ "brk", "memory", 0 },
	{ "mprotect", "memory", 0 },
	{ "madvise", "memory", 0 },
	{ "mlock", "memory", 0 },
	{ "mlock2", "memory", 0 },
	{ "munlock", "memory", 0 },
	{ "mlockall", "memory", 0 },
	{ "munlockall", "memory", 0 },
	/* files and console: file system locks, I/O, unbounded latency */
	{ "open", "file", 0 },
	{ "openat", "file", 0 },
	{ "openat2", "file", 0 },
	{ "creat", "file", 0 },
	{ "close", "file", 0 },
	{ "stat", "file", 0 },
	{ "fstat", "file", 0 },
	{ "lstat", "file", 0 },
	{ "newfstatat", "file", 0 },
	{ "statx", "file", 0 },
	{ "fsync", "file", 0 },
	{ "fdatasync", "file", 0 },
	{ "sync", "file", 0 },
	{ "syncfs", "file", 0 },
	{ "write", "file", RTSUP_SC_FDCHECK },
	{ "pwrite64", "file", RTSUP_SC_FDCHECK },
	{ "writev", "file", RTSUP_SC_FDCHECK },
	{ "pwritev", "file", RTSUP_SC_FDCHECK },
	{ "pwritev2", "file", RTSUP_SC_FDCHECK },
	/* processes: copy or replace address spaces, wait for others */
	{ "fork", "process", 0 },
	{ "vfork", "process", 0 },
	{ "clone", "process", 0 },
	{ "clone3", "process", 0 },
	{ "execve", "process", 0 },
	{ "execveat", "process", 0 },
	{ "wait4", "process", 0 },
	{ "waitid", "process", 0 },
	/* sleeps other than the cycle delimiter, and giving the CPU away */
	{ "nanosleep", "sleep", 0 },
	{ "clock_nanosleep", "sleep", 0 },
	{ "pause", "sleep", 0 },
	{ "sched_yield", "yield", 0 },
};

/* Sleeps whose requested release the kernel side can read. */
static const struct {
	const char *name;
	__u32 flags;
} sleep_table[] = {
	{ "clock_nanosleep", RTSUP_SC_ABSSLEEP },
	{ "nanosleep", RTSUP_SC_RELSLEEP },
	{ "restart_syscall", RTSUP_SC_RESTART },
};

/*
 * Waits that end a cycle only on what the thread sleeps on at the cycle's
 * end: their first argument (fd, futex word, pollfd array) is the key.
 */
static const struct {
	const char *name;
	__u32 flags;
} keyed_table[] = {
	{ "read", RTSUP_SC_KEYED },
	{ "readv", RTSUP_SC_KEYED },
	{ "pread64", RTSUP_SC_KEYED },
	{ "recvfrom", RTSUP_SC_KEYED },
	{ "recvmsg", RTSUP_SC_KEYED },
	{ "recvmmsg", RTSUP_SC_KEYED },
	{ "epoll_wait", RTSUP_SC_KEYED },
	{ "epoll_pwait", RTSUP_SC_KEYED },
	{ "epoll_pwait2", RTSUP_SC_KEYED },
	{ "poll", RTSUP_SC_KEYED },
	{ "ppoll", RTSUP_SC_KEYED },
	{ "futex", RTSUP_SC_KEYED | RTSUP_SC_OPKEY },
};

int syscall_nr(const char *name)
{
	size_t i;

	for (i = 0; i < ARRAY_SIZE(syscall_table); i++)
		if (!strcmp(syscall_table[i].name, name))
			return syscall_table[i].nr;
	return -1;
}

const char *syscall_name(int nr)
{
	size_t i;

	for (i = 0; i < ARRAY_SIZE(syscall_table); i++)
		if (syscall_table[i].nr == nr)
			return syscall_table[i].name;
	return NULL;
}

const char *syscall_category(const char *name)
{
	size_t i;

	for (i = 0; i < ARRAY_SIZE(unsafe_table); i++)
		if (!strcmp(unsafe_table[i].name, name))
			return unsafe_table[i].category;
	return NULL;
}

int sysclass_build(__u32 *table, size_t n, const char *const *delims,
		   int ndelims, char *err, size_t errlen)
{
	size_t i;
	int d, nr;

	memset(table, 0, n * sizeof(*table));
	/* names missing on this architecture (open, fork...) are skipped */
	for (i = 0; i < ARRAY_SIZE(unsafe_table); i++) {
		nr = syscall_nr(unsafe_table[i].name);
		if (nr >= 0 && (size_t)nr < n)
			table[nr] |= RTSUP_SC_UNSAFE | unsafe_table[i].flags;
	}
	for (i = 0; i < ARRAY_SIZE(sleep_table); i++) {
		nr = syscall_nr(sleep_table[i].name);
		if (nr >= 0 && (size_t)nr < n)
			table[nr] |= sleep_table[i].flags;
	}
	for (i = 0; i < ARRAY_SIZE(keyed_table); i++) {
		nr = syscall_nr(keyed_table[i].name);
		if (nr >= 0 && (size_t)nr < n)
			table[nr] |= keyed_table[i].flags;
	}
	for (d = 0; d < ndelims; d++) {
		nr = syscall_nr(delims[d]);
		if (nr < 0 || (size_t)nr >= n) {
			snprintf(err, errlen, "unknown syscall '%s'", delims[d]);
			return -1;
		}
		/*
		 * the delimiter is the cycle boundary, never a fault; the class
		 * bits stay for threads whose rules pick another delimiter
		 */
		table[nr] |= RTSUP_SC_DELIM;
	}
	return 0;
}
