// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * unsafe_flood.c - a flood of RT-unsafe events for test_faults.py: a 1 ms
 * clock_nanosleep(TIMER_ABSTIME) loop whose every cycle maps and unmaps a
 * page PAIRS times, more rare events than the ring buffer holds between two
 * reads. It writes what it did as JSON: cycles and mmap/munmap pairs.
 *
 * usage: unsafe_flood NAME CYCLES PAIRS OUT.json
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include <sys/mman.h>
#include <sys/prctl.h>

int main(int argc, char **argv)
{
	struct timespec next;
	long cycles, pairs, c, i, done = 0;
	FILE *f;

	if (argc != 5)
		return 2;
	cycles = atol(argv[2]);
	pairs = atol(argv[3]);
	prctl(PR_SET_NAME, argv[1], 0, 0, 0);
	clock_gettime(CLOCK_MONOTONIC, &next);
	for (c = 0; c < cycles; c++) {
		next.tv_nsec += 1000000;
		if (next.tv_nsec >= 1000000000) {
			next.tv_nsec -= 1000000000;
			next.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
		for (i = 0; i < pairs; i++) {
			void *p = mmap(NULL, 4096, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);

			if (p == MAP_FAILED)
				return 1;
			munmap(p, 4096);
			done++;
		}
	}
	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"tid\": %d, \"cycles\": %ld, \"pairs\": %ld}\n", getpid(), cycles, done);
	return fclose(f) ? 1 : 0;
}
