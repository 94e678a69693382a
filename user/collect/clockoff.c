// SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
/* clockoff.c - a clock's offset to CLOCK_MONOTONIC, read between two monotonic reads */
#include <stddef.h>
#include "collect/clockoff.h"

static __s64 bracket_width(const struct clock_bracket *b)
{
	return b->mono1 - b->mono0;
}

struct clock_offset clockoff_pick(const struct clock_bracket *b, int n)
{
	const struct clock_bracket *best = b;
	int i;

	for (i = 1; i < n; i++)
		if (bracket_width(&b[i]) < bracket_width(best))
			best = &b[i];
	return (struct clock_offset){
		.off = best->clk - (best->mono0 + bracket_width(best) / 2),
		.err = (bracket_width(best) + 1) / 2,
	};
}

static __s64 ts_ns(const struct timespec *ts)
{
	return ts->tv_sec * 1000000000LL + ts->tv_nsec;
}

struct clock_offset clockoff_read(clockid_t clk)
{
	struct clock_bracket b[CLOCKOFF_TRIES];
	struct timespec m0, a, m1;
	int n = 0;

	while (n < CLOCKOFF_TRIES) {
		clock_gettime(CLOCK_MONOTONIC, &m0);
		if (clock_gettime(clk, &a))
			return (struct clock_offset){ 0, -1 };
		clock_gettime(CLOCK_MONOTONIC, &m1);
		b[n] = (struct clock_bracket){ ts_ns(&m0), ts_ns(&a), ts_ns(&m1) };
		if (bracket_width(&b[n++]) <= CLOCKOFF_WINDOW_NS)
			break;
	}
	return clockoff_pick(b, n);
}

struct clock_offset clockoff_keep(struct clock_offset held, struct clock_offset now,
				  bool stepped)
{
	__s64 d = now.off - held.off;

	if (now.err < 0)
		return held;
	if (stepped || d > held.err + now.err || -d > held.err + now.err)
		return now;
	return now.err < held.err ? now : held;
}
