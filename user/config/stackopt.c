// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* stackopt.c - the words of --stacks and --stack-size, for the command line and the file */
#include <string.h>
#include "config/stackopt.h"
#include "config/strict.h"
#include "rtsup.h"

/* enum rtsup_stacks by its word: the table reads both ways */
static const char *const stacks_names[] = {
	[RTSUP_STACKS_OFF] = "off",
	[RTSUP_STACKS_FP] = "fp",
	[RTSUP_STACKS_DWARF] = "dwarf",
	[RTSUP_STACKS_AUTO] = "auto",
};

int stacks_parse(const char *s, __u32 *out)
{
	__u32 i;

	for (i = 0; i < sizeof(stacks_names) / sizeof(stacks_names[0]); i++)
		if (!strcmp(s, stacks_names[i])) {
			*out = i;
			return 0;
		}
	return -1;
}

const char *stacks_name(__u32 kind)
{
	return kind < sizeof(stacks_names) / sizeof(stacks_names[0]) ? stacks_names[kind] : "?";
}

int stack_size_parse(const char *s, __u32 *out)
{
	long v;

	if (strict_size(s, 512, RTSUP_STACK_DUMP_MAX, &v) || v % 8)
		return -1;
	*out = v;
	return 0;
}
