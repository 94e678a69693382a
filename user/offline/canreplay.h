/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * canreplay.h - `rtsup-trace can-replay FILE`: a candump log through the
 * same CAN accounting (include/can.h), checks and outputs as a live run,
 * with the same exit codes, for CI on recorded bus traces.
 */
#ifndef RTSUP_CANREPLAY_H
#define RTSUP_CANREPLAY_H

#include "options.h"
#include "judge/supervise.h"

/* can_replay_run - 0, 1 (unreadable or malformed file) or 2 (--check) */
int can_replay_run(const struct options *o, struct supervisor *s);

#endif
