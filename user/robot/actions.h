/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * actions.h - the actions sink: on a level change, run the configured
 * commands, signals and FIFO or socket writes (config actions: and
 * --on-level). Nothing here blocks the main loop: commands are spawned
 * and reaped later, FIFOs and sockets are written without waiting, and
 * every failure is one line on stderr, never fatal.
 */
#ifndef RTSUP_ACTIONS_H
#define RTSUP_ACTIONS_H

#include <sys/types.h>
#include "config/actionspec.h"
#include "judge/supervise.h"

#define ACTIONS_MAX_RUNNING	4	/* commands at once; more are skipped */

struct actions {
	struct supervisor *s;		/* its configuration holds the actions */
	__u32 gen;			/* of that configuration, for the rate limit */
	struct rate_limit rate;
	struct {
		pid_t pid;		/* 0 = free */
		char spec[ACTION_ARG_LEN + 32];	/* for the line that reports its end */
		char component[48];
	} child[ACTIONS_MAX_RUNNING];
	__u64 skipped_rate;		/* by the rate limit */
	__u64 skipped_busy;		/* ACTIONS_MAX_RUNNING were running */
	__u64 runs;			/* actions done (commands started) */
};

/* actions_open - become the supervisor's on_change sink (if it has actions) */
void actions_open(struct actions *a, struct supervisor *s);
/* actions_poll - reap finished commands, log their failures; every loop turn */
void actions_poll(struct actions *a);
/* actions_running - commands started and not reaped yet */
int actions_running(const struct actions *a);
/* actions_close - reap what has ended, say what was skipped; running ones go on */
void actions_close(struct actions *a);
/* actions_json - the JSON line an action gets (malloc'd, no newline) */
char *actions_json(const struct level_change *c);

#endif
