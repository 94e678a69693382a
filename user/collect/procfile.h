/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * procfile.h - a /proc or /sys file read every sample through one open
 * descriptor: an open and a close of its path cost more than the read (a
 * path walk each), and the loop reads several such files an interval.
 */
#ifndef RTSUP_PROCFILE_H
#define RTSUP_PROCFILE_H

#include <stdbool.h>
#include <sys/types.h>

/* zero-initialised: closed */
struct procfile {
	int fd;
	bool open;
};

/*
 * procfile_read - the file's text as it is now, NUL-terminated, at most
 * len - 1 bytes: read from its start through the kept descriptor, which is
 * opened from path (again) when there is none or its read fails (a process
 * gone: a pid reused later is its new process's file). Bytes or -errno.
 */
ssize_t procfile_read(struct procfile *f, const char *path, char *buf, size_t len);
/* procfile_close - the descriptor closed, if open */
void procfile_close(struct procfile *f);

#endif
