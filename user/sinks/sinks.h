/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * sinks.h - the file sinks of a live run: the recorded trace (--record) and
 * the Perfetto trace (--perfetto). They take every cycle and rare event as
 * the collector reads them, and each interval's thread states.
 */
#ifndef RTSUP_SINKS_H
#define RTSUP_SINKS_H

#include "judge/checks.h"
#include "collect/collector.h"
#include "options.h"
#include "sinks/perfetto.h"
#include "sinks/record.h"
#include "judge/supervise.h"

struct sinks {
	struct rec_writer *rec;
	struct perfetto *pf;
	const struct options *o;
	const struct model *model;
	__u32 *named;		/* tids whose Perfetto track has a name, sorted */
	int nnamed;
	int cap;
	bool failed;		/* a write failed: recording stopped, the run ends with 1 */
	/* --stacks --record: the mapping set written last, per process */
	struct { __u32 tgid, gen; } *maps_written;
	int nmaps_written;
	char err[256];
};

/* sinks_open - create the files and hook into the collector; -1 on error */
int sinks_open(struct sinks *sk, const struct options *o, const struct supervisor *s,
	       struct collector *c);
/*
 * sinks_interval - thread states and the interval mark; a write error stops
 * the recording (one line), never the supervision: 0
 */
int sinks_interval(struct sinks *sk, const struct collector *c, const struct self_in *self,
		   __u64 now);
/* sinks_close - the final states, the end mark; close the files; -1 if any write failed */
int sinks_close(struct sinks *sk, const struct collector *c, const struct self_in *self,
		__u64 now);

/* rec_thread_from - a thread's record from its model */
void rec_thread_from(struct rec_thread *r, const struct thread_model *tm);
/* perfetto_name - name a thread's track once */
void perfetto_name(struct perfetto *pf, __u32 **named, int *n, int *cap, __u32 tgid,
		   __u32 tid, const char *comm, const char *pcomm);

#endif
