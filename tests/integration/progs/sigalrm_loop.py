# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""sigalrm_loop.py - a real control loop for test_real_programs.py: a
SCHED_FIFO Python loop that sleeps to absolute deadlines (time.sleep of
the time left, which CPython 3.11 turns into clock_nanosleep(TIMER_ABSTIME)
and retries after EINTR with the same deadline), with a SIGALRM handler
every 5 ms. It writes what it did as JSON.

usage: sigalrm_loop.py NAME PERIOD_US CYCLES OUT.json
"""
import ctypes
import json
import os
import resource
import signal
import sys
import time

PR_SET_NAME = 15
PREEMPT_LOG = 100   # cycles whose preemptions are logged


def main():
    name, period_us, cycles, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    # the tracer follows the thread by this name from here on
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_NAME, name.encode(), 0, 0, 0)
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
    except PermissionError:
        print("sigalrm_loop: SCHED_FIFO refused, running SCHED_OTHER", file=sys.stderr)
    alarms = [0]

    def on_alarm(_sig, _frame):
        alarms[0] += 1

    signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, 0.005, 0.005)
    period = period_us / 1e6
    wake, late = [], []
    # involuntary switches (preemptions) read at each wake-up, for the first
    # cycles: a preemption before a sleep shifts the release that time.sleep
    # requests (its own clock read + the time left), which the tracer uses to
    # learn the period
    nivcsw = [resource.getrusage(resource.RUSAGE_THREAD).ru_nivcsw]
    deadline = time.monotonic() + period
    time.sleep(period)                      # release of cycle 1
    for i in range(1, cycles + 1):
        wake.append(time.monotonic())
        if i <= PREEMPT_LOG:
            nivcsw.append(resource.getrusage(resource.RUSAGE_THREAD).ru_nivcsw)
        x = 0
        for k in range(200):                # a little work
            x += k * k
        deadline += period
        left = deadline - time.monotonic()
        if left <= 0:
            late.append(i)
        time.sleep(max(left, 0))
    signal.setitimer(signal.ITIMER_REAL, 0, 0)
    with open(out, "w") as f:
        json.dump({"cycles": cycles, "tid": os.getpid(), "alarms": alarms[0],
                   "mean_period_ns": (wake[-1] - wake[0]) / (len(wake) - 1) * 1e9,
                   "late": late,
                   # preempted[j]: the sleep that released cycle j+1 was
                   # requested after a preemption (or one came after the
                   # wake-up: the log cannot tell, so it says preempted)
                   "preempted": [b != a for a, b in zip(nivcsw, nivcsw[1:])]}, f)


if __name__ == "__main__":
    main()
