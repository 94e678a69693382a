// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * timerfd_loop.c - a real control loop for test_real_programs.py: it waits
 * for its 1 ms release by reading a timerfd, and inside every cycle reads
 * a pipe it has just written to (a read that does not wait). Traced with
 * --cycle-syscall naming read, only the timerfd read may end a cycle. It
 * writes the cycles it ran (and the expirations it missed) as JSON, and
 * how often it was stopped (SIGSTOP, 20 ms or more) inside a cycle: in its
 * work, or after its timerfd read had taken its expirations (the stop
 * then comes on the way back to user space, after the read returned, so
 * inside the cycle the read began). A stop while the read waits restarts
 * the read, which then returns the expirations the stop let pass.
 *
 * usage: timerfd_loop NAME PERIOD_US CYCLES OUT.json
 */
#define _GNU_SOURCE
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include <sys/prctl.h>
#include <sys/timerfd.h>

/* far longer than a cycle's work or a wakeup's latency, far shorter than the test's stops */
#define STOPPED_NS	10000000L

static long now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000L + ts.tv_nsec;
}

int main(int argc, char **argv)
{
	struct sched_param sp = { .sched_priority = 10 };
	struct itimerspec its = { 0 };
	uint64_t exp, missed = 0;
	int tfd, p[2], cycles, i, stopped_in_cycle = 0;
	long period_ns, t0, t1, t2;
	char c = 'x';
	FILE *f;

	if (argc != 5) {
		fprintf(stderr, "usage: timerfd_loop NAME PERIOD_US CYCLES OUT.json\n");
		return 2;
	}
	prctl(PR_SET_NAME, argv[1]);
	period_ns = atol(argv[2]) * 1000;
	cycles = atoi(argv[3]);
	if (sched_setscheduler(0, SCHED_FIFO, &sp))
		perror("timerfd_loop: SCHED_FIFO (running SCHED_OTHER)");
	tfd = timerfd_create(CLOCK_MONOTONIC, 0);
	if (tfd < 0 || pipe(p))
		return 1;
	its.it_value.tv_nsec = period_ns;
	its.it_interval.tv_nsec = period_ns;
	if (timerfd_settime(tfd, 0, &its, NULL))
		return 1;
	if (read(tfd, &exp, sizeof(exp)) != sizeof(exp))	/* release of cycle 1 */
		return 1;
	t0 = now_ns();
	for (i = 1; i <= cycles; i++) {
		/* the cycle's work: a message through a pipe, read at once */
		if (write(p[1], &c, 1) != 1 || read(p[0], &c, 1) != 1)
			return 1;
		t1 = now_ns();
		if (read(tfd, &exp, sizeof(exp)) != sizeof(exp))
			return 1;
		t2 = now_ns();
		missed += exp - 1;
		/*
		 * stopped in the work, or after the read took its expirations:
		 * then more time passed than they account for. A stop while the
		 * read waits restarts it, and its expirations cover the stop.
		 * (Not "exp == 1": a read late behind noise takes 2 or more, and
		 * a stop right after it was missed.)
		 */
		stopped_in_cycle += t1 - t0 > STOPPED_NS;
		stopped_in_cycle += t2 - t1 - (long)exp * period_ns > STOPPED_NS;
		t0 = t2;
	}
	f = fopen(argv[4], "w");
	if (!f)
		return 1;
	fprintf(f, "{\"cycles\": %d, \"tid\": %d, \"missed_expirations\": %llu, "
		"\"stopped_in_cycle\": %d}\n", cycles, gettid(), (unsigned long long)missed,
		stopped_in_cycle);
	fclose(f);
	return 0;
}
