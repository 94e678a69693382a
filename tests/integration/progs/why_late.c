// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * why_late - a periodic SCHED_FIFO thread made late on purpose, for the
 * cause attribution tests (test_why.py). Every thread is pinned to one CPU.
 *
 *   why_late hog CPU SECONDS
 *	"why-rt" FIFO 50, 1 ms period, 100 us of work; "why-hog" FIFO 60
 *	burns 3 ms every 100 ms.
 *   why_late mutex|pi CPU SECONDS
 *	"why-rt" FIFO 50, 1 ms period, takes a mutex (plain, or priority
 *	inheritance) each cycle; "why-owner" FIFO 10 holds it for 2 ms every
 *	50 ms.
 *   why_late alone CPU SECONDS
 *	"why-rt" alone (the noise comes from outside: rtsup-noise inject).
 *   why_late preempt CPU SECONDS
 *	"why-rt" FIFO 50, 5 ms period, 3 ms of work; "why-preemptor" FIFO 70
 *	burns 4 ms every 50 ms (so it comes inside why-rt's work).
 *   why_late migrate CPU SECONDS
 *	"why-rt" FIFO 50, 20 ms period, 200 us of work; every 10th cycle it
 *	moves itself to the other CPU (CPU - 1, or 1) in the middle of its
 *	work: sched_setaffinity to that CPU alone. "moves" lists each move as
 *	[from, to], the CPUs it ran on before and after (sched_getcpu).
 *   why_late machine CPU SECONDS
 *	"why-rt" FIFO 50 alone, 20 ms period, 100 us of work: the lateness
 *	comes from the machine (a guest its hypervisor holds: vm-test hiccups).
 *   why_late fault CPU SECONDS
 *	"why-rt" FIFO 50, 1 ms period, 100 us of work, blocks in two places:
 *	every 100th cycle it writes a byte to /dev/null (a syscall that
 *	returns) and then touches a page that userfaultfd holds: "why-uffd"
 *	FIFO 10 resolves the fault 2 ms after it read it (a block in a page
 *	fault, in no syscall); 50 cycles later it waits 2 ms on a futex that
 *	nobody wakes (a block in futex). "faults" and "futex_waits" count
 *	those that slept.
 *
 * SCALE (optional, default 1) makes every period, work, burst and hold of
 * the mode that many times longer: for an emulated guest's slow CPUs.
 *
 * At the end one JSON line on stdout: what the program itself saw: the
 * tids, the bursts (or lock holds) done, the deadline misses why-rt saw
 * (its work ended after its next release) and the longest burst; and how
 * its wakeups went: "slept_misses" (cycles that slept, then missed: a late
 * wakeup or a wait after it), "backlogs" (releases already past when it
 * went to sleep: no sleep), "late_ns" (every wakeup 1 ms or more after its
 * release, as it saw it after the sleep returned: its timer's lateness plus
 * the way back to user space).
 */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <linux/futex.h>
#include <linux/userfaultfd.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define MS 1000000LL

static int cpu;
static int64_t end_ns;
static pthread_mutex_t lock;
static volatile int rt_tid, other_tid;
static long bursts, misses, cycles;
static int64_t burst_max;
/*
 * The longest burst from its timer's expiry: the thread switched in at or
 * after it (a timer never fires early), so this bounds the time it held
 * the CPU from its start, a vCPU held by the host before its first clock
 * read included (burst_max starts at that read)
 */
static int64_t burst_span_max;
#define LATE_MAX	512
static long slept_misses, backlogs, nlate;
static int64_t late_ns[LATE_MAX];
static int migrate_every, moves[LATE_MAX][2];
static long nmoves;
/* fault mode: the pages userfaultfd holds, the faults and futex waits made */
#define FAULT_PAGES	256
static int fault_every, uffd = -1, devnull = -1, futex_word, resolver_stop;
static char *fault_area, *fault_src;
static long page_size, faults, futex_waits;

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void die(const char *what)
{
	fprintf(stderr, "why_late: %s: %s\n", what, strerror(errno));
	exit(1);
}

/* rt_self - name, pin and prioritise the calling thread */
static void rt_self(const char *name, int prio)
{
	struct sched_param sp = { .sched_priority = prio };
	cpu_set_t set;

	pthread_setname_np(pthread_self(), name);
	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	if (pthread_setaffinity_np(pthread_self(), sizeof(set), &set))
		die("affinity");
	errno = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
	if (errno)
		die("SCHED_FIFO (run as root)");
}

static void burn_until(int64_t t)
{
	while (now_ns() < t)
		;
}

static void sleep_until(int64_t t)
{
	struct timespec ts = { t / 1000000000LL, t % 1000000000LL };

	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
		;
}

/* move_self - to the other CPU, inside the cycle: where it ran before and after */
static void move_self(int *from_to)
{
	int other = cpu ? cpu - 1 : 1, here = sched_getcpu();
	cpu_set_t set;

	CPU_ZERO(&set);
	CPU_SET(here == cpu ? other : cpu, &set);
	if (sched_setaffinity(0, sizeof(set), &set))
		die("affinity");
	from_to[0] = here;
	from_to[1] = sched_getcpu();
}

struct rt_args {
	int64_t period, work;
	int use_lock;
	int64_t hold;	/* fault mode: the futex wait's length */
};

/*
 * block_in_fault_or_futex - fault mode, once a cycle: every fault_every-th
 * cycle a write that returns, then a touch of a page that only why-uffd
 * fills; fault_every / 2 cycles later a futex wait of 'hold' that times out
 */
static void block_in_fault_or_futex(int64_t hold)
{
	long c = cycles % fault_every;

	if (c == fault_every - 1 && faults < FAULT_PAGES) {
		(void)!write(devnull, "x", 1);
		*(volatile char *)(fault_area + faults * page_size) = 1;
		faults++;
	} else if (c == fault_every / 2 - 1) {
		struct timespec ts = { hold / 1000000000LL, hold % 1000000000LL };

		/* nobody wakes it: a wait that slept its whole length */
		if (syscall(SYS_futex, &futex_word, FUTEX_WAIT_PRIVATE, 0, &ts, NULL, 0) &&
		    errno == ETIMEDOUT)
			futex_waits++;
	}
}

/* periodic - why-rt: work, then sleep to the next absolute release */
static void *periodic(void *p)
{
	const struct rt_args *a = p;
	int64_t next;

	rt_self("why-rt", 50);
	rt_tid = gettid();
	next = now_ns() + a->period;
	while (next < end_ns) {
		int64_t t = now_ns();
		int slept = t < next;

		/* a release already past returns at once: the tracer sees it so */
		sleep_until(next);
		if (slept) {
			t = now_ns() - next;
			if (t >= 1 * MS && nlate < LATE_MAX)
				late_ns[nlate++] = t;
		} else {
			backlogs++;
		}
		if (a->use_lock)
			pthread_mutex_lock(&lock);
		if (migrate_every && cycles % migrate_every == migrate_every - 1 &&
		    nmoves < LATE_MAX) {
			burn_until(now_ns() + a->work / 2);
			move_self(&moves[nmoves++][0]);
		}
		burn_until(now_ns() + a->work);
		if (a->use_lock)
			pthread_mutex_unlock(&lock);
		if (fault_every)
			block_in_fault_or_futex(a->hold);
		next += a->period;
		cycles++;
		/* as the tracer judges: the next release is past at the sleep */
		if (now_ns() >= next) {
			misses++;
			slept_misses += slept;
		}
	}
	return NULL;
}

struct other_args {
	const char *name;
	int prio;
	int64_t every, burn;
	int use_lock;
};

/* other - the hog, the preemptor or the lock owner: burn at known times */
static void *other(void *p)
{
	const struct other_args *a = p;
	int64_t next, t0, end;

	rt_self(a->name, a->prio);
	other_tid = gettid();
	next = now_ns() + 200 * MS;	/* let why-rt settle first */
	while (next + a->burn < end_ns - 50 * MS) {
		sleep_until(next);
		t0 = now_ns();
		if (a->use_lock)
			pthread_mutex_lock(&lock);
		burn_until(t0 + a->burn);
		if (a->use_lock)
			pthread_mutex_unlock(&lock);
		end = now_ns();
		if (end - t0 > burst_max)
			burst_max = end - t0;
		if (end - next > burst_span_max)
			burst_span_max = end - next;
		bursts++;
		/* +-10 ms so that it never locks to why-rt's phase */
		next += a->every + (rand() % 21 - 10) * MS;
	}
	return NULL;
}

/* resolver - why-uffd: fills each page why-rt touches, 'burn' after it read the fault */
static void *resolver(void *p)
{
	const struct other_args *a = p;
	struct pollfd pfd = { .events = POLLIN };
	struct uffd_msg m;
	int64_t t0, end;

	rt_self(a->name, a->prio);
	other_tid = gettid();
	pfd.fd = uffd;
	while (!__atomic_load_n(&resolver_stop, __ATOMIC_ACQUIRE)) {
		if (poll(&pfd, 1, 100) <= 0 || read(uffd, &m, sizeof(m)) != sizeof(m) ||
		    m.event != UFFD_EVENT_PAGEFAULT)
			continue;
		t0 = now_ns();
		sleep_until(t0 + a->burn);
		struct uffdio_copy cp = {
			.dst = m.arg.pagefault.address & ~(page_size - 1),
			.src = (unsigned long)fault_src, .len = page_size,
		};
		if (ioctl(uffd, UFFDIO_COPY, &cp))
			die("UFFDIO_COPY");
		end = now_ns();
		if (end - t0 > burst_max)
			burst_max = end - t0;
		if (end - t0 > burst_span_max)
			burst_span_max = end - t0;
		bursts++;
	}
	return NULL;
}

/* fault_setup - pages that fault into why-uffd: unlocked, empty, registered */
static void fault_setup(void)
{
	size_t len;

	page_size = sysconf(_SC_PAGESIZE);
	len = FAULT_PAGES * page_size;
	devnull = open("/dev/null", O_WRONLY | O_CLOEXEC);
	uffd = syscall(SYS_userfaultfd, O_CLOEXEC | O_NONBLOCK);
	if (devnull < 0 || uffd < 0)
		die("userfaultfd");
	struct uffdio_api api = { .api = UFFD_API };
	if (ioctl(uffd, UFFDIO_API, &api))
		die("UFFDIO_API");
	fault_src = mmap(NULL, page_size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
			 -1, 0);
	fault_area = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	if (fault_src == MAP_FAILED || fault_area == MAP_FAILED)
		die("mmap");
	/* mlockall's MCL_FUTURE filled them: unlock and empty them again */
	if (munlock(fault_area, len) || madvise(fault_area, len, MADV_DONTNEED))
		die("munlock");
	struct uffdio_register reg = {
		.range = { .start = (unsigned long)fault_area, .len = len },
		.mode = UFFDIO_REGISTER_MODE_MISSING,
	};
	if (ioctl(uffd, UFFDIO_REGISTER, &reg))
		die("UFFDIO_REGISTER");
}

int main(int argc, char **argv)
{
	struct rt_args ra = { 1 * MS, 100000, 0, 0 };
	struct other_args oa = { "why-hog", 60, 100 * MS, 3 * MS, 0 };
	pthread_mutexattr_t ma;
	pthread_t a, b;
	const char *mode;
	pthread_attr_t attr;
	cpu_set_t set;
	int alone;

	if (argc != 4 && argc != 5) {
		fprintf(stderr, "usage: why_late hog|mutex|pi|preempt|alone|machine|migrate|fault CPU SECONDS [SCALE]\n");
		return 1;
	}
	mode = argv[1];
	cpu = atoi(argv[2]);
	end_ns = now_ns() + (int64_t)(atof(argv[3]) * 1e9);
	if (mlockall(MCL_CURRENT | MCL_FUTURE))
		die("mlockall");
	pthread_mutexattr_init(&ma);
	if (!strcmp(mode, "mutex") || !strcmp(mode, "pi")) {
		if (!strcmp(mode, "pi"))
			pthread_mutexattr_setprotocol(&ma, PTHREAD_PRIO_INHERIT);
		ra.use_lock = 1;
		oa = (struct other_args){ "why-owner", 10, 50 * MS, 2 * MS, 1 };
	} else if (!strcmp(mode, "preempt")) {
		ra = (struct rt_args){ 5 * MS, 3 * MS, 0, 0 };
		oa = (struct other_args){ "why-preemptor", 70, 50 * MS, 4 * MS, 0 };
	} else if (!strcmp(mode, "migrate")) {
		ra = (struct rt_args){ 20 * MS, 200000, 0, 0 };
		migrate_every = 10;
	} else if (!strcmp(mode, "machine")) {
		ra = (struct rt_args){ 20 * MS, 100000, 0, 0 };
	} else if (!strcmp(mode, "fault")) {
		ra.hold = 2 * MS;
		oa = (struct other_args){ "why-uffd", 10, 0, 2 * MS, 0 };
		fault_every = 100;
		fault_setup();
	} else if (strcmp(mode, "hog") && strcmp(mode, "alone")) {
		fprintf(stderr, "why_late: %s: unknown mode\n", mode);
		return 1;
	}
	/* SCALE: every time of the mode that many times longer (an emulated guest) */
	if (argc == 5 && atoi(argv[4]) > 1) {
		ra.period *= atoi(argv[4]);
		ra.work *= atoi(argv[4]);
		oa.every *= atoi(argv[4]);
		oa.burn *= atoi(argv[4]);
		ra.hold *= atoi(argv[4]);
	}
	pthread_mutex_init(&lock, &ma);
	srand(1);
	/* born on their CPU: no migration of their start-up counts as one of the test's */
	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	pthread_attr_init(&attr);
	if (pthread_attr_setaffinity_np(&attr, sizeof(set), &set))
		die("affinity");
	if (pthread_create(&a, &attr, periodic, &ra))
		die("pthread_create");
	alone = !strcmp(mode, "alone") || !strcmp(mode, "machine") || migrate_every;
	if (!alone && pthread_create(&b, &attr, fault_every ? resolver : other, &oa))
		die("pthread_create");
	pthread_join(a, NULL);
	__atomic_store_n(&resolver_stop, 1, __ATOMIC_RELEASE);
	if (!alone)
		pthread_join(b, NULL);
	printf("{\"pid\": %d, \"rt_tid\": %d, \"other_tid\": %d, \"other\": \"%s\", \"prio\": %d, "
	       "\"bursts\": %ld, \"burst_max_ns\": %lld, \"cycles\": %ld, \"misses\": %ld, ",
	       getpid(), rt_tid, other_tid, oa.name, oa.prio, bursts, (long long)burst_max, cycles, misses);
	printf("\"burst_span_max_ns\": %lld, ", (long long)burst_span_max);
	printf("\"slept_misses\": %ld, \"backlogs\": %ld, \"late_ns\": [", slept_misses, backlogs);
	for (long i = 0; i < nlate; i++)
		printf("%s%lld", i ? ", " : "", (long long)late_ns[i]);
	printf("], \"faults\": %ld, \"futex_waits\": %ld, \"moves\": [", faults, futex_waits);
	for (long i = 0; i < nmoves; i++)
		printf("%s[%d, %d]", i ? ", " : "", moves[i][0], moves[i][1]);
	printf("]}\n");
	return 0;
}
