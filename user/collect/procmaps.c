// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* procmaps.c - executable file mappings of a process, from /proc/PID/maps */
#include <stdlib.h>
#include <string.h>
#include "collect/procmaps.h"

int procmaps_parse_line(const char *line, struct procmap *m)
{
	unsigned long long start, end, pgoff, inode;
	char perms[8], dev[16];
	int pos = 0;
	size_t n;
	const char *path;

	if (sscanf(line, "%llx-%llx %7s %llx %15s %llu %n", &start, &end, perms, &pgoff, dev,
		   &inode, &pos) < 6 || !pos || start >= end)
		return -1;
	path = line + pos;
	/* code of a file, or the vDSO: anonymous and JIT regions are no module */
	if (strlen(perms) < 3 || perms[2] != 'x' ||
	    (path[0] != '/' && strncmp(path, PROCMAP_VDSO "\n", sizeof(PROCMAP_VDSO)) &&
	     strcmp(path, PROCMAP_VDSO)))
		return 0;
	memset(m, 0, sizeof(*m));
	m->start = start;
	m->end = end;
	m->pgoff = pgoff;
	n = strcspn(path, "\n");
	if (n >= sizeof(m->path))
		return 0;
	memcpy(m->path, path, n);
	m->path[n] = '\0';
	if (n > 10 && !strcmp(m->path + n - 10, " (deleted)")) {
		m->deleted = true;
		m->path[n - 10] = '\0';
	}
	return 1;
}

int procmaps_read(FILE *f, struct procmap **out)
{
	char line[512];
	struct procmap m, *v = NULL, *nv;
	int n = 0, cap = 0;

	while (fgets(line, sizeof(line), f)) {
		if (procmaps_parse_line(line, &m) != 1)
			continue;
		if (n == cap) {
			cap = cap ? cap * 2 : 16;
			nv = realloc(v, cap * sizeof(*v));
			if (!nv) {
				free(v);
				return -1;
			}
			v = nv;
		}
		v[n++] = m;
	}
	*out = v;
	return n;
}
