/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * statsfloor.h - what the kernel's BPF statistics add to each run they
 * time (overhead.h): an empty program, run in a loop by the kernel
 * (BPF_PROG_TEST_RUN) while the statistics are on, through the same
 * bpf_prog_run() as a tracepoint's program. Its run time per run is the
 * clock read and the call: the floor of every run the window timed.
 */
#ifndef RTSUP_STATSFLOOR_H
#define RTSUP_STATSFLOOR_H

struct stats_floor {
	int fd;			/* the empty program; -1: not loaded (yet, or refused) */
	int err;		/* its load's -errno, 0 */
};

/* nothing loaded yet */
#define STATS_FLOOR_NONE ((struct stats_floor){ .fd = -1 })

/* stats_floor_init - nothing loaded yet (STATS_FLOOR_NONE) */
void stats_floor_init(struct stats_floor *f);
/*
 * stats_floor_measure - the floor in ns per run, the statistics being on;
 * the least of a few short batches (a batch an interrupt or a preemption
 * fell in reads high: too much taken off would hide our cost). -1 when the
 * kernel refuses the program or its test runs.
 */
double stats_floor_measure(struct stats_floor *f);
void stats_floor_close(struct stats_floor *f);

#endif
