// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* health.c - rtsup-trace's own health (health.h) */
#include "judge/health.h"

void health_counters(struct health *h, const __u64 *counters)
{
	h->lost_events = counters[RTSUP_C_RB_DROPS];
	h->lost_cycle_records = counters[RTSUP_C_CYC_DROPS];
	h->untracked_threads = counters[RTSUP_C_MAP_FULL];
	h->untracked_syscall_counts = counters[RTSUP_C_SYS_FULL];
	h->can_frames_not_counted = counters[RTSUP_C_CAN_FULL];
	h->hook_runs_recovered = counters[RTSUP_C_DELIM_UNSEEN];
}

double health_fill_pct(const struct health_map *m)
{
	if (!m->capacity)
		return -1;
	return m->entries * 100.0 / m->capacity;
}

bool health_near_full(const struct health_map *m)
{
	/* in integers: 90 % of a capacity is near full whatever the rounding */
	return m->capacity && (__u64)m->entries * 100 >= (__u64)m->capacity * HEALTH_NEAR_PCT;
}

bool health_problems(const struct health *h)
{
	return h->lost_events || h->lost_cycle_records || h->untracked_threads ||
	       h->untracked_syscall_counts || h->can_frames_not_counted || h->events_not_kept ||
	       h->hook_runs_missed ||
	       h->parse_errors || h->actions_dropped || health_near_full(&h->thread_map) ||
	       health_near_full(&h->can_id_map);
}
