// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/*
 * synth-trace - write a recorded trace (user/sinks/record.h) of many
 * periodic threads, for `rtsup-trace replay` to measure what the model,
 * the checks and the outputs cost per thread per interval without loading
 * BPF (scripts/bench, "userspace, replayed"). Every number is made up but
 * of a real loop's shape: 10 Hz, 50 us of work, 20-80 us of latency.
 *
 *   rtsup-synth-trace OUT THREADS PARKED SECONDS
 *
 * THREADS threads; PARKED of them (SCHED_OTHER) run one cycle in the first
 * interval and then none (a robot's many waiting threads); the others
 * (SCHED_FIFO) run 10 cycles a second. Of those, every 10th misses a
 * deadline every 10 s (preempted by a named thread: a cause), every 13th
 * makes an RT-unsafe mmap every 10 s, and the last one exits half-way: the
 * outputs' rarer parts (messages, causes, events, exits) are written too.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sinks/record.h"

#define HZ	 10
#define PERIOD	 (1000000000ULL / HZ)
#define T0	 1000000000000ULL	/* the recording's CLOCK_MONOTONIC start */

/* rnd - xorshift: the same trace on every run */
static __u64 rnd(void)
{
	static __u64 x = 88172645463325252ULL;

	x ^= x << 13;
	x ^= x >> 7;
	x ^= x << 17;
	return x;
}

static void put(struct rec_writer *w, enum rec_type type, const void *p, size_t len)
{
	char err[512];

	if (rec_write(w, type, p, len, err, sizeof(err))) {
		fprintf(stderr, "synth-trace: %s\n", err);
		exit(1);
	}
}

/* event - a rare event of thread t at ts; a miss is preempted by "noisy" */
static void event(struct rec_writer *w, const struct rec_thread *t, __u32 type, __u64 ts,
		  __u64 arg, __u64 arg2)
{
	struct rtsup_event e;

	memset(&e, 0, sizeof(e));
	e.ts = ts;
	e.type = type;
	e.tid = t->tid;
	e.tgid = t->tgid;
	e.arg = arg;
	e.arg2 = arg2;
	memcpy(e.comm, t->comm, sizeof(e.comm));
	if (type == RTSUP_EV_MISS) {
		e.cause.kind = RTSUP_CAUSE_PREEMPT;
		e.cause.ns = arg + 200000;
		e.cause.preempt_ns = e.cause.ns;
		e.cause.preempts = 1;
		e.cause.who.tid = 77;
		e.cause.who.tgid = 77;
		e.cause.who.policy = 1;
		e.cause.who.prio = 90;
		snprintf(e.cause.who.comm, sizeof(e.cause.who.comm), "noisy");
	}
	put(w, REC_EVENT, &e, sizeof(e));
}

/* cycle - one finished cycle of thread 'tid' released at 'start' */
static void cycle(struct rec_writer *w, __u32 tid, __u32 tgid, __u64 start, bool first,
		  bool miss)
{
	struct rec_cycle c;

	memset(&c, 0, sizeof(c));
	c.r.tid = tid;
	c.r.tgid = tgid;
	c.r.c.start = start;
	c.r.c.nominal = PERIOD;
	c.r.c.period = first ? 0 : PERIOD - 40000 + rnd() % 80000;
	c.r.c.exec = 40000 + rnd() % 20000;
	c.r.c.cpu = c.r.c.exec;
	c.r.c.latency = 20000 + rnd() % 60000;
	c.r.c.syscalls = 2;
	c.r.c.flags = RTSUP_CF_HAS_LATENCY | (first ? 0 : RTSUP_CF_HAS_PERIOD) |
		      (miss ? RTSUP_CF_MISS : 0);
	if (miss)
		c.r.c.latency += 300000;
	c.end = start + c.r.c.exec;
	put(w, REC_CYCLE, &c, sizeof(c));
}

int main(int argc, char **argv)
{
	struct rec_header h = { .interval_s = 1.0, .ewma_w = 64 };
	struct rec_interval mark;
	struct rec_writer *w;
	struct rec_thread *t;
	int n, parked, secs, s, i, k;
	__u32 tgid = 4000;
	char err[512];

	if (argc != 5 || (n = atoi(argv[2])) < 1 || (parked = atoi(argv[3])) < 0 ||
	    parked > n || (secs = atoi(argv[4])) < 1) {
		fprintf(stderr, "usage: rtsup-synth-trace OUT THREADS PARKED SECONDS\n");
		return 64;
	}
	snprintf(h.kernel, sizeof(h.kernel), "synthetic");
	snprintf(h.args, sizeof(h.args), "rtsup-synth-trace %d %d %d", n, parked, secs);
	h.start_mono_ns = T0;
	h.start_real_ns = T0;
	if (rec_create(&w, argv[1], &h, err, sizeof(err))) {
		fprintf(stderr, "synth-trace: %s\n", err);
		return 1;
	}
	t = calloc((size_t)n, sizeof(*t));
	if (!t)
		return 1;
	for (i = 0; i < n; i++) {
		t[i].tid = tgid + 1 + (__u32)i;
		t[i].tgid = tgid;
		snprintf(t[i].comm, sizeof(t[i].comm), "%s%d", i < parked ? "park" : "ctl", i);
		snprintf(t[i].pcomm, sizeof(t[i].pcomm), "synth");
		/* the parked ones SCHED_OTHER: a FIFO thread with a period, parked, is starving */
		t[i].policy = i < parked ? 0 : 1;
		t[i].prio = i < parked ? 0 : 10;
		t[i].first_seen = T0 + 1000;
		t[i].mode = RTSUP_MODE_DELIM;
		t[i].nominal = PERIOD;
	}
	for (s = 0; s < secs; s++) {
		__u64 base = T0 + (__u64)s * 1000000000ULL;

		for (i = 0; i < n; i++) {
			/* a phase of its own, so the cycles spread over the second */
			__u64 phase = (__u64)i * 997 % PERIOD;
			int cycles = i < parked ? (s == 0) : HZ;

			bool active = i >= parked, exits = i == n - 1 && s == secs / 2;

			if (t[i].exited)
				cycles = 0;
			for (k = 0; k < cycles; k++) {
				__u64 start = base + phase + (__u64)k * PERIOD;
				bool miss = active && i % 10 == 0 && k == 5 && s % 10 == 1;

				cycle(w, t[i].tid, tgid, start, s == 0 && k == 0, miss);
				if (miss)
					event(w, &t[i], RTSUP_EV_MISS, start, 300000, 0);
				if (active && i % 13 == 0 && k == 3 && s % 10 == 2) {
					t[i].unsafe[RTSUP_U_SYSCALL]++;
					t[i].nsys = 1;
					t[i].sys[0].nr = 9;	/* mmap on x86-64 */
					t[i].sys[0].total++;
					event(w, &t[i], RTSUP_EV_UNSAFE, start + 1000,
					      RTSUP_U_SYSCALL, 9);
				}
				t[i].vol_cs++;
				t[i].syscalls += 2;
				t[i].last_cycle = start;
			}
			if (exits) {
				t[i].exited = base + 999000000ULL;
				event(w, &t[i], RTSUP_EV_EXIT, t[i].exited, 0, 0);
			}
			put(w, REC_THREAD, &t[i], sizeof(t[i]));
		}
		memset(&mark, 0, sizeof(mark));
		mark.mono_ns = base + 1000000000ULL;
		mark.overhead_pct = -1;
		put(w, s == secs - 1 ? REC_END : REC_INTERVAL, &mark, sizeof(mark));
	}
	free(t);
	if (rec_close(w, err, sizeof(err))) {
		fprintf(stderr, "synth-trace: %s\n", err);
		return 1;
	}
	return 0;
}
