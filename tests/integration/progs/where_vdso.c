// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * where_vdso - a control thread whose RT-unsafe syscall is made inside the
 * vDSO, for tests/integration/test_where.py: clock_gettime of a CPU-time
 * clock, which the vDSO cannot answer from its data page and asks the
 * kernel for (its fallback syscall). glibc's clock_gettime calls the vDSO
 * for every clock, so the stack is [vdso] <- libc <- ctrl_update(). The
 * test's configuration makes clock_gettime unsafe for the thread
 * (forbid_syscalls), and its rules choose the thread's stacks.
 *
 * where_vdso CYCLES PERIOD_US EVERY: the thread "ctrl" waits first (no cycle
 * yet: the test lets it go with a line on stdin once the rules for it are
 * in the kernel), then runs CYCLES cycles to absolute releases; every
 * EVERY-th cycle ctrl_update() reads its CPU time. Its start time comes
 * from the main thread through a pipe: its own clock_gettime would be one
 * more syscall where the vDSO cannot read the clock (a guest's clock
 * source). At the end it prints its count as JSON on stderr:
 * {"tid": T, "cputime": N}.
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static long cycles, period_ns, every;
static volatile long reads;
static volatile pid_t ctrl_tid;
static volatile long sink;
static int gate[2];	/* main -> ctrl: the start time */

/* ctrl_update - the cycle's work; asks the kernel where it should not */
static __attribute__((noinline)) void ctrl_update(long i)
{
	struct timespec t;

	if (i % every)
		return;
	/* the result used: no tail call, ctrl_update keeps its frame */
	if (!clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t))	/* WHERE_CPUTIME */
		reads++;
	sink += t.tv_nsec;
}

/* ctrl_loop - absolute releases every period from t */
static __attribute__((noinline)) void ctrl_loop(struct timespec t)
{
	long i;

	for (i = 0; i < cycles; i++) {
		t.tv_nsec += period_ns;
		while (t.tv_nsec >= 1000000000L) {
			t.tv_nsec -= 1000000000L;
			t.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, NULL);
		ctrl_update(i);	/* WHERE_VDSO_CALL */
	}
}

static void *ctrl_main(void *arg)
{
	struct timespec t;

	ctrl_tid = gettid();
	if (read(gate[0], &t, sizeof(t)) != sizeof(t))
		return arg;
	ctrl_loop(t);
	sink++;
	return arg;
}

int main(int argc, char **argv)
{
	pthread_t th;
	struct timespec t;
	char c = 0;

	if (argc != 4) {
		fprintf(stderr, "usage: where_vdso CYCLES PERIOD_US EVERY\n");
		return 1;
	}
	cycles = atol(argv[1]);
	period_ns = atol(argv[2]) * 1000;
	every = atol(argv[3]);
	if (cycles <= 0 || period_ns <= 0 || every <= 0)
		return 1;
	if (pipe(gate))
		return 1;
	pthread_create(&th, NULL, ctrl_main, NULL);
	pthread_setname_np(th, "ctrl");
	while (c != '\n' && read(0, &c, 1) == 1)
		;
	clock_gettime(CLOCK_MONOTONIC, &t);
	if (write(gate[1], &t, sizeof(t)) != sizeof(t))
		return 1;
	pthread_join(th, NULL);
	fprintf(stderr, "{\"tid\": %d, \"cputime\": %ld}\n", (int)ctrl_tid, reads);
	return 0;
}
