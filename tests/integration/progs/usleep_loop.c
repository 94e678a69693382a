// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * usleep_loop.c - a real control loop for test_real_programs.py: a 1 ms
 * clock_nanosleep(TIMER_ABSTIME) loop that calls usleep(50) inside every
 * cycle, after a start-up that sleeps relatively and allocates. It writes
 * what it did as JSON: the cycles it ran, the ones it saw late itself, and
 * when each ended (ns after it took its name).
 *
 * usage: usleep_loop NAME PERIOD_US CYCLES OUT.json
 */
#define _GNU_SOURCE
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/prctl.h>

#define NS	1000000000LL

/* mono - CLOCK_MONOTONIC in ns */
static long long mono(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * NS + ts.tv_nsec;
}

/* spin - busy for 'ns' */
static void spin(long long ns)
{
	long long end = mono() + ns;

	while (mono() < end)
		;
}

/* sleep_until - clock_nanosleep(TIMER_ABSTIME) to 'at', again after EINTR */
static void sleep_until(long long at)
{
	struct timespec ts = { .tv_sec = at / NS, .tv_nsec = at % NS };

	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL))
		;
}

int main(int argc, char **argv)
{
	struct sched_param sp = { .sched_priority = 10 };
	long long period, next, start, *wake, *end, *late_at;
	int cycles, i, nlate = 0;
	char *buf;
	FILE *f;

	if (argc != 5) {
		fprintf(stderr, "usage: usleep_loop NAME PERIOD_US CYCLES OUT.json\n");
		return 2;
	}
	/* the tracer follows the thread by this name from here on */
	prctl(PR_SET_NAME, argv[1]);
	start = mono();
	period = atoll(argv[2]) * 1000;
	cycles = atoi(argv[3]);
	if (sched_setscheduler(0, SCHED_FIFO, &sp))
		perror("usleep_loop: SCHED_FIFO (running SCHED_OTHER)");
	/* start-up: a relative sleep, then allocations and page faults */
	usleep(20000);
	wake = calloc(cycles + 1, sizeof(*wake));
	end = calloc(cycles + 1, sizeof(*end));
	late_at = calloc(cycles + 1, sizeof(*late_at));
	buf = malloc(1 << 20);
	if (!wake || !end || !late_at || !buf)
		return 1;
	memset(buf, 1, 1 << 20);
	memset(wake, 0, (cycles + 1) * sizeof(*wake));

	next = mono() + period;
	sleep_until(next);		/* release of cycle 1 */
	for (i = 1; i <= cycles; i++) {
		wake[i] = mono();
		spin(100000);
		usleep(50);		/* the sleep inside the cycle */
		spin(20000);
		next += period;
		/* late: the next release is past when the cycle ends */
		end[i] = mono();
		if (end[i] >= next)
			late_at[nlate++] = i;
		sleep_until(next);
	}

	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"cycles\": %d, \"period_ns\": %lld, \"tid\": %d,", cycles, period,
		gettid());
	fprintf(f, " \"mean_period_ns\": %.1f, \"late\": [",
		(double)(wake[cycles] - wake[1]) / (cycles - 1));
	for (i = 0; i < nlate; i++)
		fprintf(f, "%s%lld", i ? ", " : "", late_at[i]);
	/* when each cycle ended, from when the thread took its name */
	fprintf(f, "], \"end_ns\": [");
	for (i = 1; i <= cycles; i++)
		fprintf(f, "%s%lld", i > 1 ? ", " : "", end[i] - start);
	fprintf(f, "]}\n");
	fclose(f);
	return 0;
}
