/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * hist.h - log-linear histogram buckets, shared by BPF and userspace.
 *
 * Plain C with no loops the verifier could not bound: compiled into the BPF
 * object and into the host unit tests.
 */
#ifndef RTSUP_HIST_H
#define RTSUP_HIST_H

#include "rtsup.h"

/*
 * A function the BPF side keeps as a subprogram: its branches are verified
 * once per call instead of multiplying with every branch around the call.
 */
#ifndef RTSUP_SUBPROG
#define RTSUP_SUBPROG static inline
#endif
/*
 * One the BPF side keeps global: verified once for the whole program, its
 * callers see a number they bound themselves (6.1's verifier walked
 * hist_log2's branches anew at every call: 20 000 of sys_enter's 37 744
 * instructions).
 */
#ifndef RTSUP_GLOBAL
#define RTSUP_GLOBAL static inline
#endif

/* hist_log2 - index of the highest set bit of v (v > 0), branch-light */
RTSUP_INLINE __u32 hist_log2(__u64 v)
{
	__u32 r = 0, s;

	s = (v > 0xFFFFFFFFULL) << 5; v >>= s; r |= s;
	s = (v > 0xFFFF) << 4; v >>= s; r |= s;
	s = (v > 0xFF) << 3; v >>= s; r |= s;
	s = (v > 0xF) << 2; v >>= s; r |= s;
	s = (v > 0x3) << 1; v >>= s; r |= s;
	r |= (__u32)(v >> 1);
	return r;
}

/* hist_bucket - bucket index of value v */
RTSUP_GLOBAL __u32 hist_bucket(__u64 v)
{
	__u32 e, sub;

	if (v < HIST_SUB)
		return (__u32)v;
	e = hist_log2(v);
	if (e > HIST_MAX_EXP)
		return HIST_BUCKETS - 1;
	sub = (__u32)(v >> (e - HIST_SUB_BITS)) & (HIST_SUB - 1);
	return (e - HIST_SUB_BITS + 1) * HIST_SUB + sub;
}

/* hist_bucket_low - smallest value that falls into bucket b */
RTSUP_INLINE __u64 hist_bucket_low(__u32 b)
{
	__u32 e, sub;

	if (b < HIST_SUB)
		return b;
	e = b / HIST_SUB + HIST_SUB_BITS - 1;
	sub = b % HIST_SUB;
	return ((__u64)(HIST_SUB + sub)) << (e - HIST_SUB_BITS);
}

/* hist_bucket_high - largest value that falls into bucket b */
RTSUP_INLINE __u64 hist_bucket_high(__u32 b)
{
	if (b >= HIST_BUCKETS - 1)
		return ~0ULL;
	return hist_bucket_low(b + 1) - 1;
}

#endif /* RTSUP_HIST_H */
