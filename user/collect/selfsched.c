// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* selfsched.c - the main loop's own CPU and run-queue time (selfsched.h) */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <time.h>
#include "procfile.h"
#include "selfsched.h"

int self_sched_parse(const char *text, struct self_sched *out)
{
	uint64_t cpu, wait;

	if (sscanf(text, "%" SCNu64 " %" SCNu64, &cpu, &wait) != 2)
		return -EINVAL;
	out->cpu_ns = cpu;
	out->wait_ns = wait;
	return 0;
}

/*
 * the main loop's thread's file: only that thread reads it (an fd of
 * /proc/thread-self is the opener's thread's)
 */
static struct procfile schedstat;

int self_sched_read(struct self_sched *out)
{
	char buf[128];
	ssize_t n = procfile_read(&schedstat, "/proc/thread-self/schedstat", buf, sizeof(buf));
	int err;

	if (n < 0)
		return (int)n;
	err = self_sched_parse(buf, out);
	if (!err) {
		struct timespec ts;

		if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts))
			return -errno;
		out->cpu_ns = (__u64)ts.tv_sec * 1000000000 + ts.tv_nsec;
	}
	return err;
}

struct self_span self_span_since(const struct self_sched *then, const struct self_sched *now,
				 bool ok)
{
	struct self_span s = SELF_SPAN_UNKNOWN;

	/* both only grow; a smaller 'now' is another thread's: unknown, not negative */
	if (!ok || now->cpu_ns < then->cpu_ns || now->wait_ns < then->wait_ns)
		return s;
	s.cpu_s = (now->cpu_ns - then->cpu_ns) / 1e9;
	s.wait_s = (now->wait_ns - then->wait_ns) / 1e9;
	return s;
}
