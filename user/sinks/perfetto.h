/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * perfetto.h - a trace for the Perfetto UI (Chrome JSON trace format): a
 * track per thread, a slice per cycle, deadline misses and RT-unsafe events
 * as instant events. Written live (--perfetto) or from a recorded trace.
 */
#ifndef RTSUP_PERFETTO_H
#define RTSUP_PERFETTO_H

#include <stddef.h>
#include <linux/types.h>
#include "rtsup.h"

struct perfetto;

/* perfetto_open - create FILE; -1 with one line in err */
int perfetto_open(struct perfetto **p, const char *path, char *err, size_t errlen);
/* perfetto_thread - name a thread's track (once per thread is enough) */
void perfetto_thread(struct perfetto *p, __u32 tgid, __u32 tid, const char *comm,
		     const char *pcomm);
/* perfetto_cycle - one finished cycle as a slice from its release to its end */
void perfetto_cycle(struct perfetto *p, __u32 tgid, __u32 tid, const struct rtsup_cycle *c);
/* perfetto_event - a rare event as an instant event on the thread's track */
void perfetto_event(struct perfetto *p, const struct rtsup_event *e);
/*
 * perfetto_stack - where in the code (--stacks): an instant event "where:
 * WHAT" at the RT-unsafe event's time, the symbolized stack in its args
 */
void perfetto_stack(struct perfetto *p, __u64 ts, __u32 tgid, __u32 tid, const char *what,
		    const char *stack);
/* perfetto_close - finish the JSON and close; -1 with one line in err */
int perfetto_close(struct perfetto *p, char *err, size_t errlen);

#endif
