// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* procfile.c - a /proc or /sys file read every sample through one open descriptor */
#include <errno.h>
#include <fcntl.h>
#include <unistd.h>
#include "procfile.h"

void procfile_close(struct procfile *f)
{
	if (f->open)
		close(f->fd);
	f->open = false;
}

/* read_kept - one read from the start of the open file */
static ssize_t read_kept(const struct procfile *f, char *buf, size_t len)
{
	ssize_t n = pread(f->fd, buf, len - 1, 0);

	return n < 0 ? -errno : n;
}

ssize_t procfile_read(struct procfile *f, const char *path, char *buf, size_t len)
{
	ssize_t n = -EBADF;

	if (!len)
		return -EINVAL;
	buf[0] = '\0';
	if (f->open)
		n = read_kept(f, buf, len);
	if (n < 0) {
		procfile_close(f);
		f->fd = open(path, O_RDONLY | O_CLOEXEC);
		if (f->fd < 0)
			return -errno;
		f->open = true;
		n = read_kept(f, buf, len);
		if (n < 0) {
			procfile_close(f);
			return n;
		}
	}
	buf[n] = '\0';
	return n;
}
