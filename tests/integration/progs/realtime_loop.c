// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * realtime_loop.c - a control loop on CLOCK_REALTIME for test_faults.py's
 * clock steps: clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME) every period;
 * a wakeup more than 2 s past its deadline (the clock stepped forward; an
 * emulated guest is often 100 ms late) starts the schedule again from
 * now, as a careful loop does. A step back only makes one sleep longer:
 * the schedule goes on, on the clock. It writes what it saw as JSON:
 * cycles, restarts, the sleeps that lasted 1 s more than a period on
 * CLOCK_MONOTONIC ('stretched': a step back), its worst lateness on
 * CLOCK_MONOTONIC (which no step moves; a step back adds to it), and
 * its worst lateness on its own clock (the step back's sleep included).
 * A step back between a wakeup and its clock read leaves that cycle
 * judged on CLOCK_MONOTONIC ('stepped_after_wake'): it woke before the
 * step, and its clock read says -2 s.
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
	long long period, next, mnext, late, worst = 0, late_rt, worst_rt = 0, before;
	long cycles, c, restarts = 0, stretched = 0, stepped_after_wake = 0;
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
		before = now(CLOCK_MONOTONIC);
		clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &ts, NULL);
		late = now(CLOCK_MONOTONIC) - mnext;
		late_rt = now(CLOCK_REALTIME) - next;
		if (late_rt < -period) {
			/* stepped back after the wakeup: the sleep ended on the old time */
			stepped_after_wake++;
			late_rt = late;
		}
		if (now(CLOCK_MONOTONIC) - before > period + NS) {
			/* stepped back: the sleep lasted the step more; on the clock, on time */
			stretched++;
			mnext = now(CLOCK_MONOTONIC) - late_rt;
			late = late_rt;
		}
		if (late_rt > 2 * NS) {
			/* stepped forward: start again from now */
			next = now(CLOCK_REALTIME);
			mnext = now(CLOCK_MONOTONIC);
			restarts++;
		} else {
			if (late > worst)
				worst = late;
			if (late_rt > worst_rt)
				worst_rt = late_rt;
		}
		next += period;
		mnext += period;
	}
	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"cycles\": %ld, \"restarts\": %ld, \"stretched\": %ld, "
		"\"stepped_after_wake\": %ld, \"worst_late_ns\": %lld, \"worst_late_rt_ns\": %lld}\n",
		cycles, restarts, stretched, stepped_after_wake, worst, worst_rt);
	return fclose(f) ? 1 : 0;
}
