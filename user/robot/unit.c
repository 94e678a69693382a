// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* unit.c - follow a systemd unit's cgroup across restarts */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <bpf/bpf.h>
#include <bpf/libbpf.h>
#include "collect/collector.h"
#include "robot/unit.h"
#include "can.h"	/* the skeleton's .bss holds can_if_slot */
#include "rtsup.skel.h"

#define CGROUP_ROOT "/sys/fs/cgroup"
#define MAX_DEPTH 8

void unit_name(const char *name, char *out, size_t len)
{
	static const char *const types[] = { ".service", ".scope", ".slice", ".socket",
					     ".mount", ".swap" };
	size_t i, n = strlen(name);

	for (i = 0; i < sizeof(types) / sizeof(types[0]); i++) {
		size_t t = strlen(types[i]);

		if (n > t && !strcmp(name + n - t, types[i])) {
			snprintf(out, len, "%s", name);
			return;
		}
	}
	snprintf(out, len, "%s.service", name);
}

/* find_in - depth-first search for a directory called name */
static int find_in(char *path, size_t len, const char *name, int depth)
{
	size_t base = strlen(path);
	struct dirent *de;
	DIR *d;
	int found = -1;

	if (depth > MAX_DEPTH)
		return -1;
	d = opendir(path);
	if (!d)
		return -1;
	while (found && (de = readdir(d))) {
		if (de->d_type != DT_DIR || de->d_name[0] == '.')
			continue;
		if (snprintf(path + base, len - base, "/%s", de->d_name) >= (int)(len - base))
			continue;
		if (!strcmp(de->d_name, name))
			found = 0;
		/* units live in slices; other directories hold no units */
		else if (strstr(de->d_name, ".slice"))
			found = find_in(path, len, name, depth + 1);
		if (found)
			path[base] = '\0';
	}
	closedir(d);
	return found;
}

int unit_find(const char *root, const char *name, char *path, size_t len)
{
	snprintf(path, len, "%s", root);
	if (find_in(path, len, name, 0)) {
		path[0] = '\0';
		return -1;
	}
	return 0;
}

void unit_init(struct unit_follow *u, const char *name)
{
	memset(u, 0, sizeof(*u));
	u->fd = -1;
	unit_name(name, u->name, sizeof(u->name));
	unit_find(CGROUP_ROOT, u->name, u->path, sizeof(u->path));
}

/* attach_cgroup - the kernel side matches new tasks of this cgroup from now on */
static int attach_cgroup(struct unit_follow *u, struct collector *c, const char *path,
			 ino_t ino)
{
	__u32 zero = 0;
	int fd = open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);

	if (fd < 0)
		return -1;
	if (bpf_map_update_elem(bpf_map__fd(c->skel->maps.cgroup), &zero, &fd, BPF_ANY)) {
		fprintf(stderr, "rtsup-trace: --unit %s: cannot match cgroup %s: %s\n", u->name,
			path, strerror(errno));
		close(fd);
		return -1;
	}
	if (u->fd >= 0)
		close(u->fd);
	u->fd = fd;
	u->ino = ino;
	if (path != u->path)
		snprintf(u->path, sizeof(u->path), "%s", path);
	return 0;
}

void unit_check(struct unit_follow *u, struct collector *c)
{
	struct targets t;
	struct stat st;
	char path[sizeof(u->path)];

	if (u->path[0] && !stat(u->path, &st) && st.st_ino == u->ino && u->fd >= 0)
		goto scan;
	/* first time, or the unit stopped or restarted: where is its cgroup now? */
	if (unit_find(CGROUP_ROOT, u->name, path, sizeof(path)) || stat(path, &st)) {
		if (u->fd >= 0)
			fprintf(stderr, "rtsup-trace: --unit %s: the unit is gone; waiting for it\n",
				u->name);
		if (u->fd >= 0)
			close(u->fd);
		u->fd = -1;
		u->path[0] = '\0';
		return;
	}
	if (attach_cgroup(u, c, path, st.st_ino))
		return;
	fprintf(stderr, "rtsup-trace: --unit %s: supervising cgroup %s\n", u->name,
		u->path + strlen(CGROUP_ROOT));
scan:
	memset(&t, 0, sizeof(t));
	t.cgroup = u->path;
	collector_scan(c, &t);
}

void unit_free(struct unit_follow *u)
{
	if (u->fd >= 0)
		close(u->fd);
	u->fd = -1;
}
