// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * where_loop - a periodic control thread that maps memory from a known
 * function inside its cycle, for tests/integration/test_where.py.
 *
 * where_loop CYCLES PERIOD_US EVERY [LINGER_S]: the thread "ctrl" runs CYCLES cycles to
 * absolute releases; every EVERY-th cycle ctrl_update() maps and unmaps a
 * page. At the end it prints its own counts as JSON on stderr (stdout is
 * the tracer's, whose long JSON lines it would split): the truth the test
 * compares the reported stacks with. Built twice by the Makefile: with
 * frame pointers (where_loop_fp, WHERE_RAW_SYSCALL: the mmap is a syscall
 * made in this file, so no frameless libc wrapper hides the caller) and
 * -O2 -g without them (where_loop_dwarf, through glibc's mmap), and so with
 * the calls inside a shared library of ours (where_loop_lib, WHERE_LIB).
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

static long cycles, period_ns, every;
static volatile long maps, unmaps;
/* time in each mmap, ns: scripts/stack-cost compares --stacks modes */
#define MAX_SAMPLES 65536
static long mmap_ns[MAX_SAMPLES];
static volatile pid_t ctrl_tid;
static volatile char sink;

#ifdef WHERE_RAW_SYSCALL
static volatile long raw_calls;

/*
 * raw_done - a call after the syscall: gcc 12 builds a leaf function with
 * inline asm without a frame whatever -mno-omit-leaf-frame-pointer says
 */
static __attribute__((noinline)) void raw_done(void)
{
	raw_calls++;
}

/* do_mmap, do_munmap - the syscall instruction here, in a frame of ours */
static __attribute__((noinline)) void *do_mmap(size_t len)
{
	long ret;
	register long r10 __asm__("r10") = MAP_PRIVATE | MAP_ANONYMOUS;
	register long r8 __asm__("r8") = -1;
	register long r9 __asm__("r9") = 0;

	__asm__ volatile("syscall" : "=a"(ret)
			 : "0"(SYS_mmap), "D"(0), "S"(len), "d"(PROT_READ | PROT_WRITE),
			   "r"(r10), "r"(r8), "r"(r9)
			 : "rcx", "r11", "memory");
	raw_done();
	return (void *)ret;
}

static __attribute__((noinline)) int do_munmap(void *p, size_t len)
{
	long ret;

	__asm__ volatile("syscall" : "=a"(ret) : "0"(SYS_munmap), "D"(p), "S"(len)
			 : "rcx", "r11", "memory");
	raw_done();
	return ret;
}
#elif defined(WHERE_LIB)
/* where_loop_lib: the calls are made inside libwhere.so (where_lib.c) */
void *lib_map(size_t len);
int lib_unmap(void *p, size_t len);
#define do_mmap(len) (lib_map(len) ?: MAP_FAILED)
#define do_munmap(p, len) lib_unmap(p, len)
#else
#define do_mmap(len) mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
#define do_munmap(p, len) munmap(p, len)
#endif

/* ctrl_update - the cycle's work; allocates where it should not */
static __attribute__((noinline)) void ctrl_update(long i)
{
	struct timespec t0, t1;
	char *p;

	if (i % every)
		return;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	p = do_mmap(4096);	/* WHERE_MMAP */
	clock_gettime(CLOCK_MONOTONIC, &t1);
	if (maps < MAX_SAMPLES)
		mmap_ns[maps] = (t1.tv_sec - t0.tv_sec) * 1000000000L + t1.tv_nsec - t0.tv_nsec;
	maps++;
	if (p == MAP_FAILED)
		return;
	sink = p[0];	/* WHERE_TOUCH: a fresh page, one minor fault */
	/* the result used: no tail call, ctrl_update keeps its frame */
	if (!do_munmap(p, 4096))	/* WHERE_MUNMAP */
		unmaps++;
}

/* ctrl_loop - absolute releases every period */
static __attribute__((noinline)) void ctrl_loop(void)
{
	struct timespec t;
	long i;

	clock_gettime(CLOCK_MONOTONIC, &t);
	for (i = 0; i < cycles; i++) {
		t.tv_nsec += period_ns;
		while (t.tv_nsec >= 1000000000L) {
			t.tv_nsec -= 1000000000L;
			t.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, NULL);
		ctrl_update(i);	/* WHERE_CALL */
	}
}

static int cmp_long(const void *a, const void *b)
{
	return *(const long *)a < *(const long *)b ? -1 : *(const long *)a > *(const long *)b;
}

/* quantile - the q-quantile of the first n samples (sorts them) */
static long quantile(long *v, long n, double q)
{
	if (!n)
		return 0;
	qsort(v, n, sizeof(*v), cmp_long);
	return v[(long)(q * (n - 1))];
}

static void *ctrl_main(void *arg)
{
	ctrl_tid = gettid();
	ctrl_loop();
	sink++;
	return arg;
}

int main(int argc, char **argv)
{
	pthread_t th;
	long n;

	if (argc != 4 && argc != 5) {
		fprintf(stderr, "usage: where_loop CYCLES PERIOD_US EVERY [LINGER_S]\n");
		return 1;
	}
	cycles = atol(argv[1]);
	period_ns = atol(argv[2]) * 1000;
	every = atol(argv[3]);
	if (cycles <= 0 || period_ns <= 0 || every <= 0)
		return 1;
	pthread_create(&th, NULL, ctrl_main, NULL);
	pthread_setname_np(th, "ctrl");
	pthread_join(th, NULL);
	n = maps < MAX_SAMPLES ? maps : MAX_SAMPLES;
	/* the 10th percentile: the mmap's own path, less of a busy machine's noise */
	fprintf(stderr, "{\"tid\": %d, \"mmap\": %ld, \"munmap\": %ld, \"mmap_ns\": %ld, "
		"\"mmap_p10_ns\": %ld}\n", (int)ctrl_tid, maps, unmaps, quantile(mmap_ns, n, 0.5),
		quantile(mmap_ns, n, 0.1));
	/* scripts/stack-cost reads the programs' statistics while we linger */
	if (argc == 5)
		sleep(atoi(argv[4]));
	return 0;
}
