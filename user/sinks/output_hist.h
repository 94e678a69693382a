/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * output_hist.h - the --hist sink: per thread with cycles, the histograms of
 * the chosen metrics, drawn on the terminal (histdraw) or as JSON.
 */
#ifndef RTSUP_OUTPUT_HIST_H
#define RTSUP_OUTPUT_HIST_H

#include <stdbool.h>
#include <jansson.h>
#include "collect/collector.h"
#include "model/canmodel.h"
#include "judge/supervise.h"

/* hist_shown - does a thread get histograms (it has cycles)? */
bool hist_shown(const struct thread_model *tm);
/* hist_table - draw the histograms of the run (or of the last interval: window) */
void hist_table(const struct collector *c, const struct supervisor *sv, bool window);
/*
 * hist_json - {"latency_ns": {"count": N, "buckets": [[lo, hi, count], ...]}, ...}:
 * the non-empty kernel buckets, lo and hi inclusive, in ns
 */
json_t *hist_json(const struct thread_model *tm, unsigned int metrics, bool window);

/* hist_can_table - the inter-frame gaps of every CAN identifier, drawn */
void hist_can_table(const struct can_model *m, const struct options *o);
/* hist_can_json - "gap_hist" into each of can_json's "ids", in the model's order */
void hist_can_json(json_t *can, const struct can_model *m);

#endif
