/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * health.h - rtsup-trace's own health, in the summary and every JSON report:
 * what it lost, what it could not track, how full its kernel maps are, what
 * text it could not parse, what actions it did not run. Everything here is
 * a count since the start (never goes back) or a fill of now.
 */
#ifndef RTSUP_HEALTH_H
#define RTSUP_HEALTH_H

#include <stdbool.h>
#include <linux/types.h>
#include "rtsup.h"

/* A map is near capacity from this fill on (% of its entries). */
#define HEALTH_NEAR_PCT	90

/* One kernel map's fill; capacity 0 when unknown (a replayed trace). */
struct health_map {
	__u32 entries;
	__u32 capacity;
};

struct health {
	__u64 lost_events;		/* rare events the ring buffer had no room for */
	__u64 lost_cycle_records;	/* --record's cycles the recording buffer had no room for */
	__u64 untracked_threads;	/* targets the full thread map could not hold */
	__u64 untracked_syscall_counts;	/* unsafe syscall counts the map could not hold */
	__u64 can_frames_not_counted;	/* CAN frames whose identifier did not fit the id map */
	__u64 events_not_kept;		/* rare events the interval's list had no memory for */
	__u64 parse_errors;		/* /proc and cgroup text that did not parse, skipped */
	__u64 actions_dropped;		/* actions not run: rate limit or too many running */
	__u64 hook_runs_missed;		/* runs of our programs the kernel skipped (recursion) */
	__u64 hook_runs_recovered;	/* of them, delimiter returns found otherwise */
	struct health_map thread_map;
	__u32 thread_map_copied;	/* of its entries, copied out whole at the last read */
	__u32 thread_map_short;		/* ... short: the buckets that moved (threadmem.h) */
	__u32 thread_map_short_refused;	/* short copies the model refused: copied whole */
	__u32 thread_map_visited;	/* ... looked at by the last read */
	bool thread_map_whole;		/* ... which walked the whole map (threadread.h) */
	bool thread_map_batch;		/* ... in batches, not through the iterator */
	__u32 thread_map_tasks;		/* tasks the iterator read with it */
	bool task_walk;			/* the last sample walked every task (thread_walk_tasks) */
	__u32 tasks_asked;		/* ... and asked this many threads' of the kernel */
	struct health_map can_id_map;	/* capacity 0 without --can */
};

/* health_counters - the kernel side's counters (RTSUP_C_NR of them) */
void health_counters(struct health *h, const __u64 *counters);
/* health_fill_pct - how full a map is, in %; -1 when its capacity is unknown */
double health_fill_pct(const struct health_map *m);
/* health_near_full - a map at HEALTH_NEAR_PCT or more of its capacity */
bool health_near_full(const struct health_map *m);
/* health_problems - something was lost, skipped or not tracked, or a map is near full */
bool health_problems(const struct health *h);

#endif
