/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * overhead.h - the overhead check's measure: our programs' own run time in
 * a window of the kernel's BPF statistics, in % of one CPU.
 *
 * While the statistics are on, the kernel reads the clock before and after
 * every program run, and a run's time holds one clock read. An empty
 * program's run measures that floor (statsfloor.h): 52 ns on the
 * development VM, where our sys_enter program itself takes about 9. Left
 * in, a machine busy with syscalls made the check read several times what
 * our programs cost it (a getppid flood: 23-26 % "of a CPU" with empty
 * programs and ours alike, 4 % of it ours). The floor is taken off each
 * run; without it the raw time stands.
 */
#ifndef RTSUP_OVERHEAD_H
#define RTSUP_OVERHEAD_H

#include <linux/types.h>

/* One window of the statistics: what the overhead check measured. */
struct stats_window {
	__u64 wall_ns;		/* the window's length; 0: none yet */
	__u64 runs;		/* our programs' runs in it */
	__u64 run_ns;		/* their run time, as the statistics read it */
	double floor_ns;	/* an empty program's run time per run; <0: unknown */
};

/* stats_own_ns - the window's run time less the statistics' floor, at least 0 */
static inline double stats_own_ns(const struct stats_window *w)
{
	double own = (double)w->run_ns;

	if (w->floor_ns > 0)
		own -= w->floor_ns * (double)w->runs;
	return own > 0 ? own : 0;
}

/* stats_overhead_pct - our programs' own run time in % of one CPU; -1 with no window */
static inline double stats_overhead_pct(const struct stats_window *w)
{
	return w->wall_ns ? stats_own_ns(w) / (double)w->wall_ns * 100 : -1.0;
}

#endif
