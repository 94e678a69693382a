// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * where_nolibc - where_loop without the C library, for --stacks auto
 * (tests/integration/test_where.py): static, no libc, built with frame
 * pointers, so every module of the process (the program and the vDSO)
 * keeps them and auto picks the frame-pointer unwinder. x86_64 only: its
 * syscalls are made here, in a frame of ours.
 *
 * where_nolibc CYCLES PERIOD_US EVERY: waits for a line on stdin first (no
 * cycle yet: the test lets it go once rtsup-trace follows it), then runs
 * CYCLES cycles to absolute releases; every EVERY-th cycle
 * ctrl_update() maps and unmaps a page. At the end it prints its counts as
 * JSON on stderr: {"tid": T, "mmap": N, "munmap": N}.
 */
#define NR_read			0
#define NR_write		1
#define NR_mmap			9
#define NR_munmap		11
#define NR_gettid		186
#define NR_clock_gettime	228
#define NR_clock_nanosleep	230
#define NR_exit_group		231
#define CLOCK_MONOTONIC		1
#define TIMER_ABSTIME		1

struct ts {
	long sec, nsec;
};

static volatile long raw_calls, maps, unmaps;
static volatile char sink;

/* raw_done - a call after the syscall: the syscall's function keeps its frame */
static __attribute__((noinline)) void raw_done(void)
{
	raw_calls++;
}

/* sys - one syscall, made here */
static __attribute__((noinline)) long sys(long n, long a, long b, long c, long d, long e, long f)
{
	long ret;
	register long r10 __asm__("r10") = d;
	register long r8 __asm__("r8") = e;
	register long r9 __asm__("r9") = f;

	__asm__ volatile("syscall" : "=a"(ret)
			 : "0"(n), "D"(a), "S"(b), "d"(c), "r"(r10), "r"(r8), "r"(r9)
			 : "rcx", "r11", "memory");
	raw_done();
	return ret;
}

/* ctrl_update - the cycle's work; allocates where it should not */
static __attribute__((noinline)) void ctrl_update(long i, long every)
{
	char *p;

	if (i % every)
		return;
	p = (char *)sys(NR_mmap, 0, 4096, 3, 0x22, -1, 0);	/* WHERE_NOLIBC_MMAP */
	maps++;
	if ((unsigned long)p > -4096UL)
		return;
	sink = p[0];
	if (!sys(NR_munmap, (long)p, 4096, 0, 0, 0, 0))	/* WHERE_NOLIBC_MUNMAP */
		unmaps++;
}

/* ctrl_loop - absolute releases every period */
static __attribute__((noinline)) void ctrl_loop(long cycles, long period_ns, long every)
{
	struct ts t;
	long i;

	sys(NR_clock_gettime, CLOCK_MONOTONIC, (long)&t, 0, 0, 0, 0);
	for (i = 0; i < cycles; i++) {
		t.nsec += period_ns;
		while (t.nsec >= 1000000000L) {
			t.nsec -= 1000000000L;
			t.sec++;
		}
		sys(NR_clock_nanosleep, CLOCK_MONOTONIC, TIMER_ABSTIME, (long)&t, 0, 0, 0);
		ctrl_update(i, every);	/* WHERE_NOLIBC_CALL */
	}
}

static long num(const char *s)
{
	long v = 0;

	while (*s >= '0' && *s <= '9')
		v = v * 10 + *s++ - '0';
	return *s ? -1 : v;
}

/* put - append text, or a number, to the line */
static char *put(char *o, const char *s)
{
	while (*s)
		*o++ = *s++;
	return o;
}

static char *put_num(char *o, long v)
{
	char d[24];
	int n = 0;

	do
		d[n++] = '0' + v % 10;
	while ((v /= 10));
	while (n)
		*o++ = d[--n];
	return o;
}

/* start_c - from _start: argc and argv on the initial stack */
__attribute__((noinline, used)) void start_c(long *sp)
{
	char **argv = (char **)(sp + 1), line[128], *o = line;
	long argc = sp[0], cycles = -1, period = -1, every = -1;
	char c = 0;

	if (argc == 4) {
		cycles = num(argv[1]);
		period = num(argv[2]);
		every = num(argv[3]);
	}
	if (cycles <= 0 || period <= 0 || every <= 0) {
		sys(NR_exit_group, 1, 0, 0, 0, 0, 0);
		return;
	}
	while (c != '\n' && sys(NR_read, 0, (long)&c, 1, 0, 0, 0) == 1)
		;
	ctrl_loop(cycles, period * 1000, every);
	o = put(o, "{\"tid\": ");
	o = put_num(o, sys(NR_gettid, 0, 0, 0, 0, 0, 0));
	o = put(o, ", \"mmap\": ");
	o = put_num(o, maps);
	o = put(o, ", \"munmap\": ");
	o = put_num(o, unmaps);
	o = put(o, "}\n");
	sys(NR_write, 2, (long)line, o - line, 0, 0, 0);
	sys(NR_exit_group, 0, 0, 0, 0, 0, 0);
}

/* the entry: the stack aligned as for a call, the outermost frame pointer 0 */
__asm__(".globl _start\n"
	"_start:\n"
	"	xor %ebp, %ebp\n"
	"	mov %rsp, %rdi\n"
	"	and $-16, %rsp\n"
	"	call start_c\n"
	"	hlt\n");
