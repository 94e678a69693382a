/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * liveness.h - when the collector may call a thread dead. Only from what it
 * read: an exit the kernel recorded in the entry, or the entry missing from
 * a thread map read to its end. A read that failed half-way says nothing
 * about the entries it did not reach: those threads keep their last state.
 */
#ifndef RTSUP_LIVENESS_H
#define RTSUP_LIVENESS_H

#include <stdbool.h>

/* thread_dead - dead after this read? (read complete, entry present, exit recorded) */
static inline bool thread_dead(bool read_complete, bool present, bool exited)
{
	if (present)
		return exited;
	return read_complete;
}

#endif
