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

/* output_interval - report the interval that collector_sample just ended */
void output_interval(const struct collector *c, const struct supervisor *s, double elapsed,
		     double interval);
/* output_summary - the final report over the whole run */
void output_summary(const struct collector *c, const struct supervisor *s, double elapsed);
/* output_error - an error line: JSON on stdout in JSON mode, always stderr */
void output_error(const struct options *o, const char *msg);

#endif
