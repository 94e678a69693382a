// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * rtsup-noise - measure a machine's timing noise, or make some.
 *
 *   rtsup-noise gauge [-d TIME] [-P US]
 *	one SCHED_FIFO 90 thread per CPU sleeps to absolute releases every
 *	P us (1000) for TIME (2 s) and prints one JSON line: the wakeup
 *	latency max, p99 and p50 over all CPUs, in us.
 *   rtsup-noise inject [-d TIME] [-b BURN] [-e EVERY]
 *	one SCHED_FIFO 99 thread per CPU, pinned, burns BURN (3 ms) every
 *	EVERY (30 ms, randomised by +-25 % so that it never locks to the
 *	phase of a 1 ms loop) until TIME (0: until SIGTERM or SIGINT).
 *
 * What the tests use to say how noisy a run was, and to make noise that is
 * part of the test rather than an accident of the machine.
 */
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#define MAX_CPUS 256

static volatile sig_atomic_t stop;

struct cpu_thread {
	pthread_t pt;
	int cpu;
	int64_t *lat;		/* gauge: one latency per cycle, ns */
	long n, cap;
	long bursts;		/* inject: bursts done */
};

static struct {
	int64_t duration, period, burn, every;
	int prio;
} opt = { 2000000000LL, 1000000, 3000000, 30000000, 0 };

static void die(const char *what, const char *why)
{
	fprintf(stderr, "rtsup-noise: %s: %s\n", what, why);
	exit(1);
}

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static struct timespec ns_ts(int64_t ns)
{
	struct timespec ts = { ns / 1000000000LL, ns % 1000000000LL };

	return ts;
}

/* parse_time - "2s", "30ms", "500us", "100ns", bare number = us */
static int64_t parse_time(const char *s, const char *what)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || v < 0)
		die(what, "not a duration");
	if (!strcmp(end, "s"))
		return v * 1e9;
	if (!strcmp(end, "ms"))
		return v * 1e6;
	if (!strcmp(end, "us") || !*end)
		return v * 1e3;
	if (!strcmp(end, "ns"))
		return v;
	die(what, "unit must be s, ms, us or ns");
	return 0;
}

/* rt_self - pin the calling thread to one CPU at SCHED_FIFO prio */
static void rt_self(int cpu, int prio)
{
	struct sched_param sp = { .sched_priority = prio };
	cpu_set_t set;

	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
	if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp))
		die("SCHED_FIFO", "not allowed (run as root)");
}

static void *gauge_main(void *arg)
{
	struct cpu_thread *t = arg;
	int64_t next, end, now;
	struct timespec ts;

	rt_self(t->cpu, 90);
	next = now_ns() + opt.period;
	end = next + opt.duration;
	while (next < end && !stop) {
		ts = ns_ts(next);
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		now = now_ns();
		if (t->n < t->cap)
			t->lat[t->n++] = now > next ? now - next : 0;
		next += opt.period;
		while (next <= now)	/* a wakeup later than a period: skip */
			next += opt.period;
	}
	return NULL;
}

static void *inject_main(void *arg)
{
	struct cpu_thread *t = arg;
	int64_t next, end, spin;
	unsigned int seed = t->cpu * 7919 + 1;
	struct timespec ts;

	rt_self(t->cpu, 99);
	next = now_ns() + opt.every / 2 + rand_r(&seed) % (opt.every / 2 + 1);
	end = opt.duration ? now_ns() + opt.duration : INT64_MAX;
	while (!stop && next < end) {
		ts = ns_ts(next);
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		spin = now_ns();
		while (now_ns() - spin < opt.burn && !stop)
			;
		t->bursts++;
		/* the next burst in EVERY +- 25 % */
		next += opt.every * 3 / 4 + rand_r(&seed) % (opt.every / 2 + 1);
	}
	return NULL;
}

static int cmp64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;

	return x < y ? -1 : x > y;
}

static void on_signal(int sig)
{
	stop = 1;
}

static void usage(void)
{
	fputs("usage: rtsup-noise gauge [-d TIME] [-P PERIOD]\n"
	      "       rtsup-noise inject [-d TIME] [-b BURN] [-e EVERY]\n", stderr);
	exit(1);
}

int main(int argc, char **argv)
{
	static struct cpu_thread th[MAX_CPUS];
	int ncpu = sysconf(_SC_NPROCESSORS_ONLN), i, c;
	bool gauge;
	int64_t *all;
	long n = 0;

	if (argc < 2)
		usage();
	gauge = !strcmp(argv[1], "gauge");
	if (!gauge && strcmp(argv[1], "inject"))
		usage();
	if (!gauge)
		opt.duration = 0;
	optind = 2;
	while ((c = getopt(argc, argv, "d:P:b:e:")) != -1) {
		switch (c) {
		case 'd': opt.duration = parse_time(optarg, "-d"); break;
		case 'P': opt.period = parse_time(optarg, "-P"); break;
		case 'b': opt.burn = parse_time(optarg, "-b"); break;
		case 'e': opt.every = parse_time(optarg, "-e"); break;
		default: usage();
		}
	}
	if (opt.period <= 0 || opt.every <= opt.burn)
		die("options", "the period must be > 0 and EVERY longer than BURN");
	if (ncpu > MAX_CPUS)
		ncpu = MAX_CPUS;
	signal(SIGTERM, on_signal);
	signal(SIGINT, on_signal);
	mlockall(MCL_CURRENT | MCL_FUTURE);
	for (i = 0; i < ncpu; i++) {
		th[i].cpu = i;
		if (gauge) {
			th[i].cap = opt.duration / opt.period + 2;
			th[i].lat = calloc(th[i].cap, sizeof(*th[i].lat));
			if (!th[i].lat)
				die("memory", "out of memory");
		}
		if (pthread_create(&th[i].pt, NULL, gauge ? gauge_main : inject_main, &th[i]))
			die("pthread_create", strerror(errno));
	}
	for (i = 0; i < ncpu; i++)
		pthread_join(th[i].pt, NULL);
	if (!gauge) {
		long bursts = 0;

		for (i = 0; i < ncpu; i++)
			bursts += th[i].bursts;
		printf("{\"bursts\": %ld, \"cpus\": %d, \"burn_us\": %.0f, \"every_us\": %.0f}\n",
		       bursts, ncpu, opt.burn / 1e3, opt.every / 1e3);
		return 0;
	}
	for (i = 0; i < ncpu; i++)
		n += th[i].n;
	all = calloc(n + 1, sizeof(*all));
	if (!all)
		die("memory", "out of memory");
	n = 0;
	for (i = 0; i < ncpu; i++) {
		memcpy(all + n, th[i].lat, th[i].n * sizeof(*all));
		n += th[i].n;
	}
	qsort(all, n, sizeof(*all), cmp64);
	if (!n)
		die("gauge", "no sample");
	printf("{\"samples\": %ld, \"cpus\": %d, \"period_us\": %.0f, \"p50_us\": %.1f, "
	       "\"p99_us\": %.1f, \"max_us\": %.1f}\n", n, ncpu, opt.period / 1e3,
	       all[n / 2] / 1e3, all[(long)(n * 0.99)] / 1e3, all[n - 1] / 1e3);
	free(all);
	return 0;
}
