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
#include <string.h>
#include <linux/types.h>

struct procmap {
	__u64 start, end, pgoff;
	bool deleted;		/* "(deleted)": the file is gone from its path */
	char path[256];		/* PROCMAP_VDSO for the vDSO */
};

/* the vDSO's mapping: no file, its image is read from the process's memory */
#define PROCMAP_VDSO	"[vdso]"

/* procmap_is_vdso - the vDSO's mapping? */
static inline bool procmap_is_vdso(const struct procmap *m)
{
	return !strcmp(m->path, PROCMAP_VDSO);
}

/*
 * procmaps_parse_line - one line of /proc/PID/maps: 1 for an executable
 * file mapping or the vDSO (m filled), 0 for anything else, -1 for a line
 * that is not in the format
 */
int procmaps_parse_line(const char *line, struct procmap *m);
/* procmaps_read - the executable file mappings from f; count, or -1 */
int procmaps_read(FILE *f, struct procmap **out);

#endif
