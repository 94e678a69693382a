// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * thread_storm.c - threads created and gone at a rate, for test_faults.py:
 * every 10 ms it starts RATE/100 threads that end at once, and joins them,
 * for SECONDS. It writes what it did as JSON: the threads it created.
 *
 * usage: thread_storm NAME RATE SECONDS OUT.json
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <sys/prctl.h>

#define BATCH_MAX 1000

static void *nothing(void *arg)
{
	return arg;
}

int main(int argc, char **argv)
{
	static pthread_t t[BATCH_MAX];
	struct timespec next;
	long rate, ticks, k, i, n, created = 0, failed = 0;
	FILE *f;

	if (argc != 5)
		return 2;
	rate = atol(argv[2]);
	ticks = atol(argv[3]) * 100;
	n = rate / 100 > BATCH_MAX ? BATCH_MAX : rate / 100;
	prctl(PR_SET_NAME, argv[1], 0, 0, 0);
	clock_gettime(CLOCK_MONOTONIC, &next);
	for (k = 0; k < ticks; k++) {
		for (i = 0; i < n; i++)
			if (pthread_create(&t[i], NULL, nothing, NULL))
				break;
		failed += n - i;
		created += i;
		while (i--)
			pthread_join(t[i], NULL);
		next.tv_nsec += 10000000;
		if (next.tv_nsec >= 1000000000) {
			next.tv_nsec -= 1000000000;
			next.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
	}
	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"created\": %ld, \"failed\": %ld, \"seconds\": %.3f}\n", created, failed,
		ticks / 100.0);
	return fclose(f) ? 1 : 0;
}
