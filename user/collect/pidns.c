// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* pidns.c - is rtsup-trace in the initial PID namespace? */
#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "collect/pidns.h"

int nspid_levels(const char *status)
{
	const char *p = status;
	int n = 0;

	/* the line's own start: "NSpid:" elsewhere would be a name */
	while (p && strncmp(p, "NSpid:", 6)) {
		p = strchr(p, '\n');
		if (p)
			p++;
	}
	if (!p)
		return 0;
	for (p += 6; *p && *p != '\n'; ) {
		while (*p == ' ' || *p == '\t')
			p++;
		if (!isdigit((unsigned char)*p))
			break;
		n++;
		while (isdigit((unsigned char)*p))
			p++;
	}
	return n;
}

bool pidns_is_initial(void)
{
	char buf[4096];
	struct stat st;
	size_t len;
	FILE *f;

	/*
	 * The namespace's own inode says it even under a /proc mounted inside
	 * the container (unshare --mount-proc), where NSpid shows one level only
	 */
	if (!stat("/proc/self/ns/pid", &st) && st.st_ino != PIDNS_INIT_INO)
		return false;
	/* a /proc of an outer namespace lists this process's pid at every level */
	f = fopen("/proc/self/status", "re");
	if (!f)
		return true;
	len = fread(buf, 1, sizeof(buf) - 1, f);
	fclose(f);
	buf[len] = '\0';
	return nspid_levels(buf) <= 1;
}
