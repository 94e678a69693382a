/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * stats.h - per-metric statistics updates, shared by BPF and userspace.
 *
 * The kernel updates these once per finished cycle; the host unit tests
 * run the very same code.
 */
#ifndef RTSUP_STATS_H
#define RTSUP_STATS_H

#include "rtsup.h"
#include "hist.h"

/*
 * ewma_update - exponentially weighted mean, weight w / RTSUP_EWMA_ONE for
 * the new value (the seed's "weighted mean": recent values count more).
 * Kept in fixed point so the kernel needs no floats.
 */
RTSUP_INLINE __s64 ewma_update(__s64 ewma, __u64 count, __u64 v, __u32 w)
{
	__s64 x = (__s64)(v << RTSUP_EWMA_SHIFT);
	__s64 step;

	if (count == 0)
		return x;
	/*
	 * arithmetic shift of a signed product; w <= 1024 keeps it in range
	 * for any real time. The difference and the product are taken
	 * unsigned: a value near 2^53 ns (a damaged trace) wraps as the CPU
	 * does instead of being undefined (UBSan, fuzz_record)
	 */
	step = (__s64)(((__u64)x - (__u64)ewma) * w) >> 10;
	return (__s64)((__u64)ewma + (__u64)step);
}

/*
 * metric_banks_range - the buckets between the lowest and highest value of
 * both interval banks of s ([HIST_BUCKETS, -1] when both are empty): where
 * the values since the collector's last read went (rtsup.h, "Interval
 * windows"). Userspace only: the collector's short copies and the model.
 */
#ifndef __bpf__
static inline void metric_banks_range(const struct rtsup_metric_stats *s, int *lo, int *hi)
{
	int i, a, b;

	*lo = HIST_BUCKETS;
	*hi = -1;
	for (i = 0; i < 2; i++) {
		if (s->win[i].min > s->win[i].max)
			continue;	/* empty (minmax_reset) */
		a = (int)hist_bucket(s->win[i].min);
		b = (int)hist_bucket(s->win[i].max);
		if (a < *lo)
			*lo = a;
		if (b > *hi)
			*hi = b;
	}
}
#endif

/* minmax_reset - empty an interval bank */
RTSUP_INLINE void minmax_reset(struct rtsup_minmax *mm)
{
	mm->min = ~0ULL;
	mm->max = 0;
}

/* metric_init - empty statistics */
RTSUP_INLINE void metric_init(struct rtsup_metric_stats *s)
{
	__builtin_memset(s, 0, sizeof(*s));	/* host only: BPF copies a zero entry */
	s->min = ~0ULL;
	minmax_reset(&s->win[0]);
	minmax_reset(&s->win[1]);
}

/* metric_add - account one value; epoch selects the interval bank */
RTSUP_SUBPROG void metric_add(struct rtsup_metric_stats *s, __u64 v, __u32 w,
			     __u32 epoch)
{
	struct rtsup_minmax *mm = &s->win[RTSUP_BANK(epoch)];
	__u32 b = hist_bucket(v);

	/* entries start all-zero: the first value sets min */
	if (!s->count || v < s->min)
		s->min = v;
	s->ewma = ewma_update(s->ewma, s->count, v, w);
	s->count++;
	s->sum += v;
	if (v > s->max)
		s->max = v;
	if (v < mm->min)
		mm->min = v;
	if (v > mm->max)
		mm->max = v;
	if (b < HIST_BUCKETS)	/* always true; bounds the verifier */
		s->hist[b]++;
}

/* thread_account_cycle - fold one finished cycle into a thread's stats */
RTSUP_INLINE void thread_account_cycle(struct rtsup_thread *t,
				       const struct rtsup_cycle *c, __u32 w,
				       __u32 epoch)
{
	t->cycles++;
	t->last_cycle = c->start;
	if (c->flags & RTSUP_CF_MISS)
		t->misses++;
	if (c->flags & RTSUP_CF_OVERRUN)
		t->overruns++;
	if (c->flags & RTSUP_CF_HAS_PERIOD)
		metric_add(&t->m[RTSUP_M_PERIOD], c->period, w, epoch);
	metric_add(&t->m[RTSUP_M_EXEC], c->exec, w, epoch);
	metric_add(&t->m[RTSUP_M_CPU], c->cpu, w, epoch);
	if (c->flags & RTSUP_CF_HAS_LATENCY)
		metric_add(&t->m[RTSUP_M_LATENCY], c->latency, w, epoch);
	/* unsafe events count once their cycle is whole (not in an exit's teardown) */
	t->syscalls += c->syscalls;
	t->minflt += c->minflt;
	t->majflt += c->majflt;
	t->unsafe[RTSUP_U_SYSCALL] += c->unsafe_sys;
	t->unsafe[RTSUP_U_MINFLT] += c->minflt;
	t->unsafe[RTSUP_U_MAJFLT] += c->majflt;
	t->unsafe[RTSUP_U_BLOCK] += c->blocks;
	t->unsafe[RTSUP_U_MIGRATE] += c->migrations;
}

#endif /* RTSUP_STATS_H */
