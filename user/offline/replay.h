/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * replay.h - `rtsup-trace replay FILE`: a recorded trace through the same
 * model, checks and outputs as a live run, with the same exit codes.
 */
#ifndef RTSUP_REPLAY_H
#define RTSUP_REPLAY_H

#include "options.h"
#include "judge/supervise.h"

/* replay_run - 0, 1 (tool error: unreadable or corrupt file) or 2 (--check) */
int replay_run(const struct options *o, struct supervisor *s);

#endif
