// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * fuzz_proc.c - the /proc and cgroup text the targets module reads
 * (user/collect/targets.c): a comm file (then comm_sanitize), /proc/<tid>/status
 * for the Tgid, cgroup.threads, and the CPU mask formatter on the bytes.
 */
#include <string.h>
#include "collect/targets.h"
#include "fuzz.h"

/* count - a cgroup.threads callback that stops at the 1000th thread */
static int count(void *arg, pid_t tid)
{
	int *n = arg;

	return ++*n >= 1000;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	unsigned long bits[1024 / (8 * sizeof(unsigned long))] = { 0 };
	char comm[RTSUP_COMM_LEN], list[64];
	FILE *f;
	int n = 0;

	if (!size)
		return 0;
	f = fmemopen((void *)data, size, "r");
	if (!f)
		return 0;
	if (!comm_read(f, comm, sizeof(comm))) {
		comm_sanitize(comm, sizeof(comm));
		if (strlen(comm) >= sizeof(comm))
			abort();
	}
	rewind(f);
	status_tgid(f);
	rewind(f);
	cgroup_threads(f, count, &n);
	fclose(f);
	memcpy(bits, data, size < sizeof(bits) ? size : sizeof(bits));
	cpu_list_mask(bits, 1024, list, sizeof(list));
	if (!memchr(list, '\0', sizeof(list)))
		abort();
	return 0;
}
