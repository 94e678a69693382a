/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * output.h - the sinks: a top-like table or JSON lines on stdout. They only
 * read the model; they never reach back into the loader.
 */
#ifndef RTSUP_OUTPUT_H
#define RTSUP_OUTPUT_H

#include <stdbool.h>
#include "collect/collector.h"
#include "judge/supervise.h"

/*
 * output_interval - report the interval that collector_sample just ended;
 * JSON settles the lifetime percentiles of its "total" (model_life_settle)
 */
void output_interval(struct collector *c, const struct supervisor *s, double elapsed,
		     double interval);
/* output_summary - the final report over the whole run, lifetime percentiles settled */
void output_summary(struct collector *c, const struct supervisor *s, double elapsed);
/* output_error - an error line: JSON on stdout in JSON mode, always stderr */
void output_error(const struct options *o, const char *msg);

#endif
