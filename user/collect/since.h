/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * since.h - time from a kernel timestamp to 'now'. The kernel stamps its
 * maps while they are read: a timestamp can be newer than a 'now' taken
 * a little before the read. Every "how long ago" goes through ns_since,
 * so such a timestamp is 0 ns old, never 584 years (an unsigned wrap).
 */
#ifndef RTSUP_SINCE_H
#define RTSUP_SINCE_H

#include <linux/types.h>

/* ns_since - now - ts, 0 when ts is not older than now */
static inline __u64 ns_since(__u64 now, __u64 ts)
{
	return ts < now ? now - ts : 0;
}

#endif
