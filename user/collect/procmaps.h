/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * procmaps.h - the executable file mappings of a process (/proc/PID/maps),
 * read when a target process is first seen: its stacks are symbolized
 * with them even after it is gone.
 */
#ifndef RTSUP_PROCMAPS_H
#define RTSUP_PROCMAPS_H

#include <stdbool.h>
#include <stdio.h>
#include <linux/types.h>

struct procmap {
	__u64 start, end, pgoff;
	bool deleted;		/* "(deleted)": the file is gone from its path */
	char path[256];
};

/*
 * procmaps_parse_line - one line of /proc/PID/maps: 1 for an executable
 * file mapping (m filled), 0 for anything else, -1 for a line that is not
 * in the format
 */
int procmaps_parse_line(const char *line, struct procmap *m);
/* procmaps_read - the executable file mappings from f; count, or -1 */
int procmaps_read(FILE *f, struct procmap **out);

#endif
