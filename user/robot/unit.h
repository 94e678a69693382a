/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * unit.h - --unit NAME: supervise a systemd unit's cgroup, and keep
 * following it when the unit restarts (systemd removes the cgroup when the
 * unit stops and creates a new one when it starts again).
 */
#ifndef RTSUP_UNIT_H
#define RTSUP_UNIT_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

struct collector;

struct unit_follow {
	char name[256];		/* with its type suffix, e.g. "ctrl.service" */
	char path[4096];	/* cgroup directory, "" while the unit has none */
	ino_t ino;		/* the cgroup's inode: a new cgroup has a new one */
	int fd;			/* open cgroup directory, -1 = none */
};

/* unit_name - NAME with ".service" added when it has no unit type suffix */
void unit_name(const char *name, char *out, size_t len);
/*
 * unit_find - search the cgroup tree below root for the directory of unit
 * 'name' (systemd's layout: a unit's cgroup is a directory with its name);
 * 0 and the path, -1 when there is none
 */
int unit_find(const char *root, const char *name, char *path, size_t len);
/* unit_init - resolve NAME now; a unit not running yet is not an error */
void unit_init(struct unit_follow *u, const char *name);
/*
 * unit_check - once per interval: when the cgroup is new (the unit
 * restarted) point the kernel side at it; add the threads in it (tasks that
 * systemd moved in after forking them are found here)
 */
void unit_check(struct unit_follow *u, struct collector *c);
void unit_free(struct unit_follow *u);

#endif
