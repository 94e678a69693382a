/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * stackopt.h - the words of --stacks/--stack-size and of a rule's stacks:
 * and stack_size: keys, one parser for the command line and the file
 */
#ifndef RTSUP_STACKOPT_H
#define RTSUP_STACKOPT_H

#include <linux/types.h>

/* stacks_parse - "off", "fp", "dwarf", "auto" as enum rtsup_stacks: 0, or -1 */
int stacks_parse(const char *s, __u32 *out);
/* stacks_name - the word of an enum rtsup_stacks, "?" for another value */
const char *stacks_name(__u32 kind);
/* stack_size_parse - "8K", "16384": bytes of user stack, 512 to 64K, 8-aligned: 0, or -1 */
int stack_size_parse(const char *s, __u32 *out);

#endif
