// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* clockwatch.c - a timerfd the kernel cancels when the wall clock steps */
#include <errno.h>
#include <stdint.h>
#include <unistd.h>
#include <sys/timerfd.h>
#include "collect/clockwatch.h"

/* arm - a deadline that never comes: the timer only ever ends cancelled */
static int arm(int fd)
{
	struct itimerspec its = { .it_value = { .tv_sec = (time_t)INT32_MAX * 64 } };

	return timerfd_settime(fd, TFD_TIMER_ABSTIME | TFD_TIMER_CANCEL_ON_SET, &its, NULL) ?
	       -errno : 0;
}

int clockwatch_open(void)
{
	int fd = timerfd_create(CLOCK_REALTIME, TFD_NONBLOCK | TFD_CLOEXEC), err;

	if (fd < 0)
		return -errno;
	err = arm(fd);
	if (err) {
		close(fd);
		return err;
	}
	return fd;
}

int clockwatch_stepped(int fd)
{
	uint64_t n;

	if (read(fd, &n, sizeof(n)) >= 0)
		return 0;	/* expired: not in 2^37 s */
	if (errno == EAGAIN)
		return 0;
	if (errno != ECANCELED)
		return -errno;
	/* cancelled: armed again, for the next step */
	return arm(fd) ?: 1;
}
