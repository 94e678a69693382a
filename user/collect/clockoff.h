/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * clockoff.h - a clock's offset to CLOCK_MONOTONIC at one instant. The
 * kernel side converts absolute sleeps with these offsets (collector.c,
 * update_clocks) and a step of the wall clock is told as their change.
 * Two reads one after the other are ms apart when the tool is preempted
 * between them (a TCG guest: a step of +5 s said as +5.000073 s), so the
 * clock is read between two monotonic reads, and a bracket wider than
 * CLOCKOFF_WINDOW_NS is read again.
 */
#ifndef RTSUP_CLOCKOFF_H
#define RTSUP_CLOCKOFF_H

#include <stdbool.h>
#include <time.h>
#include <linux/types.h>

/* a bracket this narrow puts the offset within half of it */
#define CLOCKOFF_WINDOW_NS 20000
/* brackets read at most before the narrowest is taken */
#define CLOCKOFF_TRIES 64

/* one reading: the clock between two CLOCK_MONOTONIC reads, ns */
struct clock_bracket {
	__s64 mono0, clk, mono1;
};

/* an offset and its error bound, ns; err < 0: the clock could not be read */
struct clock_offset {
	__s64 off, err;
};

/*
 * clockoff_pick - the offset of the narrowest of n brackets (n >= 1):
 * the clock less the midpoint of its monotonic reads, within half that
 * bracket's width.
 */
struct clock_offset clockoff_pick(const struct clock_bracket *b, int n);
/* clockoff_read - clk's offset to CLOCK_MONOTONIC (clockoff_pick's terms); {0, -1} if clk cannot be read */
struct clock_offset clockoff_read(clockid_t clk);
/*
 * clockoff_keep - the offset to hold after reading 'now': the offsets of
 * one clock change only when it is stepped, so two readings within their
 * errors are the same offset and the narrower is kept. A change that
 * reads as a step reaches the kernel side (which moves pending releases
 * by it, cycle_clock_at_exit); the reads' own noise does not. 'stepped'
 * (the clock watch saw a step; the first reading) takes 'now' whole; a
 * clock that could not be read leaves 'held'.
 */
struct clock_offset clockoff_keep(struct clock_offset held, struct clock_offset now,
				  bool stepped);

#endif
