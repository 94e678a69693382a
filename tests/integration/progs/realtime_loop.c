// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * realtime_loop.c - a control loop on CLOCK_REALTIME for test_faults.py's
 * clock step: clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME) every period;
 * a wakeup more than 2 s past its deadline (the clock stepped forward; an
 * emulated guest is often 100 ms late) starts the schedule again from
 * now, as a careful loop does. It writes
 * what it saw as JSON: cycles, restarts, and its worst lateness on the
 * CLOCK_MONOTONIC clock (which no step moves).
 *
 * usage: realtime_loop NAME PERIOD_US CYCLES OUT.json
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <sys/prctl.h>

#define NS 1000000000LL

static long long now(clockid_t c)
{
	struct timespec ts;

	clock_gettime(c, &ts);
	return ts.tv_sec * NS + ts.tv_nsec;
}

int main(int argc, char **argv)
{
	long long period, next, mnext, late, worst = 0;
	long cycles, c, restarts = 0;
	struct timespec ts;
	FILE *f;

	if (argc != 5)
		return 2;
	period = atol(argv[2]) * 1000LL;
	cycles = atol(argv[3]);
	prctl(PR_SET_NAME, argv[1], 0, 0, 0);
	next = now(CLOCK_REALTIME) + period;
	mnext = now(CLOCK_MONOTONIC) + period;
	for (c = 0; c < cycles; c++) {
		ts.tv_sec = next / NS;
		ts.tv_nsec = next % NS;
		clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &ts, NULL);
		late = now(CLOCK_MONOTONIC) - mnext;
		if (now(CLOCK_REALTIME) - next > 2 * NS) {
			/* stepped forward: start again from now */
			next = now(CLOCK_REALTIME);
			mnext = now(CLOCK_MONOTONIC);
			restarts++;
		} else if (late > worst) {
			worst = late;
		}
		next += period;
		mnext += period;
	}
	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"cycles\": %ld, \"restarts\": %ld, \"worst_late_ns\": %lld}\n", cycles,
		restarts, worst);
	return fclose(f) ? 1 : 0;
}
