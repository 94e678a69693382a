/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * fuzz.h - what the libFuzzer targets share: the parsers under test read
 * files by name, so each input goes into an in-memory file whose name
 * (/proc/self/fd/N) they open like any other.
 */
#ifndef RTSUP_FUZZ_H
#define RTSUP_FUZZ_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* fuzz_file - the input as a file: its name, valid until the next call */
static inline const char *fuzz_file(const uint8_t *data, size_t size)
{
	static char path[64];
	static int fd = -1;

	if (fd < 0) {
		fd = memfd_create("rtsup-fuzz", 0);
		if (fd < 0) {
			perror("memfd_create");
			abort();
		}
		snprintf(path, sizeof(path), "/proc/self/fd/%d", fd);
	}
	if (ftruncate(fd, 0) || pwrite(fd, data, size, 0) != (ssize_t)size) {
		perror("fuzz input");
		abort();
	}
	return path;
}

/* fuzz_quiet - the reports a target prints are not what is tested */
static inline void fuzz_quiet(void)
{
	if (!freopen("/dev/null", "w", stdout))
		abort();
}

#endif
