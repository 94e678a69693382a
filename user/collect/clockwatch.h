/* SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause */
/*
 * clockwatch.h - a step of the wall clock (date -s, NTP setting the time
 * at boot, a new TAI offset) seen when it happens, not at the next
 * interval: a CLOCK_REALTIME timerfd armed with TFD_TIMER_CANCEL_ON_SET,
 * which the kernel cancels at every such step. The kernel side converts
 * absolute sleeps on CLOCK_REALTIME and TAI with the offsets userspace
 * writes (collector.c, update_clocks): a step must reach them at once.
 */
#ifndef RTSUP_CLOCKWATCH_H
#define RTSUP_CLOCKWATCH_H

/* clockwatch_open - the armed timerfd (non-blocking), or -errno */
int clockwatch_open(void);
/* clockwatch_stepped - 1 when the clock was stepped since the last call (armed again), 0 if not, -errno */
int clockwatch_stepped(int fd);

#endif
