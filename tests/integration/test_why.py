# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""Why it was late (issue 14): a small program (progs/why_late.c) makes its
periodic thread why-rt late on purpose, with a culprit it names and counts
itself (a hog, a lock owner, a preemptor on why-rt's CPU); every deadline
miss rtsup-trace reports must carry that culprit. The machine itself as the
culprit (a hypervisor holding the CPU) is made inside a vm-test guest, whose
host stops it on request (test_guest.py runs that test there).
"""
import json
import os
import re
import subprocess
import time
from pathlib import Path

import pytest

from conftest import BUILD, EMULATED, NOISE, Trace, block_events

WHY_LATE = BUILD / "progs" / "why_late"
# the last CPU: the tests' own Python and rtsup-trace mostly run elsewhere
CPU = str(os.cpu_count() - 1)
MS = 1000000

host_only = pytest.mark.skipif(EMULATED, reason="host only: the program's timing")
# inside a vm-test guest: its control share, through which it asks its host
# to hold it (docs/vm-test.md, "Hiccups")
VM_CTL = Path("/run/vm-test")
IN_VM = (VM_CTL / "started").exists()


def cpu_steal_ns(cpu):
    """What the hypervisor stole from one CPU since boot (/proc/stat, 10 ms units)."""
    for line in Path("/proc/stat").read_text().splitlines():
        f = line.split()
        if f[0] == "cpu" + cpu:
            return int(f[8]) * 10 * MS
    return 0


def run_why(mode, seconds=3, args=(), during=None, scale=1, summary_out=None):
    """Trace why_late MODE; return (its truth, why-rt's summary, the intervals).
    during() runs while the program does; scale stretches the mode's times;
    the whole summary is appended to summary_out when given."""
    stolen = cpu_steal_ns(CPU)
    tr = Trace(["--comm", "why_late"] + list(args))
    # rtsup-trace's own reads of its maps hold a CPU for up to ~1 ms on a
    # kernel without full preemption: a cost it names as its own (the
    # 'self' culprit), kept off the CPU under test here
    if os.cpu_count() > 1:
        os.sched_setaffinity(tr.proc.pid, {0})
    try:
        p = subprocess.Popen([str(WHY_LATE), mode, CPU, str(seconds), str(scale)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            if during:
                during()
            out, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        assert p.returncode == 0, err
        intervals, summary, _ = tr.stop()
    finally:
        if tr.proc.poll() is None:
            tr.proc.kill()
    truth = json.loads(out)
    if summary_out is not None:
        summary_out.append(summary)
    stolen = cpu_steal_ns(CPU) - stolen
    rt = [t for t in summary["threads"] if t["tid"] == truth["rt_tid"]]
    assert len(rt) == 1, summary["threads"]
    # the misses named for the hypervisor's steal (a KVM guest's steal_time,
    # read at why-rt's switches) took no more than the kernel counted stolen
    # from its CPU over the run: /proc/stat counts it in 10 ms units, so each
    # of the two reads may be short by one
    named = sum(g["total_ns"] for g in rt[0]["total"]["causes"] if g["kind"] == "steal")
    assert named <= stolen + 20 * MS, (named, stolen, rt[0]["total"]["causes"])
    return truth, rt[0], intervals


def groups(rt):
    """why-rt's misses by cause over the run: every miss, none folded."""
    return rt["total"]["causes"]


def by_culprit(gs, tid, kinds=None):
    return [g for g in gs if g["who"] and g["who"]["tid"] == tid and
            (kinds is None or g["kind"] in kinds)]


def elsewhere(g, truth, also=()):
    """Is this group of misses the machine's or another program's? The host is
    shared: other tests' tracers, generators, noise injectors and VMs run on
    it, and a hypervisor steals time. Those misses are named (a task outside
    why_late and 'also', or 'timer' or 'steal': the machine; a backlog or wait
    behind no task follows one of those), not hidden; the test cannot know
    their truth, so they are left out of the shares below (run_why bounds
    the steal by the kernel's own count)."""
    if g["who"]:
        return g["who"]["tgid"] != truth["pid"] and g["who"]["tgid"] not in also
    return g["kind"] in ("timer", "backlog", "wait", "steal")


def count(gs):
    return sum(g["count"] for g in gs)


def check_named(gs, truth, culprit_tid, also=(), every_burst=True):
    """>= 95 % of the misses the test knows the truth of name the culprit; and
    (every_burst: a burst always makes a miss) each of its bursts made one
    miss name it for a wait or a preemption, but those whose cycle had a
    bigger part from elsewhere (a burst of foreign noise in the same cycle
    wins). Returns the culprit's wait/preemption groups."""
    ours = [g for g in gs if not elsewhere(g, truth, also)]
    named = by_culprit(ours, culprit_tid)
    assert count(named) >= 0.95 * count(ours), gs
    held = by_culprit(gs, culprit_tid, ("wait", "preemption"))
    other_held = [g for g in gs if elsewhere(g, truth, also) and g["kind"] != "backlog"]
    if every_burst:
        assert count(held) >= truth["bursts"] - count(other_held), (truth, gs)
    return held


def miss_events(intervals, tid):
    return [e for i in intervals for e in i["events"]
            if e["event"] == "deadline_miss" and e["tid"] == tid]


@host_only
def test_fifo_hog_is_named(bpf):
    """FIFO 60 why-hog burns 3 ms every 100 ms on why-rt's CPU (FIFO 50,
    1 ms period): >= 95 % of the misses name the hog; the rest may be the
    machine's own (a hypervisor's steal on a shared host: those are named
    'steal' or 'timer' and counted apart, not hidden)."""
    truth, rt, intervals = run_why("hog")
    gs = groups(rt)
    misses = sum(g["count"] for g in gs)
    assert misses == rt["total"]["deadline_misses"], gs
    # enough bursts for the shares below to mean something: 27 in 3 s on a
    # quiet machine; 19 on a CI machine whose hypervisor held the hog (FIFO
    # 60) 14 ms inside one 3 ms burst (burst_max_ns)
    assert truth["bursts"] >= 10, truth
    assert misses >= truth["bursts"], (truth, gs)
    hog = by_culprit(gs, truth["other_tid"])
    held = check_named(gs, truth, truth["other_tid"])
    assert all(g["who"]["comm"] == "why-hog" and g["who"]["prio"] == 60 and
               g["who"]["policy"] == "SCHED_FIFO" for g in hog), hog
    # each burst makes why-rt wait (woken inside it) or be preempted (running
    # when it came) for the rest of the burst: at least the burst minus one
    # period (why-rt's release is at most 1 ms after the burst began), less
    # the burst's start and end seen by the program and by the kernel apart
    # (tens of us; 200 us each)
    assert sum(g["total_ns"] for g in held) >= count(held) * (3 * MS - 1 * MS - 200000), \
        (truth, gs)
    # the hog's share of one cycle's wait is one burst at most: from its
    # timer's expiry (it switched in at or after it, a vCPU held by the host
    # before its first clock read included) to its last clock read, + 200 us
    # from that read to its switch-out
    for g in by_culprit(gs, truth["other_tid"], ("wait", "preemption")):
        assert g["max_ns"] <= truth["burst_span_max_ns"] + 200000, (truth, g)
    # each miss event says it in JSON too
    ev = miss_events(intervals, truth["rt_tid"])
    assert ev and all("cause" in e for e in ev)
    # a wait's or preemption's culprit is the longest holder, with its share
    for e in ev:
        c = e["cause"]
        if c["kind"] in ("wait", "preemption") and c["who"]:
            assert c["culprits"][0]["tid"] == c["who"]["tid"], e
            assert c["culprits"][0]["ns"] == c["ns"], e
            assert c["ns"] <= c["parts"]["wait_ns"] + c["parts"]["preempt_ns"], e


@host_only
@pytest.mark.parametrize("mode", ["mutex", "pi"])
def test_priority_inversion_on_plain_mutex(bpf, mode):
    """FIFO 10 why-owner holds a mutex 2 ms every 50 ms; FIFO 50 why-rt takes
    it each cycle: the misses are blocks woken by the owner; with a plain
    mutex (FUTEX_WAIT) an inversion, with a PI mutex (FUTEX_LOCK_PI) none."""
    truth, rt, intervals = run_why(mode)
    gs = groups(rt)
    blocks = by_culprit(gs, truth["other_tid"], ("block",))
    assert blocks, gs
    assert all(g["who"]["comm"] == "why-owner" and g["who"]["prio"] == 10 for g in blocks)
    # each hold blocks why-rt for >= 1 ms (its release is at most 1 ms after
    # the hold began) + 100 us of work: one miss at least per hold, named for
    # the block but when a bigger part of that cycle came from elsewhere
    # (foreign noise on a shared host), and the last hold may end with the run
    other = [g for g in gs if elsewhere(g, truth) and g["kind"] != "backlog"]
    assert count(blocks) >= truth["bursts"] - 1 - count(other), (truth, gs)
    # the flag is the cycle's longest block's: a cycle that waited longer
    # behind foreign noise than it blocked keeps it under another cause
    inversions = [g for g in gs if g["inversion"] and g["kind"] == "block"]
    if mode == "mutex":
        assert inversions and all(g["who"]["tid"] == truth["other_tid"] for g in inversions)
    else:
        assert not [g for g in gs if g["inversion"]], gs
    ev = [e for e in miss_events(intervals, truth["rt_tid"]) if e["cause"]["kind"] == "block"]
    assert ev, intervals
    for e in ev:
        b = e["cause"]["block"]
        assert b["syscall"] == "futex" and b["waker"]["tid"] == truth["other_tid"], e
        # FUTEX_WAIT (0) or FUTEX_WAIT_BITSET (9) for glibc's plain mutex; FUTEX_LOCK_PI (6)
        assert b["futex_op"] in ((0, 9) if mode == "mutex" else (6,)), e
        assert b["inversion"] == (mode == "mutex"), e


@host_only
def test_block_names_its_syscall_and_none_in_a_page_fault(bpf):
    """why-rt blocks in two places (progs/why_late.c, fault): in a page
    fault that userfaultfd holds 2 ms, right after a write that returned,
    and in a 2 ms futex wait. Each block event, and the cause of each miss
    it makes, says futex for the second and no syscall for the first, not
    the write before it (the last syscall entered: what the causes said
    before the syscall was read where the block happens)."""
    truth, rt, intervals = run_why("fault")
    assert truth["faults"] >= 20 and truth["futex_waits"] >= 20, truth
    # both kinds are injected and each one slept: counted exactly
    assert rt["total"]["unsafe"]["block"] == truth["faults"] + truth["futex_waits"], truth
    assert block_events(intervals, truth["rt_tid"]) == {
        None: truth["faults"], "futex": truth["futex_waits"]}, truth
    # each 2 ms block in a 1 ms period makes a miss, named for it (a bigger
    # part from elsewhere, noise on a shared host, may take one)
    ev = [e for e in miss_events(intervals, truth["rt_tid"]) if e["cause"]["kind"] == "block"]
    faults = [e for e in ev if e["cause"]["block"]["waker"]["tid"] == truth["other_tid"]]
    futex = [e for e in ev if e["cause"]["block"]["syscall"] == "futex"]
    assert all(e["cause"]["block"]["syscall"] is None for e in faults), faults
    assert all(e["cause"]["block"]["futex_op"] == 0 for e in futex), futex
    # miss events fold per cause kind: the first and last of each interval's are kept
    assert faults and futex, ev


@host_only
def test_preemptor_is_named(bpf):
    """FIFO 70 why-preemptor burns 4 ms every 50 ms inside why-rt's 3 ms of
    work in 5 ms: the misses name it, some of them as preemptions."""
    truth, rt, _ = run_why("preempt")
    gs = groups(rt)
    # a burst that comes while why-rt sleeps with 2 ms to spare may make no miss
    check_named(gs, truth, truth["other_tid"], every_burst=False)
    pre = by_culprit(gs, truth["other_tid"], ("preemption",))
    assert pre and all(g["who"]["comm"] == "why-preemptor" and g["who"]["prio"] == 70
                       for g in pre), gs
    # the preemptor's share lasts the burst, never longer: from its timer's
    # expiry, + 200 us from its last clock read to its switch-out (as above).
    # From its first clock read the bound failed twice (CI 91, CI 102: 4.84
    # ms against 4.09 ms): on a VM whose host holds the vCPU for ms, the hold
    # can fall between the switch-in and that read
    assert max(g["max_ns"] for g in pre) <= truth["burst_span_max_ns"] + 200000, (truth, pre)


@host_only
def test_noise_injector_is_named(bpf):
    """rtsup-noise inject (a FIFO 99 thread per CPU burning 3 ms every 30 ms
    +-25 %) against why-rt alone: the misses name the injector's thread on
    why-rt's CPU."""
    noise = subprocess.Popen([str(NOISE), "inject", "-b", "3ms", "-e", "30ms", "-d", "5s"],
                             stdout=subprocess.DEVNULL)
    try:
        truth, rt, _ = run_why("alone")
    finally:
        noise.wait(timeout=30)
    gs = groups(rt)
    misses = sum(g["count"] for g in gs)
    # 3 s of 3 ms bursts every ~30 ms: about 100, each a miss at least
    assert misses >= 50, gs
    named = [g for g in gs if g["who"] and g["who"]["tgid"] == noise.pid]
    assert named and all(g["who"]["comm"] == "rtsup-noise" and g["who"]["prio"] == 99
                         for g in named)
    ours = [g for g in gs if not elsewhere(g, truth, also=(noise.pid,))]
    assert count(named) >= 0.95 * count(ours), gs


@host_only
def test_replay_gives_the_same_causes(bpf, tmp_path):
    """--record keeps every miss's cause: the replay groups them the same,
    and its checks name each interval's own top cause as the live run's did
    (the replay judged an interval with the one before's causes)."""
    rec = tmp_path / "why.rec"
    live = []
    truth, rt, _ = run_why("hog", args=["--record", str(rec), "-i", "500ms"], summary_out=live)
    r = subprocess.run([str(BUILD / "rtsup-trace"), "replay", str(rec), "-j"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout.splitlines()[-1])
    again = [t for t in summary["threads"] if t["tid"] == truth["rt_tid"]]
    assert len(again) == 1
    strip = [{k: g[k] for k in ("kind", "count", "total_ns", "max_ns", "inversion")} |
             {"who": g["who"] and (g["who"]["tid"], g["who"]["comm"])}
             for g in groups(rt)]
    assert groups(rt) and strip == [
        {k: g[k] for k in ("kind", "count", "total_ns", "max_ns", "inversion")} |
        {"who": g["who"] and (g["who"]["tid"], g["who"]["comm"])} for g in groups(again[0])]
    # The first violation, OK to WARN at the hog's first misses, names that
    # interval's causes, live and replayed (the old replay named the interval
    # before's: none). Its cause clause only, and only the first violation:
    # a cycle record consumed after the sample's mark counts in the live
    # interval's map read and in the replay's next, so counts may differ by a
    # cycle or two (the noise injector's runs: 51 of 496 live, 50 of 494
    # replayed) and a later level change may fall in another interval.
    def causes(vs):
        return [re.findall(r"\d+ caused by .*?\)", v["what"]) for v in vs]
    said = causes(live[0]["violations"])
    assert said and said[0], live[0]["violations"]
    assert causes(summary["violations"])[:1] == said[:1]


# the holds the guest asks its host for: 8 of 100 ms, one every 500 ms
HOLDS, HOLD_MS, EVERY_MS = 8, 100, 400
MACHINE_PERIOD_MS = 20  # why_late machine's period (why_late.c)


def ask_holds():
    """Ask the host to hold this VM (vm-test hiccups); return each hold's
    length as the host measured it, in ns."""
    time.sleep(1)       # why-rt's first cycles: its period settles
    req = VM_CTL / "hiccup.req"
    req.write_text("%d %d %d\n" % (HOLDS, HOLD_MS, EVERY_MS))
    req.rename(VM_CTL / "hiccup")
    done = VM_CTL / "hiccup.done"
    end = time.time() + 60
    while not done.exists() and time.time() < end:
        time.sleep(0.1)
    assert done.exists(), "the host did not hold this VM: scripts/vm-test without hiccups?"
    text = done.read_text()
    held = [int(x) * 1000 for x in text.split()]
    assert len(held) == HOLDS, text
    ask_holds.held = held


@pytest.mark.skipif(not IN_VM, reason="inside a vm-test guest only: its host holds it "
                    "(test_guest.py runs it there)")
def test_machine_latency_is_named(bpf):
    """why-rt alone on an idle CPU (20 ms period, 100 us of work) of a guest
    whose host stops the whole VM 8 times for 100 ms while the guest's
    clocks go on: the timer of why-rt's next release fires at the end of
    the hold, 80 ms late or more. Those misses are the machine's: kind
    timer, no task, an idle CPU at the wakeup, as many as why-rt saw late
    wakeups; the releases the hold swallowed are backlogs behind no task."""
    # this test's own Python off why-rt's CPU: that CPU idles between cycles
    mask = os.sched_getaffinity(0)
    if os.cpu_count() > 1:
        os.sched_setaffinity(0, {0})
    try:
        truth, rt, intervals = run_why("machine", seconds=7, during=ask_holds)
    finally:
        os.sched_setaffinity(0, mask)
    held = ask_holds.held
    assert min(held) >= HOLD_MS * MS, held
    gs = groups(rt)
    misses = count(gs)
    assert misses == rt["total"]["deadline_misses"], gs
    # why-rt's own view: a wakeup 50 ms late or more is a hold (or the
    # machine's own stall as long: the emulated guest's host is busy too)
    late = truth["late_ns"]
    big = [x for x in late if x >= 50 * MS]
    # each hold covers a release (100 ms > 20 ms): one late wakeup per hold,
    # but when the hold began while why-rt ran its 100 us (0.5 % of a
    # period): then it finds its release past, no sleep (a backlog)
    assert len(big) >= len(held) - 1, (truth, held)
    timer = [g for g in gs if g["kind"] == "timer"]
    assert timer, (truth, gs)
    # the machine: no task, an idle CPU woken (the idle task was current)
    assert all(g["who"] is None and "idle CPU" in g["text"] for g in timer), timer
    # a late wakeup of 50 ms (more than 2 periods) ends its cycle past the
    # next release: a miss whose biggest part is the timer's (the wait
    # after it, on an idle CPU, is the switch-in alone). But a hold that
    # begins between the timer's wakeup and why-rt's switch-in (a window
    # of tens of us in a TCG guest: about 0.3 % of a period, per hold)
    # makes the wait the biggest part: behind no task, on the idle CPU,
    # the machine's too (a CI run: 8 late wakeups, 7 timer misses and
    # 1 such wait). A machine miss is a cycle that slept and missed, as
    # why-rt counted them (its check and its syscall entry are apart by a
    # few instructions: a release between them is a miss for the tracer
    # only; none expected in 7 s)
    idle_waits = [g for g in gs if g["kind"] == "wait" and g["who"] is None]
    assert all("for its idle CPU: machine latency" in g["text"] for g in idle_waits), idle_waits
    machine = timer + idle_waits
    # and a hold that begins after why-rt's switch-in, before it reads its
    # clock: why-rt sees a late wakeup, but the guest's kernel saw it run
    # through the hold (a TCG guest has no steal time): its own CPU time,
    # `exec` (a CI run: 8 late wakeups, 7 timer misses and 1 exec miss)
    held_runs = [g for g in gs if g["kind"] == "exec"]
    assert len(big) <= count(machine) + count(held_runs), (truth, gs)
    assert count(machine) <= truth["slept_misses"], (truth, gs)
    # why-rt saw each wakeup after the tracer did (the way back to user
    # space): its lateness bounds the machine's part from above
    assert max(g["max_ns"] for g in machine) <= max(late), (truth, machine)
    assert max(g["max_ns"] for g in timer) >= (HOLD_MS - 20) * MS, timer
    # the releases a hold swallowed: backlogs behind no task (they inherit
    # the late cycle's culprit: none). A hold of d ns holds floor(d / 20 ms)
    # releases or one more, by its phase against the period: the first is
    # the late wakeup's, the last may be caught up before it is past (a
    # 100 ms hold: 3 backlog misses or 4; a CI run saw 27 for 8 holds where
    # "4 per hold" wanted 28). One hold may begin while why-rt runs its
    # 100 us (a backlog, no late wakeup): it is left out. Backlogs behind a
    # task follow the guest's own noise (a task that held why-rt's CPU):
    # not the holds' business
    machine_backlogs = [g for g in gs if g["kind"] == "backlog" and g["who"] is None
                        and g["after"] in ("timer", "wait")]
    per_hold = [d // (MACHINE_PERIOD_MS * MS) - 2 for d in held]
    assert count(machine_backlogs) >= sum(per_hold) - max(per_hold), (truth, gs, held)
    assert all("(machine" in g["text"] for g in machine_backlogs), gs
    # the verdicts name the machine, the backlogs counted with the late
    # wakeups they follow (a hold's interval: the late wakeup and its
    # backlogs, 1 + 3 misses at least for a 100 ms hold)
    msgs = [m for i in intervals for t in i["threads"] if t["tid"] == truth["rt_tid"]
            for m in t["status"]["messages"] if "caused by machine / timer latency" in m]
    assert msgs, [t["status"] for i in intervals for t in i["threads"]
                  if t["tid"] == truth["rt_tid"]]
    assert max(int(m.split(" caused by machine")[0].split()[-1]) for m in msgs) >= 1 + min(
        per_hold), msgs
    # each miss event says it too: the parts, no culprit; and a hold's,
    # mostly the idle CPU (the task current at the wakeup: the idle task).
    # Not always: the resumed guest has the work the hold delayed to catch
    # up with, and a kernel thread (ksoftirqd/1 with the expired timers, an
    # IRQ thread) may be current on why-rt's CPU when its timer fires; seen
    # for 2 holds of 8 on rt-6.12
    ev = [e for e in miss_events(intervals, truth["rt_tid"]) if e["cause"]["kind"] == "timer"]
    assert ev, intervals
    for e in ev:
        c = e["cause"]
        assert c["who"] is None, e
        assert c["ns"] == c["parts"]["timer_ns"] >= c["parts"]["wait_ns"], e
    holds = [e for e in ev if e["cause"]["ns"] >= 50 * MS]
    assert holds and 2 * len([e for e in holds if e["cause"]["idle_cpu"]]) >= len(holds), holds


@pytest.mark.skipif(os.cpu_count() < 2, reason="needs two CPUs")
def test_migration_from_where_to_where_and_why(bpf):
    """why-rt moves itself to the other CPU inside every 10th cycle
    (sched_setaffinity to that CPU alone): each move is a migration inside
    the cycle, from the CPU it ran on to the other, for an affinity change
    (sched_migrate_task: its CPU left its mask). Counts, no timing: the
    guest runs it too."""
    summary = []
    truth, rt, intervals = run_why("migrate", seconds=4, summary_out=summary)
    moves = [tuple(m) for m in truth["moves"]]
    assert len(moves) >= 10 and all(a != b for a, b in moves), truth
    ev = [e for i in intervals for e in i["events"]
          if e["event"] == "unsafe" and e["reason"] == "migration" and e["tid"] == truth["rt_tid"]]
    # the totals count finished cycles: the one why-rt's exit cuts (its
    # teardown, not its loop) keeps its own apart, a move too when it made
    # one there (its last cycle was a 10th). (A CI run counted 18 of 19
    # once: the message says which move and whether the kernel skipped a
    # run of a hook.)
    last_moved = (truth["cycles"] - 1) % 10 == 9
    assert rt["total"]["unsafe"]["migration"] == len(moves) - last_moved, (
        truth, rt["total"]["unsafe"], rt["total"]["cycles"], summary[0]["health"],
        [(e["time"], e["migration"]) for e in ev])
    folded = [f for i in intervals for f in i.get("events_folded", [])
              if f.get("reason") == "migration" and f["tid"] == truth["rt_tid"]]
    assert len(ev) + sum(f["folded"] for f in folded) == len(moves), (ev, folded)
    assert ev, intervals
    for e in ev:
        m = e["migration"]
        assert (m["from"], m["to"]) in moves and m["why"] == "affinity", (e, moves)
        assert e["cpu"] == m["to"], e


@pytest.mark.skipif(os.cpu_count() < 2, reason="needs two CPUs")
def test_perfetto_shows_the_causes(bpf, tmp_path):
    """--perfetto explains the misses where they happen: each miss carries
    its cause and parts; the longest wait of a late cycle is a slice on its
    CPU's track named after the task that held the CPU; a block's wakeup is
    a flow arrow from a slice on the waker's track (why-owner, who unlocked
    the mutex) to why-rt's cycle. Checked against the JSON of the same run;
    no timing: the guest runs it too."""
    pf = tmp_path / "why.json"
    # an emulated guest's CPUs do not keep up with a 1 ms period: 5 ms
    # there, the owner's hold 10 ms every 250 ms
    truth, rt, intervals = run_why("mutex", seconds=5 if EMULATED else 3,
                                   args=["--perfetto", str(pf)], scale=5 if EMULATED else 1)
    ev = json.loads(pf.read_text())["traceEvents"]
    rt_tid, owner = truth["rt_tid"], truth["other_tid"]
    misses = [e for e in ev if e["ph"] == "i" and e["name"] == "deadline miss"
              and e["tid"] == rt_tid]
    # every miss, none folded, each with its cause and parts
    assert misses and len(misses) == rt["total"]["deadline_misses"], rt["total"]
    assert all(e["args"]["kind"] and e["args"]["cause"] and "parts" in e["args"]
               for e in misses)
    # the groups of the JSON count the same kinds
    kinds = {}
    for e in misses:
        kinds[e["args"]["kind"]] = kinds.get(e["args"]["kind"], 0) + 1
    jkinds = {}
    for g in groups(rt):
        jkinds[g["kind"]] = jkinds.get(g["kind"], 0) + g["count"]
    assert kinds == jkinds, (kinds, jkinds)
    cycles = [e for e in ev if e["ph"] == "X" and e["name"] == "cycle" and e["tid"] == rt_tid]
    # block misses woken by why-owner: an arrow from its track to why-rt's cycle
    blocks = [e for e in misses if e["args"]["kind"] == "block" and
              e["args"].get("culprit_tid") == owner]
    assert blocks, kinds
    starts = {e["id"]: e for e in ev if e["ph"] == "s" and e["cat"] == "wakeup"}
    ends = [e for e in ev if e["ph"] == "f" and e["cat"] == "wakeup" and e["tid"] == rt_tid]
    assert len(ends) >= len(blocks), (len(ends), len(blocks))
    wakes = {(e["tid"], e["ts"]) for e in ev if e["ph"] == "X" and e["cat"] == "wakeup"}
    names = {e["tid"]: e["args"]["name"] for e in ev if e["ph"] == "M" and
             e["name"] == "thread_name"}
    for f in ends:
        s = starts[f["id"]]
        assert s["ts"] <= f["ts"], (s, f)
        # it starts inside the waker's slice and ends inside why-rt's cycle
        assert (s["tid"], s["ts"]) in wakes, s
        assert any(c["ts"] <= f["ts"] <= c["ts"] + c["dur"] for c in cycles), f
    assert any(starts[f["id"]]["tid"] == owner for f in ends)
    assert names.get(owner) == "why-owner", names.get(owner)
    # the longest wait of each late cycle on its CPU's track
    held = [e for e in ev if e["ph"] == "X" and e["cat"] == "cause" and
            e["args"]["waiting_tid"] == rt_tid]
    assert held and len(held) <= len(misses), (len(held), len(misses))
    cpu_tracks = {e["tid"]: e["args"]["name"] for e in ev if e["ph"] == "M" and
                  e["name"] == "thread_name" and e["pid"] == held[0]["pid"]}
    for h in held:
        assert h["name"].startswith("held by ") and h["dur"] > 0, h
        assert cpu_tracks[h["tid"]] == "CPU %s" % CPU, (h, cpu_tracks)
