/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * output_stacks.h - where in the code (--stacks): the distinct user stacks
 * of each thread's RT-unsafe events with their counts, in the table and
 * in JSON (docs/json.md).
 */
#ifndef RTSUP_OUTPUT_STACKS_H
#define RTSUP_OUTPUT_STACKS_H

#include <stdbool.h>
#include <stdio.h>
#include <jansson.h>
#include "model/stackagg.h"
#include "model/model.h"

/* stack_what - "syscall mmap", "block": the event a stack belongs to */
void stack_what(const struct stack_entry *e, char *buf, size_t len);
/*
 * stacks_table - a line per stack of the interval (window) with events in
 * it, or every stack of the run with its frames one per line (summary)
 */
void stacks_table(FILE *out, const struct stackagg *a, const struct model *m, bool window);
/* stacks_json - a thread's stacks: the interval's (window) or the run's */
json_t *stacks_json(const struct stackagg *a, __u32 tid, bool window);
/* stacks_health_json - stack records taken, and those lost, counted */
json_t *stacks_health_json(const struct stackagg *a);

#endif
