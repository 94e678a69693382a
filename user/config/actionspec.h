/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * actionspec.h - what to do when a supervised component reaches (or leaves)
 * a level: run a command, send a signal, write a line to a FIFO or a Unix
 * socket. The --on-level SPEC parser, its printed form, and the rate limit
 * of actions.c, all plain functions (tests/unit/config/test_actionspec.c).
 */
#ifndef RTSUP_ACTIONSPEC_H
#define RTSUP_ACTIONSPEC_H

#include <stdbool.h>
#include <stddef.h>
#include <linux/types.h>
#include "judge/status.h"

#define ACTION_ARG_LEN	256
#define ACTION_MAX	16		/* --on-level and actions: together */

enum action_kind {
	ACTION_RUN,		/* arg: a shell command (/bin/sh -c) */
	ACTION_SIGNAL,		/* sig to pid, or to the component's process if pid is 0 */
	ACTION_FIFO,		/* arg: path of a FIFO, one JSON line */
	ACTION_UNIX,		/* arg: path of a Unix socket, one JSON line */
};

struct action {
	enum level level;
	bool leave;		/* on leaving the level, not on reaching it */
	enum action_kind kind;
	int sig;
	__u64 pid;		/* ACTION_SIGNAL: 0 = the component's process */
	char arg[ACTION_ARG_LEN];
	int line;		/* in the config file, 0 from the command line */
};

/*
 * action_parse - "[!]LEVEL:WHAT", WHAT one of signal=SIG[@PID], fifo=PATH,
 * unix=PATH, run=CMD, or any other text: a shell command. 0 or -1 with a
 * reason in err ("want ...").
 */
int action_parse(const char *spec, struct action *a, char *err, size_t errlen);
/* action_format - the SPEC of an action, as action_parse reads it back */
void action_format(const struct action *a, char *buf, size_t len);
/* action_matches - does a change from -> to fire this action? */
bool action_matches(const struct action *a, enum level from, enum level to);
/* level_parse - "OK", "WARN", "ERROR", "STALE" (any case); -1 if none */
int level_parse(const char *s);
/* signal_parse - "USR1", "SIGUSR1", "10" or "RTMIN+2"; -1 if none */
int signal_parse(const char *s);
/* signal_name - "USR1" (a static buffer for numbers without a name) */
const char *signal_name(int sig);

/*
 * The rate limit: an action runs at most once per RATE_GAP_NS for one
 * component; the table remembers the last run of RATE_SLOTS pairs, the
 * oldest making room for a new one.
 */
#define RATE_GAP_NS	1000000000ULL
#define RATE_SLOTS	256

struct rate_slot {
	int action;		/* index in the configuration's actions, -1 = free */
	char component[48];
	__u64 last_ns;
};

struct rate_limit {
	struct rate_slot slot[RATE_SLOTS];
};

/* rate_init - no action ran yet */
void rate_init(struct rate_limit *r);
/* rate_allow - may action run for component at now? If so, it counts as run */
bool rate_allow(struct rate_limit *r, int action, const char *component, __u64 now);

#endif
