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
 * A step between a wakeup and its clock read (either way) leaves that
 * cycle judged on CLOCK_MONOTONIC ('stepped_after_wake'): it woke before
 * the step, at its time, and its clock read says -2 s or +5 s. A step
 * forward that releases the sleep in progress wakes it before its time on
 * CLOCK_MONOTONIC: that cycle has no lateness on its clock.
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

/*
 * pair - CLOCK_REALTIME and CLOCK_MONOTONIC at one instant: the realtime
 * read between two monotonic ones no more than 20 us apart. Two reads one
 * after the other were ms apart when a TCG guest preempted the loop
 * between them, and every later lateness on one clock was off by that.
 */
static void pair(long long *rt, long long *mono)
{
	long long m0, m1;
	int i;

	for (i = 0; i < 1000; i++) {
		m0 = now(CLOCK_MONOTONIC);
		*rt = now(CLOCK_REALTIME);
		m1 = now(CLOCK_MONOTONIC);
		if (m1 - m0 < 20000)
			break;
	}
	*mono = m0 + (m1 - m0) / 2;
}

int main(int argc, char **argv)
{
	long long period, next, mnext, late, worst = 0, late_rt, worst_rt = 0, before, rt, mono;
	long cycles, c, restarts = 0, stretched = 0, stepped_after_wake = 0;
	struct timespec ts;
	FILE *f;

	if (argc != 5)
		return 2;
	period = atol(argv[2]) * 1000LL;
	cycles = atol(argv[3]);
	prctl(PR_SET_NAME, argv[1], 0, 0, 0);
	pair(&rt, &mono);
	next = rt + period;
	mnext = mono + period;
	for (c = 0; c < cycles; c++) {
		ts.tv_sec = next / NS;
		ts.tv_nsec = next % NS;
		before = now(CLOCK_MONOTONIC);
		clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &ts, NULL);
		pair(&rt, &mono);
		late = mono - mnext;
		late_rt = rt - next;
		if (mono - before > period + NS) {
			/* stepped back: the sleep lasted the step more; on the clock, on time */
			stretched++;
			mnext = mono - late_rt;
			late = late_rt;
		} else if ((late_rt < -period || late_rt > 2 * NS) && late >= 0) {
			/*
			 * stepped after the wakeup, before the read: the sleep
			 * ended at its time, its lateness is the monotonic one
			 */
			stepped_after_wake++;
			late_rt = late;
			if (late > worst)
				worst = late;
			if (late > worst_rt)
				worst_rt = late;
		}
		if (rt - next > 2 * NS) {
			/* stepped forward: start again from now */
			pair(&next, &mnext);
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
