# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""rtsup-trace against rtsup-loadgen: the numbers it reports are the truth."""
import datetime
import json
import os
import re
import subprocess
import threading
import time

import pytest

import cycle_audit
from cycle_audit import CF_MISS, CF_OVERRUN
from conftest import (EMULATED, LOADGEN, PERIOD_US, TRACE, Loadgen, Trace, block_events,
                      fdinfo_values, proc_status, prog_ids, run_supervised, threads_by_tid,
                      unique_prefix)

pytestmark = pytest.mark.usefixtures("bpf")

CYCLES = 2000


def check_timing_counts(truth_t, tot):
    """Misses and overruns against the generator's own verdicts. The race:
    the generator reads the clock just before the delimiter's entry (miss?)
    and just after its return (the cycle's start), the tracer sees the entry
    and the switch-in. A cycle within 50 us of the limit, or preempted in
    such an edge window, may be judged otherwise: the generator counts those
    cycles (`*_near`, loadgen --audit), and only those may differ. Both sides
    see the same late cycles otherwise, however noisy the machine."""
    assert (truth_t["deadline_misses"] <= tot["deadline_misses"]
            <= truth_t["deadline_misses"] + truth_t["deadline_misses_near"]), (
        tot["deadline_misses"], truth_t["deadline_misses"], truth_t["deadline_misses_near"],
        cycles_judged_otherwise(truth_t, CF_MISS))
    assert (truth_t["overruns_seen"] <= tot["overruns"]
            <= truth_t["overruns_seen"] + truth_t["overruns_near"]), (
        tot["overruns"], truth_t["overruns_seen"], truth_t["overruns_near"],
        cycles_judged_otherwise(truth_t, CF_OVERRUN))


def cycles_judged_otherwise(truth_t, flag):
    """For a failure's message: the cycles the tracer and the generator
    judged otherwise, both sides' clock reads (run_supervised kept them)."""
    if not truth_t.get("_audit"):
        return "(no cycle records)"
    return cycle_audit.explain(*truth_t["_audit"], truth_t["tid"], PERIOD_US * 1000, flag)


def check_thread_matches(truth_t, got, extra_blocks=0):
    """Every injected fault of one thread is reported with the exact count
    (extra_blocks: real blocks the generator did not inject, see the caller)."""
    tot = got["total"]
    assert got["mode"] == "delimiter"
    # cycles within 1 %, period within 2 %
    assert abs(tot["cycles"] - truth_t["cycles"]) <= truth_t["cycles"] * 0.01
    assert tot["period_ns"]["mean"] == pytest.approx(PERIOD_US * 1000,
                                                     rel=0.15 if EMULATED else 0.02)
    # the generator's own view: injected overruns plus stalls that made one
    assert truth_t["overruns_seen"] >= truth_t["overruns"]
    if EMULATED:
        # emulated syscall entry and exit take long: where a cycle ends differs
        # between the two clocks by more than a stall; every injection is seen
        assert tot["overruns"] >= truth_t["overruns"]
        assert tot["deadline_misses"] >= truth_t["overruns"]
    else:
        check_timing_counts(truth_t, tot)
    assert tot["page_faults"]["minor"] == truth_t["page_faults"]
    assert tot["unsafe"]["minor_fault"] == truth_t["page_faults"]
    # the generator's waits that slept: one that came late by the block's
    # length found the lock free, and no block happened (once in rt-6.12)
    blocks = {"unsafe": tot["unsafe"], "status": got.get("status"), "causes": got.get("causes")}
    assert tot["unsafe"]["block"] == truth_t["blocks"] + extra_blocks, json.dumps(blocks)
    unsafe_truth = {k: v for k, v in truth_t["syscalls"].items() if k != "futex"}
    assert tot["unsafe_syscalls"] == unsafe_truth
    assert tot["unsafe"]["syscall"] == sum(unsafe_truth.values())


# The tracer's cycle holds the generator's span and adds the wake path and
# syscall return before the generator's first read and the entry path after
# its last (docs/testing.md). Those paths, with rtsup-trace's own sys_exit
# and sys_enter hooks, took a median of 5 us per cycle, 99th percentile 21 to
# 31 us, on a 2-vCPU VM (2026-12-02): the bound below needs fewer than one
# cycle in 10 over PATH_NS. A preemption or a hypervisor's steal there can
# take ms, but in few cycles (4 in 2000 under the noise injector).
PATH_NS = 20_000
QUANTILE_REL = 0.02  # docs/json.md: a p50 within 2 % of the exact value


def check_exec_against_generator(truth_t, exec_ns):
    """The execution time against the generator's own clock reads
    (--cycle-log): every recorded cycle holds the generator's span exactly,
    and the p50 lies between the generator's median span and, its paths
    added, its 60th percentile plus PATH_NS: P(span > q60) = 0.4, P(path >
    PATH_NS) < 0.1, so more than half the cycles are below that sum."""
    record, log = truth_t["_audit"]
    spans, short = cycle_audit.exec_containment(record, log, truth_t["tid"])
    assert spans and not short, "\n".join(short[:20])
    median, q60 = spans[len(spans) // 2], spans[len(spans) * 6 // 10]
    assert median * (1 - QUANTILE_REL) <= exec_ns["p50"] <= \
        (q60 + PATH_NS) * (1 + QUANTILE_REL), (exec_ns, median, q60)


def thread_named(pid, name):
    """The tid of pid's thread called name, None while there is none. A
    thread may end between the listing and the read of its name (the
    generator's start-up helper did, in a guest: ENOENT)."""
    for task in os.listdir("/proc/%d/task" % pid):
        try:
            with open("/proc/%d/task/%s/comm" % (pid, task)) as f:
                if f.read().strip() == name:
                    return int(task)
        except OSError:
            continue
    return None


def test_kernel_spinlock_wait_is_no_block(tmp_path):
    """The generator's audit calls getrusage inside each cycle, which takes
    the thread's task_lock; readers of its /proc/TID/stat and status take it
    too. On PREEMPT_RT that lock is an rtmutex with priority inheritance: a
    cycle that meets a reader there waits in TASK_RTLOCK_WAIT, which the
    kernel's rtapp monitor counts as an RT-friendly wait: no RT-unsafe block
    (cycle_switch_voluntary). In the rt-6.1 guest the code before counted a
    block in 3 of 7 runs of this load (inside getrusage, its --stacks fp
    said) and failed this test in 1 of 5: it catches the bug only sometimes.
    On a kernel without PREEMPT_RT the lock spins and this checks nothing."""
    prefix = unique_prefix()
    tr = Trace(["--comm", prefix + "-0", "-i", "500ms", "--no-overhead"])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", str(3000000 // PERIOD_US)])
    readers = []
    try:
        tid = None
        end = time.time() + 30
        while tid is None and time.time() < end:
            tid = thread_named(lg.pid, prefix + "-0")
            time.sleep(0.05)
        assert tid, "the generator's thread did not start"
        stat = "/proc/%d/task/%d/" % (lg.pid, tid)
        readers = [subprocess.Popen(["sh", "-c", "while cat %sstat %sstatus; do :; done"
                                     % (stat, stat)], stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL) for _ in range(2)]
        truth = lg.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        for r in readers:
            r.kill()
            r.wait()
        lg.stop()
    t = truth["threads"][0]
    tot = threads_by_tid(summary)[t["tid"]]["total"]
    assert tot["cycles"] == t["cycles"], (tot["cycles"], t["cycles"])
    assert tot["unsafe"]["block"] == 0, tot["unsafe"]


def test_clean_load_period_and_cycles(tmp_path):
    truth, intervals, summary = run_supervised(
        tmp_path, ["-P", str(PERIOD_US), "-w", "100", "-c", str(CYCLES)])
    got = threads_by_tid(summary)
    assert len(intervals) >= 1
    for t in truth["threads"]:
        g = got[t["tid"]]
        assert g["comm"] == t["comm"]
        assert g["policy"] == "SCHED_FIFO" and g["prio"] == 80
        # a block the generator did not make: the syscall it waited in, and
        # the health (per-syscall hooks: the runs the kernel skipped)
        assert g["total"]["unsafe"]["block"] == t["blocks"], (
            block_events(intervals, t["tid"]), summary["health"])
        check_thread_matches(t, g)
        tot = g["total"]
        # no fault was injected: nothing unsafe but the migrations noise causes
        # (a thread that never blocks inside its cycle leaves its CPU only
        # when preempted: at most one migration per involuntary switch)
        u = tot["unsafe"]
        assert u["total"] == u["migration"], (u, tot["context_switches"])
        assert u["migration"] <= tot["context_switches"]["involuntary"], (
            u, tot["context_switches"])
        if not EMULATED:
            check_exec_against_generator(t, tot["exec_ns"])
        assert tot["cpu_ns"]["mean"] <= tot["exec_ns"]["mean"] * 1.01
        lat = tot["latency_ns"]
        assert lat["count"] >= CYCLES - 2 and lat["min"] <= lat["p50"] <= lat["p99"] <= lat["max"]


def test_parked_threads_are_not_copied(tmp_path):
    """The sample copies out only the thread map entries that changed
    (include/threadread.h): threads parked before the tracer starts are
    copied at its first two reads (new entries, then the second copy of a
    change), then read as short records, and their totals stay whole."""
    n, cycles = 6, 50
    lg = Loadgen(tmp_path, ["--name", unique_prefix(), "-n", str(n), "-c", str(cycles)])
    try:
        truth = lg.summary()  # every worker parked in its hour-long sleep now
        tr = Trace(["-i", "200ms", "--pid", str(lg.pid)])
        # 8 intervals at least, of which the first two copy; under emulation
        # an interval's read may come late, not early: more of them
        time.sleep(3.0 if EMULATED else 1.6)
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    maps = [i["health"]["thread_map"] for i in intervals]
    # the workers and the generator's main thread, in sigwait
    assert all(m["entries"] == n + 1 for m in maps), maps
    # whole both times: no cycle since the tracer started, so no lifetime
    # of counts a short copy's other buckets could be taken from (threadmem.h)
    assert maps[0]["copied"] == n + 1 and maps[1]["copied"] == n + 1, maps
    assert all(m["short"] == m["short_refused"] == 0 for m in maps), maps
    # no hook wrote a parked thread's entry: nothing copied after the second read
    assert len(maps) >= 6 and all(m["copied"] == m["short"] == 0 for m in maps[2:]), maps
    # ... nor named in the ring: a read visits none of them, but the whole
    # read of every THREAD_TASK_EVERY-th sample, which visits all
    assert maps[0]["whole"] and maps[1]["whole"], maps
    for m in maps[2:]:
        assert m["visited"] == (n + 1 if m["whole"] else 0), maps
    wholes = sum(m["whole"] for m in maps[2:])
    assert wholes <= -(-len(maps[2:]) // THREAD_TASK_EVERY), maps
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        assert got[t["tid"]]["comm"] == t["comm"]
    # nothing happened while traced: every interval after the first two is empty
    for i in intervals[2:]:
        assert all(x["interval"]["cycles"] == 0 for x in i["threads"]), i


def kernel_at_least(major, minor):
    """The running kernel's version is major.minor or later"""
    m = re.match(r"(\d+)\.(\d+)", os.uname().release)
    return (int(m.group(1)), int(m.group(2))) >= (major, minor)


def test_running_threads_read_in_batches_without_tasks(tmp_path):
    """Threads that all cycle every interval: looking up each named entry
    would cost more than walking the map (thread_read_whole), and batches of
    entries less than the iterator's reads (batch_read_cheaper, decided from
    the read before): the map is read in batches. Their tasks are read only
    at the reads that must see every one (the first two and every
    THREAD_TASK_EVERY-th sample, thread_read_tasks): the switch-outs say when
    a running thread's attributes move. No count is lost on the way."""
    # under emulation 2 s intervals: a guest held up for most of a second (a
    # run saw 39 of the 300 cycle in one 1 s interval) leaves no worker without
    # a cycle in one. And 44 s of cycles there: the walk of tasks the check
    # below needs after every worker cycled comes at sample 16 when a worker
    # was held back past the walks of start-up (a CI guest: 20 s gave 8
    # intervals, its only such walk at sample 8, the last)
    n, period_us, cycles, iv = 300, 100_000, (440 if EMULATED else 120), (2 if EMULATED else 1)
    go = tmp_path / "go"
    lg = Loadgen(tmp_path, ["--name", unique_prefix(), "-n", str(n), "-P", str(period_us),
                            "-w", "0", "-c", str(cycles), "--wait-file", str(go)])
    # 10 periods an interval: every worker cycles in each of them, on real
    # hardware. With 3 (300 ms intervals), a CI run of the rt-6.1 guest (TCG)
    # had no interval in which all 300 did: a worker held for an interval by
    # the emulation
    tr = Trace(["-p", str(lg.pid), "-i", "%ds" % iv, "--json-threads", "active"])
    try:
        go.touch()
        truth = lg.summary()
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    workers = {t["tid"] for t in truth["threads"]}

    def cycled(i):
        return workers & {t["tid"] for t in i["threads"] if t["interval"]["cycles"]}
    # the reads of intervals in which nine workers in ten cycled, as in the
    # interval before, after the first two (all new entries, then their
    # second copies) and the one after them, whose read decides from theirs.
    # Not every one: the 2-vCPU rt-6.1 guest (TCG) of a slower host held some
    # of the 300 back for a whole interval: a run found only 2 intervals with
    # all of them. Nine in ten named: their lookups cost more
    # than the walk (thread_read_whole: 4 visits each, past the walk's 301 +
    # 400); three quarters moved at the read before: batches (batch_read_cheaper)
    busy = [(i["health"]["thread_map"], len(cycled(i))) for k, i in enumerate(intervals)
            if k >= 3 and len(cycled(i)) >= 0.9 * n and len(cycled(intervals[k - 1])) >= 0.9 * n]
    assert len(busy) >= 3, [(len(cycled(i)), i["health"]["thread_map"]) for i in intervals]
    for m, moved in busy:
        # every entry that moved is copied; one that did not is kept (entry_kept)
        assert m["whole"] and m["batch"] and m["copied"] + m["short"] >= moved, busy
    maps = [i["health"]["thread_map"] for i in intervals]
    every = -(-len(maps[2:]) // THREAD_TASK_EVERY)
    how = intervals[0]["supervisor"]["task_attrs"]
    if how == "thread_map":
        # a read reads every task or none, and every task only at the first
        # two and at every THREAD_TASK_EVERY-th read
        assert kernel_at_least(6, 2), how  # bpf_task_from_pid
        assert all(m["tasks"] in (0, m["entries"]) for m in maps), maps
        assert maps[0]["tasks"] and maps[1]["tasks"], maps
        assert sum(m["tasks"] > 0 for m in maps[2:]) <= every, maps
    else:
        # no iterator reads a task with the entries (before 6.2, or a kernel
        # that refuses the map's iterator): the task iterator walks every task
        # at the same reads, and after a sample that asked the kernel for more
        # than THREAD_WALK_ASKS threads' attributes one by one (the workers,
        # born after the go, are new to it: thread_walk_tasks), or a forced
        # (whole) read. Intervals are consecutive samples: index k is sample k + 1.
        assert how == "task_walk", how
        assert all(m["tasks"] == 0 for m in maps), maps
        for k, m in enumerate(maps):
            seq = k + 1
            due = seq <= 2 or seq % THREAD_TASK_EVERY == 0 or \
                maps[k - 1]["tasks_asked"] > THREAD_WALK_ASKS
            assert m["task_walk"] == due or (m["task_walk"] and m["whole"]), (k, maps)
        # in between, each thread keeps what the last walk found: after a walk
        # at a sample by which every worker had cycled (it was there, its
        # policy set), none is asked again
        cycled, ready = set(), None
        for k, i in enumerate(intervals):
            if ready is None and k >= 2 and workers <= cycled and maps[k]["task_walk"]:
                ready = k
            cycled |= {t["tid"] for t in i["threads"] if t["interval"]["cycles"]}
        assert ready is not None and ready + 1 < len(maps), ("no walk after all cycled", maps)
        assert all(m["tasks_asked"] == 0 for m in maps[ready + 1:]), maps
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        assert got[t["tid"]]["total"]["cycles"] == t["cycles"], (got[t["tid"]]["total"], t)


def test_injected_faults_reported_exactly(tmp_path):
    faults = ["-f", "overrun@100", "-f", "overrun/700,thread=1",
              "-f", "mmap/500,thread=1", "-f", "openat@300,thread=0",
              "-f", "write@400,thread=0", "-f", "write@450,thread=0",
              "-f", "pagefault:3@50", "-f", "pagefault:2@1200,thread=1",
              "-f", "block@70", "-f", "block@900,thread=0",
              # the last cycle, closed by --hold's long sleep: judged by its own period
              "-f", "overrun@%d,thread=1" % (CYCLES - 1)]
    if EMULATED:
        # under TCG the generator pinned to both vCPUs with these faults does
        # not finish (its SCHED_OTHER threads get no emulated CPU); the same
        # counts are checked on real time, and the guest keeps the other tests
        pytest.skip("generator cannot finish pinned fault runs under emulation")
    truth, _, summary = run_supervised(
        tmp_path, ["-P", str(PERIOD_US), "-w", "100", "-c", str(CYCLES), "-C", "0,1"] + faults)
    got = threads_by_tid(summary)
    t0, t1 = truth["threads"]
    # the truth is what we asked for
    assert t0["overruns"] == 1 and t1["overruns"] == 4
    assert t0["syscalls"].get("openat") == 1 and t0["syscalls"].get("write") == 2
    assert t1["syscalls"].get("mmap") == 4 and t1["page_faults"] == 5
    assert t0["blocks_injected"] == 2
    for t in truth["threads"]:
        check_thread_matches(t, got[t["tid"]])


def test_exit_is_reported_and_tracing_goes_on(tmp_path):
    truth, intervals, summary = run_supervised(
        tmp_path, ["-c", str(CYCLES), "-f", "exit@500,thread=1"])
    t0, t1 = truth["threads"]
    assert t1["exited"] and not t0["exited"]
    events = [e for i in intervals for e in i["events"]]
    exits = [e for e in events if e["event"] == "exit"]
    assert [e["tid"] for e in exits] == [t1["tid"]]
    assert exits[0]["mid_cycle"] is True
    got = threads_by_tid(summary)
    assert got[t1["tid"]]["alive"] is False
    assert got[t1["tid"]]["total"]["cycles"] == pytest.approx(500, abs=1)
    # the other thread is still supervised to the end
    assert got[t0["tid"]]["alive"] is True
    assert got[t0["tid"]]["total"]["cycles"] == pytest.approx(t0["cycles"], rel=0.01)
    # the exited thread is not reported in intervals after its exit
    last = intervals[-1]
    assert t1["tid"] not in [t["tid"] for t in last["threads"]]


def test_non_target_is_not_reported(tmp_path):
    (tmp_path / "o").mkdir()
    other = Loadgen(tmp_path / "o", ["--name", "notme", "-c", "3000"], hold=False)
    try:
        truth, intervals, summary = run_supervised(tmp_path, ["-c", "1000"])
        other_truth = other.summary()
    finally:
        other.stop()
    reported = {t["tid"] for i in intervals + [summary] for t in i["threads"]}
    assert reported == {t["tid"] for t in truth["threads"]}
    assert not reported & {t["tid"] for t in other_truth["threads"]}


def test_comm_picks_up_process_started_later(tmp_path):
    # by process name: the generator's main thread and all its threads
    tr = Trace(["--comm", "rtsup-loadgen"])
    lg = Loadgen(tmp_path, ["--name", "later", "-c", "500"])
    try:
        truth = lg.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        lg.stop()
    got = threads_by_tid(summary)
    assert truth["pid"] in got
    for t in truth["threads"]:
        assert got[t["tid"]]["total"]["cycles"] == pytest.approx(t["cycles"], rel=0.01)


def _tid_named(pid, comm, timeout=30):
    end = time.time() + timeout
    while time.time() < end:
        for tid in os.listdir("/proc/%d/task" % pid):
            try:
                if open("/proc/%d/task/%s/comm" % (pid, tid)).read().strip() == comm:
                    return int(tid)
            except OSError:
                pass
        time.sleep(0.05)
    raise AssertionError("no thread named " + comm)


@pytest.mark.skipif(os.cpu_count() < 2, reason="needs two CPUs to move a thread")
def test_policy_and_affinity_changes_are_seen(tmp_path):
    """A chrt or taskset of a running target shows at the next sample:
    its next switch-out counts the change (thread_sched_seen in
    include/threadread.h), and the sample asks for its attributes again,
    without waiting for the whole read of every THREAD_TASK_EVERY-th."""
    prefix = unique_prefix()
    tr = Trace(["-i", "200ms", "--comm=%s-0" % prefix])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", "100000"], hold=False)
    try:
        tid = _tid_named(lg.pid, prefix + "-0")
        time.sleep(0.6 if not EMULATED else 3)
        subprocess.run(["chrt", "-f", "-p", "70", str(tid)], check=True)
        subprocess.run(["taskset", "-p", "-c", "0", str(tid)], check=True,
                       stdout=subprocess.DEVNULL)
        changed = time.time()
        time.sleep(0.8 if not EMULATED else 4)
        intervals, _, _ = tr.stop()
    finally:
        lg.stop()
        if tr.proc.poll() is None:
            tr.proc.kill()
    seen = [[t for t in i["threads"] if t["tid"] == tid] for i in intervals]
    seen = [x[0] for x in seen if x]
    assert seen[0]["prio"] == 80 and seen[0]["cpus"] == "0-%d" % (os.cpu_count() - 1)
    assert seen[-1]["policy"] == "SCHED_FIFO" and seen[-1]["prio"] == 70
    assert seen[-1]["cpus"] == "0"
    after = [[t for t in i["threads"] if t["tid"] == tid] for i in intervals
             if _written_at(i) > changed]
    new = [k for k, x in enumerate(after)
           if x and x[0]["prio"] == 70 and x[0]["cpus"] == "0"]
    # the first interval written after the change may have been sampled
    # before it: the next one has it, whole read or not
    assert new and new[0] <= 1, [(x[0]["prio"], x[0]["cpus"]) for x in after if x]


# include/threadread.h: a parked target's task is read every THREAD_TASK_EVERY samples
THREAD_TASK_EVERY = 8
THREAD_WALK_ASKS = 64  # include/threadread.h


def _written_at(interval):
    """an interval object's wall-clock write time, in seconds since the epoch"""
    return datetime.datetime.fromisoformat(interval["time"].replace("Z", "+00:00")).timestamp()


def test_parked_thread_policy_change_is_seen(tmp_path):
    """A parked target's attributes are read once every THREAD_TASK_EVERY
    samples (where the thread map's iterator reads the tasks, 6.2+; every
    sample with the task iterator): a chrt of a thread that does not run
    shows within that many intervals, and no verdict is made of a stale
    policy meanwhile (the thread has no rule)."""
    prefix = unique_prefix()
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", "1", "-r", "0"])
    try:
        lg.summary()  # its one cycle is done: parked from now on
        tid = _tid_named(lg.pid, prefix + "-0")
        tr = Trace(["-i", "100ms", "--pid", str(lg.pid)])
        time.sleep(1.0 if not EMULATED else 5)
        subprocess.run(["chrt", "-f", "-p", "30", str(tid)], check=True)
        chrt_end = time.time()
        end = time.time() + (10 if not EMULATED else 60)
        while time.time() < end:
            after = [x for x in tr.out if '"type":"interval"' in x.replace(" ", "")]
            if len([x for x in after if _written_at(json.loads(x)) > chrt_end]) > \
                    THREAD_TASK_EVERY + 3:
                break
            time.sleep(0.1)
        intervals, _, _ = tr.stop()
    finally:
        lg.stop()
    after = [i for i in intervals if _written_at(i) > chrt_end]
    seen = [[t for t in i["threads"] if t["tid"] == tid] for i in after]
    assert all(len(x) == 1 for x in seen), "the thread is in every interval"
    seen = [x[0] for x in seen]
    assert all(t["interval"]["cycles"] == 0 for t in seen), "it stayed parked"
    fifo = [k for k, t in enumerate(seen) if t["policy"] == "SCHED_FIFO" and t["prio"] == 30]
    assert fifo, [t["policy"] for t in seen]
    # the first interval written after the chrt may have been sampled before it: one more
    assert fifo[0] <= THREAD_TASK_EVERY, [t["policy"] for t in seen]
    assert fifo == list(range(fifo[0], len(seen))), "once read, it stays"


def test_quiet_loop_wakes_once_an_interval(tmp_path):
    """With no event coming (a parked target), the loop waits for its next
    interval instead of polling every 100 ms (collector_poll_ms): at a 1 s
    interval it sleeps about once a second, where it slept ten times."""
    lg = Loadgen(tmp_path, ["-n", "1", "-c", "1", "-r", "0"])
    try:
        lg.summary()  # its one cycle is done: parked from now on
        tr = Trace(["-i", "1s", "--pid", str(lg.pid)])
        time.sleep(3.0)  # past the start-up: its first overhead window and intervals
        v0, t0 = proc_status(tr.proc.pid, "voluntary_ctxt_switches"), time.monotonic()
        time.sleep(4.0)
        v1, t1 = proc_status(tr.proc.pid, "voluntary_ctxt_switches"), time.monotonic()
        tr.stop()
    finally:
        lg.stop()
    per_s = (v1 - v0) / (t1 - t0)
    # one sleep an interval; a second one when an overhead window ends in it
    # (one interval in 30), and any sleep on a lock or a read: 3 a second is
    # far from the 10 of a 100 ms poll
    assert per_s < 3, "%.1f sleeps a second" % per_s


def test_pid_target_includes_threads_created_later(tmp_path):
    go = tmp_path / "go"
    lg = Loadgen(tmp_path, ["--wait-file", str(go), "-c", "1000"])
    try:
        tr = Trace(["--pid", str(lg.pid)])
        go.touch()  # attached: now the generator creates its threads
        truth = lg.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        lg.stop()
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        assert got[t["tid"]]["total"]["cycles"] == pytest.approx(t["cycles"], rel=0.01)


def test_raw_tracepoint_fallback(tmp_path):
    truth, _, summary = run_supervised(
        # one thread maps: two at once can contend on the mmap lock, a real block
        tmp_path, ["-c", "1000", "-f", "mmap@100,thread=0", "-f", "overrun@200"], ["--raw-tp"])
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        check_thread_matches(t, got[t["tid"]])


# A start is mostly the verifier's walk of our programs: about 1 us per
# instruction on a PC, ten times that in an emulated guest. With the cycle
# state machine inlined, sys_enter and sched_switch walked 437 815 and
# 96 666 on Linux 6.18 (550 000 in all; 558 000 on 6.12-rt, 234 000 on
# 6.1-rt, whose verifier prunes otherwise): delim_cycle and
# switch_out_cycle became global functions, verified once, and the walk
# was 54 000 to 63 000 in all on 6.12 and 6.18, 118 000 to 156 000 on 6.1
# (its sched_switch 67 000 to 103 091: the rest of a switch-out, walked
# again for each state of the switch-in side, and sys_enter 37 744: the
# histogram's bucket, walked again at each metric). With the switch-out's
# rest and hist_bucket global too (bpf/rtsup.bpf.c, include/hist.h):
# 32 500 to 42 600 in all on 6.1, 6.12 and 6.18, no program above 14 600.
# The bounds catch each of the older walks on every one of these kernels.
VERIFIED_PER_PROGRAM = 20000
VERIFIED_TOTAL = 50000
# the generator's delimiter: its cycles sleep there
DELIM = "clock_nanosleep"


@pytest.mark.parametrize("opts", [[], ["--rt"], ["--raw-tp"], ["--stacks", "dwarf"]],
                         ids=["default", "rt", "raw-tp", "stacks"])
def test_start_up_verifies_few_instructions(opts):
    """The walk of the raw_syscalls set, pinned even where RTSUP_TRACE starts
    every run with per-syscall hooks (scripts/trace-per-syscall): their walk
    is test_per_syscall_hooks_count_exactly_...'s, whose every start costs
    20 s or more in a guest"""
    r = subprocess.run([str(TRACE), "-v", "-p", "1", "-d", "0.1s", "-j",
                        "--syscall-hooks", "raw"] + opts,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    line = [x for x in r.stderr.splitlines() if x.startswith("rtsup-trace: verified ")]
    # 5.16 and later report it (verified_insns): every kernel we test on
    assert len(line) == 1, r.stderr
    total, progs = re.match(r"rtsup-trace: verified (\d+) instructions: (.*)$", line[0]).groups()
    per = {name: int(n) for name, n in (x.rsplit(" ", 1) for x in progs.split(", "))}
    assert sum(per.values()) == int(total)
    assert any(name.startswith("sys_enter") for name in per), per
    assert max(per.values()) <= VERIFIED_PER_PROGRAM, per
    assert int(total) <= VERIFIED_TOTAL, per


def test_relative_sleep_with_nominal_period(tmp_path):
    truth, _, summary = run_supervised(
        tmp_path, ["--relative", "-c", "1000", "-f", "overrun@300"],
        ["--period", "%dus" % PERIOD_US])
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        tot = got[t["tid"]]["total"]
        assert tot["cycles"] == pytest.approx(t["cycles"], rel=0.01)
        assert t["overruns"] == 1
        if EMULATED:
            assert tot["overruns"] >= 1
            continue
        # a relative sleeper drifts by every late wakeup: only on real time
        assert tot["period_ns"]["mean"] == pytest.approx(PERIOD_US * 1000, rel=0.02)
        # the same race as check_timing_counts
        assert t["overruns_seen"] <= tot["overruns"] <= t["overruns_seen"] + t["overruns_near"]
        # a relative sleep has no deadline to miss
        assert tot["deadline_misses"] == 0


def test_activation_mode_reads_wakeups(tmp_path):
    # a delimiter the generator never calls: its threads fall back to
    # activations (wakeup to block), whose latency needs every wakeup's time
    truth, _, summary = run_supervised(
        tmp_path, ["-c", "1000"], ["--cycle-syscall", "epoll_wait"])
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        g = got[t["tid"]]
        assert g["mode"] == "activation"
        tot = g["total"]
        # an activation runs from a wakeup to the next block: one per voluntary
        # switch, which the generator reads for itself (getrusage) around its
        # loop. A late cycle's sleep may not block, so cycles are no measure.
        # The first activation starts at the first block's wakeup and the last
        # one ends at the last block: 2 at the edges.
        assert tot["cycles"] == pytest.approx(t["voluntary_switches"], abs=2)
        lat = tot["latency_ns"]
        # no tracepoint fires while some tasks run (docs/design.md, "Unseen
        # events"): an activation switched in from one begins at the thread's
        # own syscall, counted, and has no wakeup latency
        unseen = tot["context_switches"]["unseen_switch_ins"]
        assert lat["count"] >= tot["cycles"] - 2 - unseen
        assert 0 < lat["p50"] < PERIOD_US * 1000
        # the mean distance between two wakeups is a period whether or not a
        # late cycle blocked: the releases are the generator's, every period
        assert tot["period_ns"]["mean"] == pytest.approx(
            PERIOD_US * 1000 * t["cycles"] / t["voluntary_switches"], rel=0.05)


def test_stall_starves_the_thread(tmp_path):
    truth, _, summary = run_supervised(
        tmp_path, ["-c", "1500", "-C", "0,1", "-f", "stall:8@500,thread=0"])
    got = threads_by_tid(summary)
    t0 = truth["threads"][0]
    tot = got[t0["tid"]]["total"]
    assert t0["stalls"] == 1 and t0["deadline_misses"] >= 1
    if not EMULATED:
        assert (t0["deadline_misses"] <= tot["deadline_misses"]
                <= t0["deadline_misses"] + t0["deadline_misses_near"])  # check_timing_counts
    # the next release passed while the hog spun: that sleep ends late by
    # the stall less one period (7 ms on the host, 3 ms at the guest's 5 ms)
    assert tot["latency_ns"]["max"] >= (8000 - PERIOD_US) * 1000
    assert tot["context_switches"]["involuntary"] >= 1


def test_json_interval_schema(tmp_path):
    _, intervals, summary = run_supervised(tmp_path, ["-c", "1500"], ["-i", "500ms"])
    assert len(intervals) >= 2
    for obj in intervals:
        for key in ("time", "elapsed_s", "interval_s", "threads", "events",
                    "lost_events", "untracked_threads"):
            assert key in obj
        assert obj["lost_events"] == 0
        for t in obj["threads"]:
            for key in ("tid", "tgid", "comm", "policy", "prio", "cpus", "alive",
                        "interval", "total"):
                assert key in t
            for m in ("period_ns", "exec_ns", "cpu_ns", "latency_ns"):
                assert "count" in t["interval"][m]
    # the intervals add up to the total (start-up activations are dropped from
    # the total at the first delimiter call, so only delimiter-mode intervals)
    for tid, t in threads_by_tid(summary).items():
        per = sum(x["interval"]["cycles"] for i in intervals for x in i["threads"]
                  if x["tid"] == tid and x["mode"] == "delimiter")
        assert per == t["total"]["cycles"]


def run_cli(args, **kw):
    return subprocess.run([str(TRACE)] + args, capture_output=True, text=True,
                          timeout=60, **kw)


@pytest.mark.parametrize("args,msg", [
    ([], "no target"),
    (["--pid", "0"], "--pid '0': not a process id"),
    (["--pid", "99999999999"], "not a process id"),
    (["--pid", "4194000"], "no such process"),
    (["--tid", "4194000"], "no such thread"),
    (["-p", "1", "-i", "0"], "--interval"),
    (["-p", "1", "-d", "soon"], "--duration"),
    # fuzz_options: nan and inf are numbers to strtod; a huge period overflowed its ns
    (["-p", "1", "-i", "nan"], "--interval 'nan'"),
    (["-p", "1", "-d", "inf"], "--duration 'inf'"),
    (["-p", "1", "--period", "88888888888888888888888us"], "--period"),
    (["-p", "1", "--cycle-syscall", "frobnicate"], "no such syscall"),
    (["-p", "1", "--ewma-weight", "2"], "--ewma-weight"),
    (["-c", "a-name-longer-than-15"], "1 to 15 characters"),
    (["-p", "1", "--cgroup", "/nonexistent"], "--cgroup '/nonexistent'"),
])
def test_bad_input_one_line_error(args, msg):
    r = run_cli(args)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rtsup-trace: ")
    assert msg in lines[0]
    assert r.stdout == ""


def test_not_root_says_what_to_do():
    r = run_cli(["-p", "1"], user=65534, group=65534, extra_groups=[])
    assert r.returncode == 1
    assert r.stderr.strip().splitlines() == [
        "rtsup-trace: not allowed to load BPF programs: "
        "run as root or grant CAP_BPF and CAP_PERFMON"]


def test_pid_that_exits_keeps_running(tmp_path):
    lg = Loadgen(tmp_path, ["-c", "300"], hold=False)
    tr = Trace(["--pid", str(lg.pid), "-i", "200ms"])
    lg.summary()
    lg.stop()
    time.sleep(0.6)
    assert tr.proc.poll() is None  # still running after its target is gone
    intervals, summary, _ = tr.stop(sig=__import__("signal").SIGTERM)
    alive = [{k: t.get(k) for k in ("tid", "comm", "alive", "mode", "policy")}
             for t in summary["threads"] if t["alive"]]
    assert not alive, alive


def test_rt_selects_rt_threads_only(tmp_path):
    (tmp_path / "other").mkdir()
    tr = Trace(["--rt"])
    rt = Loadgen(tmp_path, ["--name", "rtyes", "-c", "800"])
    other = Loadgen(tmp_path / "other", ["--name", "rtno", "-r", "0", "-c", "800"])
    try:
        truth, other_truth = rt.summary(), other.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        rt.stop()
        other.stop()
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        assert got[t["tid"]]["policy"] == "SCHED_FIFO"
        assert got[t["tid"]]["total"]["cycles"] == pytest.approx(t["cycles"], rel=0.01)
    assert not set(got) & {t["tid"] for t in other_truth["threads"]}
    assert other_truth["pid"] not in got


def cgroup2_root():
    with open("/proc/mounts") as f:
        for line in f:
            dev, mnt, fstype = line.split()[:3]
            if fstype == "cgroup2":
                return mnt
    return None


@pytest.mark.skipif(cgroup2_root() is None, reason="no cgroup v2 hierarchy mounted")
def test_cgroup_target(tmp_path):
    cg = os.path.join(cgroup2_root(), "rtsup-test-%d" % os.getpid())
    os.mkdir(cg)
    go = tmp_path / "go"
    lg = Loadgen(tmp_path, ["--wait-file", str(go), "-c", "800"])
    try:
        with open(os.path.join(cg, "cgroup.procs"), "w") as f:
            f.write(str(lg.pid))
        tr = Trace(["--cgroup", cg])
        go.touch()
        truth = lg.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        lg.stop()
        os.rmdir(cg)
    got = threads_by_tid(summary)
    # the main thread was in the cgroup at start, the workers were forked there
    assert truth["pid"] in got
    for t in truth["threads"]:
        assert got[t["tid"]]["total"]["cycles"] == pytest.approx(t["cycles"], rel=0.01)


def stats_enabled():
    with open("/proc/sys/kernel/bpf_stats_enabled") as f:
        return int(f.read())


def held_progs(pid):
    """bpftool's record of each BPF program a process holds (name, run_cnt,
    verified_insns...): one bpftool for all"""
    ids = prog_ids(pid)
    r = subprocess.run(["bpftool", "-j", "prog", "show"], capture_output=True, text=True,
                       check=True)
    return [p for p in json.loads(r.stdout) if p["id"] in ids]


def prog_run_time(pid):
    """run_time_ns summed over the BPF programs a process holds: it grows
    only while the kernel's BPF statistics are on"""
    return sum(fdinfo_values(pid, "run_time_ns"))


def foreign_stats_holders(own_pid):
    """Processes but own_pid that hold the kernel's BPF statistics on by an fd
    (BPF_ENABLE_STATS, anon_inode:bpf-stats; /proc/sys does not show those):
    another rtsup-trace's window, a bench."""
    pids = set()
    for p in os.listdir("/proc"):
        if not p.isdigit() or int(p) == own_pid:
            continue
        try:
            for fd in os.listdir("/proc/%s/fd" % p):
                if os.readlink("/proc/%s/fd/%s" % (p, fd)) == "anon_inode:bpf-stats":
                    pids.add(int(p))
                    break
        except OSError:
            continue
    return pids


def stats_window(tmp_path):
    """Our programs' run time, sampled every 5 ms for 2.5 s after a start:
    (times it grew, spans when another process held statistics on, intervals).
    Another tool's window makes our run time grow too (a CI run here failed
    so, beside a test run by hand): scans of /proc every few tens of ms,
    shorter than such a window, mark when one was held."""
    lg = Loadgen(tmp_path, ["-n", "2", "-c", str(3000000 // PERIOD_US)])
    tr = Trace(["--pid", str(lg.pid), "-i", "1s"])
    seen, foreign, done, t0 = [], [], threading.Event(), time.monotonic()

    def scan():
        while not done.is_set():
            a = time.monotonic() - t0
            if foreign_stats_holders(tr.proc.pid):
                foreign.append((a, time.monotonic() - t0))
            time.sleep(0.01)
    scanner = threading.Thread(target=scan)
    scanner.start()
    try:
        while time.monotonic() - t0 < 2.5:
            seen.append((time.monotonic() - t0, prog_run_time(tr.proc.pid)))
            time.sleep(0.005)
        intervals, _, _ = tr.stop()
    finally:
        done.set()
        scanner.join()
        lg.stop()
    return [t for (t, a), (_, b) in zip(seen, seen[1:]) if b > a], foreign, intervals


# a process that calls getppid (the cheapest syscall) for argv[1] seconds
GETPPID_FLOOD = """
import os, sys, time
end = time.monotonic() + float(sys.argv[1])
while time.monotonic() < end:
    for i in range(1000):
        os.getppid()
"""


def test_overhead_sampled_in_a_short_window(tmp_path):
    """BPF statistics cost every BPF program on the machine two clock reads per
    run: rtsup-trace switches them on for a short window (100 ms) at the start
    of one interval in 30, and the first interval already carries a measure."""
    if stats_enabled() != 0:
        # the guest pins them on (docs/vm-test.md), another tool may hold them
        pytest.skip("kernel.bpf_stats_enabled is already on: the window cannot be seen")
    # a run beside another holder says nothing: again, three times at most
    for attempt in range(3):
        (tmp_path / str(attempt)).mkdir()
        grew, foreign, intervals = stats_window(tmp_path / str(attempt))
        if not foreign:
            break
    assert not foreign, "another process held BPF statistics on in each of 3 runs"
    assert grew, "the statistics were never switched on"
    # 100 ms; a loaded machine may stretch it, never to the whole interval
    assert max(grew) - min(grew) < 0.5, "on from %.3f s to %.3f s" % (min(grew), max(grew))
    assert max(grew) < 1.0, "still on at %.3f s" % max(grew)
    su = intervals[0]["supervisor"]
    # our programs' own time: 0 when the window's runs took no longer than
    # the statistics' floor (an idle machine's few runs)
    assert su["bpf_overhead_pct"] is not None and 0 <= su["bpf_overhead_pct"] < 100, su
    assert su["bpf_stats"]["floor_ns"] > 0, su


def floor_under_flood():
    """rtsup-trace --floor --rt for one 1 s interval under a flood of getppid
    calls: (its last report's supervisor, the window's raw run time in % of a CPU)"""
    flood = subprocess.Popen(["/usr/bin/python3", "-c", GETPPID_FLOOD, "6"])
    try:
        time.sleep(0.5)  # the flood runs before the first window opens
        r = subprocess.run([str(TRACE), "--floor", "--rt", "-d", "1200ms", "-i", "1s", "-j"],
                           capture_output=True, text=True, timeout=120)
    finally:
        flood.kill()
        flood.wait()
    assert r.returncode == 0, r.stderr
    su = [json.loads(x) for x in r.stdout.splitlines() if x.strip()][-1]["supervisor"]
    w = su["bpf_stats"]
    assert w and w["floor_ns"] > 0, su
    # the flood was in the window: two runs a call
    assert w["runs"] >= 1000, su
    return su, w["run_s"] / w["window_s"] * 100


def test_overhead_leaves_out_the_statistics_own_clock_reads(tmp_path):
    """While the BPF statistics are on, the kernel reads the clock around
    every program run, and each run's time holds one clock read: on a
    machine busy with syscalls that was most of what the overhead check
    measured (52 of a sys_enter run's 61 ns on the development VM; an RT
    guest's start-up read "4.99 % of a CPU"). Empty programs (--floor) under
    a flood of getppid calls cost next to nothing: the check says so."""
    if EMULATED:
        # Under TCG a run's time is the host's time to emulate it: the floor's
        # runs are emulated in a tight loop, the window's amid the flood's
        # syscalls, each at the host's load of its moment. 27 % (CI 96) and 51 %
        # (CI 102, a slower host: 113 ns a run against the floor's 55) were left
        # over; no bound on that ratio follows from the emulation. What holds
        # there: the floor is taken off.
        su, raw = floor_under_flood()
        assert su["bpf_overhead_pct"] < raw, (su, raw)
        return
    # The floor is measured by test runs in a loop, warm, at another moment
    # than the window's runs; a hook's run is colder and an interrupt may fall
    # in it. Both move: in 12 runs on the development VM the floor read 47-56 ns
    # a run and the flood's empty runs 50-62 ns, and 0 to 15 % of the raw
    # figure was left over (25.3 % once, CI 120). Noise only adds to what is
    # left over, so the least of three runs is the measure; without the floor
    # taken off, all of it is left over in every run.
    seen = []
    for _ in range(3):
        su, raw = floor_under_flood()
        seen.append((su["bpf_overhead_pct"] / raw if raw else 1.0, su))
        if seen[-1][0] <= 0.25:
            break
    assert min(r for r, _ in seen) <= 0.25, seen


def test_exit_never_crowded_out_by_a_flood_of_misses(tmp_path):
    # every cycle overruns by 0.3 period: each is a deadline miss, ~3000 a thread in
    # the one 10 s interval; a thread's exit in the middle must still be there
    truth, intervals, summary = run_supervised(
        tmp_path, ["-c", "3000", "-f", "overrun:%d/1" % (PERIOD_US * 13 // 10),
                   "-f", "exit@1500,thread=1"],
        ["-i", "10s"])
    t0, t1 = truth["threads"]
    assert t1["exited"] and t0["deadline_misses"] >= 2900
    events = [e for i in intervals for e in i["events"]]
    assert [e["tid"] for e in events if e["event"] == "exit"] == [t1["tid"]]
    # the flood is folded, and says how much: kept + folded = every miss reported
    assert all(i["lost_events"] == 0 for i in intervals)
    got = threads_by_tid(summary)
    for t in (t0, t1):
        kept = sum(1 for e in events if e["event"] == "deadline_miss" and e["tid"] == t["tid"])
        folded = sum(f["folded"] for i in intervals for f in i["events_folded"]
                     if f["event"] == "deadline_miss" and f["tid"] == t["tid"])
        assert kept + folded == got[t["tid"]]["total"]["deadline_misses"]
        assert folded > 0
    assert sum(i["events_not_shown"] for i in intervals) == sum(
        f["folded"] for i in intervals for f in i["events_folded"])
def rt_tids():
    """Every thread of the host with an RT policy now: {tid: tgid}."""
    rt = {}
    for p in os.listdir("/proc"):
        if not p.isdigit():
            continue
        try:
            tasks = os.listdir("/proc/%s/task" % p)
        except OSError:
            continue  # gone meanwhile
        for t in tasks:
            try:
                if os.sched_getscheduler(int(t)) in (os.SCHED_FIFO, os.SCHED_RR, 6):
                    rt[int(t)] = int(p)
            except OSError:
                pass
    return rt


def is_kernel_thread(tid):
    """PF_KTHREAD in /proc/<tid>/stat (field 9, after the name)."""
    try:
        with open("/proc/%d/stat" % tid) as f:
            return bool(int(f.read().rsplit(")", 1)[1].split()[6]) & 0x00200000)
    except (OSError, IndexError, ValueError):
        return False


class RtWatch:
    """Polls the host's RT threads while a test runs: the union of what was
    seen and whether the set changed (other programs started or ended RT
    threads). This machine is shared: the test compares with what it saw."""

    def __init__(self, every=0.05):
        self.first = rt_tids()
        self.union = dict(self.first)
        self.changed = False
        self.every = every
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while not self.done.wait(self.every):
            now = rt_tids()
            if set(now) != set(self.first):
                self.changed = True
            self.union.update(now)

    def stop(self):
        self.done.set()
        if self.thread.is_alive():
            self.thread.join()


def test_rt_check_idle_host_exits_0(tmp_path):
    """`--rt --check -d 10s` on a host with kernel RT threads (migration/N,
    watchdogd, irq/N-...) and a well-behaved RT program exits 0 (issue 12,
    item 4, reported with 20 s): kernel threads are shown, not judged; RT
    threads that wait for work are idle, not 'not initialized'. 10 s is
    twice the default init_timeout (5 s), past which a rule's thread with
    no cycle is 'not initialized'."""
    kernel = [t for t in rt_tids() if is_kernel_thread(t)]
    # a host without kernel RT threads would test the loadgen alone
    assert kernel, "this host has no kernel RT thread (ps -eLo cls): the test needs one"
    prefix = unique_prefix()
    watch = RtWatch()
    tr = subprocess.Popen([str(TRACE), "--rt", "--check", "-d", "10s", "-j"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lg = None
    try:
        # once attached (the banner), the 10 s run: the generator outlives it
        # (a thread that exits during it is an ERROR), then ends by itself and
        # its summary says what it saw
        assert "tracing with" in tr.stderr.readline()
        cycles = int(15e6 / PERIOD_US)
        # well-behaved: each thread pinned to a CPU of its own, where there are two
        cpus = ",".join(str(c) for c in sorted(os.sched_getaffinity(0))[:2])
        lg = Loadgen(tmp_path, ["--name", prefix, "-n", "2", "-c", str(cycles), "-w", "100",
                                "-C", cpus], hold=False)
        out, err = tr.communicate(timeout=120)
        watch.stop()
        truth = lg.summary()
    finally:
        watch.stop()
        if lg:
            lg.stop()
        if tr.poll() is None:
            tr.kill()
    r = subprocess.CompletedProcess(tr.args, tr.returncode, out, err)
    objs = [json.loads(x) for x in r.stdout.splitlines() if x.strip()]
    summary = [o for o in objs if o.get("type") == "summary"]
    assert len(summary) == 1, r.stderr
    got = threads_by_tid(summary[0])
    # This machine is shared: RT threads of other programs (other tests'
    # generators, with their injected faults and stalls) may be judged
    # WARN/ERROR, and when they take our generator's CPU it misses deadlines,
    # which it sees itself: then the timing checks (misses, execution near the
    # period, starving) may fire for it, nothing else. Nothing else may be
    # judged; without either the run exits 0.
    others = {tid for tid, tgid in watch.union.items()
              if tgid != lg.pid and not is_kernel_thread(tid) and tid in got}
    missed = {t["tid"] for t in truth["threads"] if t["deadline_misses"] or t["overruns_seen"]}
    culprits = {}
    for v in summary[0]["violations"]:
        if "[" in v["component"]:
            culprits.setdefault(int(v["component"].rsplit("[", 1)[1].rstrip("]")), []).append(v)
    for tid, vs in culprits.items():
        if tid in missed:
            timing = ("deadline misses", "execution ", "starving: ")
            assert all(any(k in v["what"] for k in timing) for v in vs), [v["what"] for v in vs]
        else:
            assert tid in others, (vs, r.stderr)
    # An emulated CPU (the RT guests' TCG) runs our programs far slower than
    # the kernel code around them: sched_switch 4.6-7.4 us a run there, 0.1
    # on this host. The start-up window read 3.6-6.7 % of a CPU in rt-6.12 (6
    # runs, bpf_stats: 500-2400 ns a run over an empty program's 65): true
    # there, and the supervisor's own overhead check may fire there, it alone.
    # A slow host too: a fresh-clone run on a 2-vCPU VM half as fast as the
    # one this test was written on read 1.03 % in its first interval (--rt
    # follows every switch of the machine). That check's measure is
    # test_overhead_*'s; this test holds the threads' verdicts, and the
    # supervisor's own may be that one alone, with its exit code.
    own = [c for v in summary[0]["violations"] if "[" not in v["component"]
           for c in v["checks"]]
    assert all(c["check"] == "overhead" for c in own), (own, summary[0]["supervisor"])
    if not others and not missed:
        assert r.returncode == (2 if own else 0), (summary[0]["violations"], r.stderr)
    else:
        assert r.returncode in (0, 2), r.stderr
    for t in kernel:
        if t in got:  # a kernel thread that ran: shown, flagged, never judged
            assert got[t]["kernel_thread"] is True
            assert got[t]["worst_level"] == "OK", got[t]
    ours = [t for t in got.values() if t["tgid"] == lg.pid]
    assert len(ours) == 2 and all(not t["kernel_thread"] for t in ours)
    assert all(t["worst_level"] == "OK" for t in ours if t["tid"] not in missed), ours


def test_untracked_threads_counted_once(tmp_path):
    """With --max-threads 4 and more RT threads than that, 'untracked_threads'
    counts threads, not their switch-ins, and stays constant while nothing
    changes (issue 12, item 9)."""
    prefix = unique_prefix()
    cycles = int(30e6 / PERIOD_US)
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "8", "-c", str(cycles), "-w", "50"],
                 hold=False)
    try:
        time.sleep(0.5)
        watch = RtWatch()
        tr = Trace(["--rt", "--max-threads", "4", "-i", "500ms", "-d", "4s"])
        tr.proc.wait(timeout=60)
        intervals, summary, _ = tr.stop()
        watch.stop()
    finally:
        lg.stop()
    ours = {tid for tid, tgid in watch.first.items() if tgid == lg.pid}
    assert len(ours) == 8
    tracked = set(threads_by_tid(summary))
    counts = [i["untracked_threads"] for i in intervals] + [summary["untracked_threads"]]
    # at most 4 tracked at once: every one of our 8 threads not tracked is counted...
    assert counts[-1] >= len(ours - tracked)
    # ...and each thread once: switch-ins at 1 kHz would count thousands
    assert counts[-1] <= len(watch.union), (counts, len(watch.union))
    assert counts == sorted(counts), counts  # a counter never goes back
    if not watch.changed:
        # no RT thread came or went: the map holds 4, all others are counted
        assert len(tracked) == 4
        assert counts == [len(watch.first) - 4] * len(counts), (counts, watch.first)


@pytest.mark.parametrize("mount_proc", [True, False])
def test_pid_namespace_refused(mount_proc):
    """Inside a PID namespace (a container) the tids of /proc are not the
    kernel's that the BPF programs see: rtsup-trace says so and exits 1
    (issue 12, item 11), also when /proc is the namespace's own."""
    unshare = ["unshare", "--pid", "--fork"] + (["--mount-proc"] if mount_proc else [])
    r = subprocess.run(unshare + [str(TRACE), "--rt", "-d", "2s"], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rtsup-trace: PID namespace: "), lines
    assert r.stdout == ""


# A loop of N sleeps to absolute 2 ms deadlines (Python 3.11's time.sleep is a
# clock_nanosleep(TIMER_ABSTIME)), then exec of the same program with the next
# count; or, halfway, PR_SET_NAME to a new name or a move to another cgroup.
# The loops sleep to their own absolute releases (clock_nanosleep with
# TIMER_ABSTIME through ctypes): time.sleep(t - now) would request its own
# clock read + the time left, and a preemption before it would shift that
# release and the period's settling (test_real_programs.py has that race).
SLEEP_UNTIL_PY = r'''
import ctypes
class _Ts(ctypes.Structure):
    _fields_ = [("sec", ctypes.c_long), ("nsec", ctypes.c_long)]
# looked up and allocated once, before the loop: no page fault in a cycle
_nanosleep = ctypes.CDLL(None).clock_nanosleep
_ts = _Ts()
_ts_ref = ctypes.byref(_ts)
# one call through ctypes before the loop, as an RT program warms up: glibc
# refuses CLOCK_THREAD_CPUTIME_ID (3) without a syscall, so no delimiter
_nanosleep(3, 0, _ts_ref, None)
def sleep_until(t):  # CLOCK_MONOTONIC (time.monotonic's clock), TIMER_ABSTIME
    ns = int(t * 1e9)
    _ts.sec, _ts.nsec = divmod(ns, 10**9)
    _nanosleep(1, 1, _ts_ref, None)
'''

LOOP_PY = SLEEP_UNTIL_PY + r'''
import ctypes, os, signal, sys, time
# a test may end the loop early: SIGTERM is a clean exit (status 0)
signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
n, rest = int(sys.argv[1]), sys.argv[2:]
what, arg = rest[:2] if rest[:1] in (["--rename"], ["--move"]) else (None, None)
t = time.monotonic()
for i in range(n):
    if what == "--rename" and i == n // 2:
        ctypes.CDLL(None).prctl(15, arg.encode(), 0, 0, 0)  # PR_SET_NAME
    if what == "--move" and i == n // 2:
        with open(os.path.join(arg, "cgroup.procs"), "w") as f:
            f.write(str(os.getpid()))
    t += 0.002
    sleep_until(t)
if rest and not what:
    os.execv(sys.executable, [sys.executable, sys.argv[0]] + rest)
'''


def run_cmd_traced(tmp_path, cmd, trace_args=()):
    """rtsup-trace -j -- CMD: (summary, stderr) once the command ended."""
    r = subprocess.run([str(TRACE), "-j"] + list(trace_args) + ["--"] + cmd,
                       capture_output=True, text=True, timeout=120)
    objs = [json.loads(x) for x in r.stdout.splitlines() if x.strip()]
    summary = [o for o in objs if o.get("type") == "summary"]
    assert len(summary) == 1, r.stderr
    return summary[0], r.stderr


def test_exec_starts_the_cycles_again(tmp_path):
    """A thread that execs a new program: the cycle running at the exec is
    not the new program's (its loader's mmap and openat are no RT-unsafe
    loop) and the totals are the new program's (issue 12, item 6)."""
    prog = tmp_path / "loop.py"
    prog.write_text(LOOP_PY)
    n1, n2 = 300, 400
    # on one CPU: a SCHED_OTHER thread preempted in a cycle may be moved to
    # another, an unsafe migration the program did not make (4 in the rt-6.12
    # guest once, the only unsafe events of the run)
    cpu = str(max(os.sched_getaffinity(0)))
    summary, err = run_cmd_traced(tmp_path, ["taskset", "-c", cpu, "/usr/bin/python3", str(prog),
                                             str(n1), str(n2)])
    [t] = [t for t in summary["threads"] if t["mode"] == "delimiter"]
    tot = t["total"]
    # the first sleep of the new program opens its first cycle, its exit cuts the last
    assert n2 - 2 <= tot["cycles"] <= n2, (tot["cycles"], err)
    assert tot["unsafe"]["total"] == 0, (tot["unsafe"], tot.get("unsafe_syscalls"))


def test_rename_matches_the_rules_again(tmp_path):
    """PR_SET_NAME to a name a rule matches: the rule applies from then on
    (issue 12, item 6)."""
    prog = tmp_path / "loop.py"
    prog.write_text(LOOP_PY)
    new = unique_prefix() + "-new"
    cfg = tmp_path / "rules.yaml"
    cfg.write_text("rules:\n  - name: renamed\n    match: {thread: %s}\n    period: 2ms\n" % new)
    summary, err = run_cmd_traced(tmp_path, ["/usr/bin/python3", str(prog), "1500",
                                             "--rename", new], ["--config", str(cfg), "-i", "500ms"])
    [t] = [t for t in summary["threads"] if t["comm"] == new]
    assert t.get("rule") == "renamed", (t.get("rule"), err)


@pytest.mark.skipif(cgroup2_root() is None, reason="no cgroup v2 hierarchy mounted")
def test_cgroup_move_matches_the_rules_again(tmp_path):
    """A process moved to another cgroup that a rule matches: the rule
    applies from then on (issue 12, item 6)."""
    prog = tmp_path / "loop.py"
    prog.write_text(LOOP_PY)
    name = "rtsup-test-mv-%d" % os.getpid()
    cg = os.path.join(cgroup2_root(), name)
    os.mkdir(cg)
    cfg = tmp_path / "rules.yaml"
    cfg.write_text("rules:\n  - name: moved\n    match: {cgroup: /%s}\n    period: 2ms\n" % name)
    try:
        summary, err = run_cmd_traced(tmp_path, ["/usr/bin/python3", str(prog), "1500",
                                                 "--move", cg],
                                      ["--config", str(cfg), "-i", "500ms"])
    finally:
        os.rmdir(cg)
    [t] = [t for t in summary["threads"] if t["mode"] == "delimiter"]
    assert t.get("rule") == "moved", (t.get("rule"), err)


def spawn_with_pid(pid, cmd, tries=50):
    """Start cmd as process 'pid' (free again) through ns_last_pid; None when
    other programs on this machine keep taking the pid first."""
    for _ in range(tries):
        with open("/proc/sys/kernel/ns_last_pid", "w") as f:
            f.write(str(pid - 1))
        p = subprocess.Popen(cmd)
        if p.pid == pid:
            return p
        p.kill()
        p.wait()
    return None


def test_reused_tid_is_a_new_thread(tmp_path):
    """A process that exits and a new one that gets the same pid before the
    interval ends: the new one is tracked as a new thread, not as the dead
    one's entry (issue 12, item 6)."""
    prog = tmp_path / "loop.py"
    prog.write_text(LOOP_PY)
    # the first would loop 60 s; it ends (SIGTERM, a clean exit) once the
    # tracer is up, however long that took (an emulated guest on a loaded
    # host took more than the 6 s it once had)
    n1, n2 = 30000, 600
    first = subprocess.Popen(["/usr/bin/python3", str(prog), str(n1)])
    # one long interval: the dead thread's entry is not freed before the reuse
    tr = Trace(["--pid", str(first.pid), "-i", "60s"])
    second = None
    try:
        assert first.poll() is None, "the first program ended before the tracer started"
        time.sleep(0.5)  # a few of its cycles seen by the tracer
        first.terminate()
        assert first.wait(timeout=60) == 0
        second = spawn_with_pid(first.pid, ["/usr/bin/python3", str(prog), str(n2)])
        if second is None:
            pytest.skip("pid %d kept being taken by other programs" % first.pid)
        assert second.wait(timeout=60) == 0
        time.sleep(0.2)
        _, summary, err = tr.stop()
    finally:
        for p in (first, second):
            if p and p.poll() is None:
                p.kill()
        if tr.proc.poll() is None:
            tr.proc.kill()
    t = threads_by_tid(summary)[first.pid]
    # the second program's cycles (its first sleep opens the first, its exit cuts the last)
    assert n2 - 2 <= t["total"]["cycles"] <= n2, (t["total"]["cycles"], err)


# A second thread (not the leader) runs the loop of LOOP_PY, then execs it:
# the kernel gives it the leader's tid (de_thread), the leader exits.
EXEC_FROM_THREAD_PY = SLEEP_UNTIL_PY + r'''
import os, sys, threading, time
def run():
    t = time.monotonic()
    for i in range(int(sys.argv[2])):
        t += 0.002
        sleep_until(t)
    os.execv(sys.executable, [sys.executable, sys.argv[1], sys.argv[3]])
threading.Thread(target=run).start()
threading.Event().wait()
'''


def test_exec_from_a_thread_takes_the_leaders_tid(tmp_path):
    """A thread that is not the leader execs: it goes on with the leader's tid,
    whose entry says 'exited'; the new program is counted (issue 12, item 6)."""
    loop = tmp_path / "loop.py"
    loop.write_text(LOOP_PY)
    prog = tmp_path / "exec_from_thread.py"
    prog.write_text(EXEC_FROM_THREAD_PY)
    n1, n2 = 300, 400
    summary, err = run_cmd_traced(tmp_path, ["/usr/bin/python3", str(prog), str(loop),
                                             str(n1), str(n2)])
    leader = [t for t in summary["threads"] if t["tid"] == t["tgid"]]
    assert len(leader) == 1, summary["threads"]
    tot = leader[0]["total"]
    assert n2 - 2 <= tot["cycles"] <= n2, (tot["cycles"], err)


# --rt follows policy changes (include/rtfollow.h): a program that is not RT
# when the tracer starts, and becomes RT in one of the ways the kernel has,
# then runs n cycles of 2 ms; "drop" runs n as SCHED_FIFO, then 1 s later
# m as SCHED_OTHER. Its pid (the forked child's, for "fork") goes to argv[2].
RT_POLICY_PY = SLEEP_UNTIL_PY + r'''
import os, sys, time
mode, out, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
m = int(sys.argv[4]) if len(sys.argv) > 4 else 0
late = 0
def loop(k):
    """k cycles of 2 ms; returns how many sleeps, from the first, had their
    release already past (or under 0.1 ms ahead: the time from here to the
    kernel's timer) when called: those return without a context switch.
    Such sleeps after the first one ahead (a host that held the thread for
    a period) are counted in 'late': each ends no cycle."""
    global late
    t = time.monotonic()
    lead = None
    for i in range(k):
        t += 0.002
        ahead = t - time.monotonic() > 0.0001
        if lead is None and ahead:
            lead = i
        elif lead is not None and not ahead:
            late += 1
        sleep_until(t)
    return k if lead is None else lead
def say_late():
    with open(out + ".late", "w") as f:
        f.write(str(late))
def say(pid):
    with open(out + ".tmp", "w") as f:
        f.write(str(pid))
    os.rename(out + ".tmp", out)
fifo = os.sched_param(10)
if mode == "loop":  # the exec'd program: RT from its first instruction
    loop(n)
    sys.exit(0)
time.sleep(0.3)  # a while as SCHED_OTHER, seen by the tracer as no target
if mode == "setsched":
    os.sched_setscheduler(0, os.SCHED_FIFO, fifo)
    say(os.getpid())
    lead = loop(n)
    with open(out + ".lead", "w") as f:
        f.write(str(lead))
    say_late()
elif mode in ("fork", "fork-reset"):
    reset = os.SCHED_RESET_ON_FORK if mode == "fork-reset" else 0
    os.sched_setscheduler(0, os.SCHED_FIFO | reset, fifo)
    pid = os.fork()
    if pid == 0:
        say(os.getpid())
        loop(n)
        os._exit(0)
    _, st = os.waitpid(pid, 0)
    sys.exit(os.waitstatus_to_exitcode(st))
elif mode == "exec":
    os.sched_setscheduler(0, os.SCHED_FIFO, fifo)
    say(os.getpid())
    os.execv(sys.executable, [sys.executable, sys.argv[0], "loop", out, str(n)])
elif mode == "flip":
    # a reader woken by every byte of a pipe (activations: its switch-ins
    # are seen, not held) is RT for n bytes, not RT for 10 (20 ms), RT again
    # for n; the writer, this process, writes one every 2 ms
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(w)
        for policy, k in ((os.SCHED_FIFO, n), (os.SCHED_OTHER, 10), (os.SCHED_FIFO, n)):
            os.sched_setscheduler(0, policy, fifo if policy == os.SCHED_FIFO else
                                  os.sched_param(0))
            for _ in range(k):
                os.read(r, 1)
        say(os.getpid())
        os._exit(0)
    os.close(r)
    t = time.monotonic()
    for i in range(2 * n + 10):
        t += 0.002
        sleep_until(t)
        os.write(w, b"x")
    sys.exit(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]))
elif mode == "back":  # RT for n cycles, not RT for 1 s, RT again for n
    os.sched_setscheduler(0, os.SCHED_FIFO, fifo)
    say(os.getpid())
    loop(n)
    os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    time.sleep(1.0)  # five of the test's intervals: let go
    os.sched_setscheduler(0, os.SCHED_FIFO, fifo)
    late = 0  # the second run's only
    lead = loop(n)
    with open(out + ".lead", "w") as f:
        f.write(str(lead))
    say_late()
elif mode == "drop":
    os.sched_setscheduler(0, os.SCHED_FIFO, fifo)
    say(os.getpid())
    loop(n)
    os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    time.sleep(1.0)  # five of the test's intervals: let go before the m cycles
    loop(m)
'''


def cycle_trail(intervals, summary, pid, err):
    """A failure message's account of a thread's cycles: each interval it is
    in as +cycles/misses=running total [its checks' texts] {its events}, its
    summary total, the tracer's stderr"""
    trail = ["%d:+%d/%d=%d%s%s" % (i, x["interval"]["cycles"], x["interval"]["deadline_misses"],
                                   x["total"]["cycles"],
                                   "".join("[%s]" % c["text"] for c in x["status"]["checks"]),
                                   "".join("{%s}" % e["event"] for e in iv["events"]
                                           if e.get("tid") == pid))
             for i, iv in enumerate(intervals) for x in iv["threads"] if x["tid"] == pid]
    t = threads_by_tid(summary).get(pid, {})
    return "intervals %s\nsummary total %s\n%s" % (
        " ".join(trail), json.dumps({k: v for k, v in t.get("total", {}).items()
                                     if k not in ("hist",)}), err)


def prog_names(pid):
    """The names of the BPF programs a process holds"""
    return {p["name"] for p in held_progs(pid)}


# "policy": --rt's policy hook (fexit on __sched_setscheduler); "switch": the
# fallback where tp_btf (so fexit) is not there, forced with --raw-tp
RT_HOOKS = {"policy": [], "switch": ["--raw-tp"]}
# The RT guests' kernels (test_guest.py runs this file there) load and attach
# the hook; this development host's kernel refuses any fexit program (EPERM
# at load, a security module: even reading available_filter_functions is
# refused), so there "policy" runs the fallback too, found by the loader.
RT_HOOK_REQUIRED = EMULATED


def run_rt_policy(tmp_path, args, interval="200ms", hook="policy"):
    """rtsup-trace --rt, started before the program: (pid it wrote, its own
    pid, intervals, summary, stderr, whether the policy hook is attached)."""
    prog = tmp_path / "rtpol.py"
    prog.write_text(RT_POLICY_PY)
    out = tmp_path / "pid"
    tr = Trace(["--rt", "-i", interval] + RT_HOOKS[hook])
    p = None
    try:
        # the policy hook is there where the kernel allows it, never when not asked
        hooked = "rt_setsched" in prog_names(tr.proc.pid)
        assert hooked == (hook == "policy") if RT_HOOK_REQUIRED else not hooked or (
            hook == "policy")
        p = subprocess.Popen(["/usr/bin/python3", str(prog), args[0], str(out)] + args[1:])
        assert p.wait(timeout=300 if EMULATED else 60) == 0
        time.sleep(0.5)  # two intervals: the last one's read sees the end
        intervals, summary, err = tr.stop()
    finally:
        if p and p.poll() is None:
            p.kill()
        if tr.proc.poll() is None:
            tr.proc.kill()
    return int(out.read_text()), p.pid, intervals, summary, err, hooked


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_finds_a_thread_that_becomes_rt(tmp_path, hook):
    """SCHED_OTHER when the tracer starts, then sched_setscheduler to
    SCHED_FIFO: --rt follows it from then on (issue 19), all its cycles."""
    n = 500
    pid, _, intervals, summary, err, hooked = run_rt_policy(tmp_path, ["setsched", str(n)],
                                                            hook=hook)
    got = threads_by_tid(summary)
    assert pid in got, err
    # without the policy hook it is found at its first switch in as RT: the
    # sleeps before its first real block (their release already past, as
    # the program saw: a host that held the VM) open no cycle it can see
    lead = 0 if hooked else int((tmp_path / "pid.lead").read_text())
    # a sleep the host made late after that ends no cycle
    late = int((tmp_path / "pid.late").read_text())
    # its first sleep opens the first cycle, its exit cuts the last
    assert n - 2 - lead - late <= got[pid]["total"]["cycles"] <= n, "lead %d late %d\n%s" % (
        lead, late, cycle_trail(intervals, summary, pid, err))


# A SCHED_FIFO process with a big address space, on one CPU: n cycles of 2
# ms, then its exit, which frees the memory after the exit event where
# exit_mm follows the sched_process_exit tracepoint (6.18). argv: out, MiB,
# cpu, n
EXIT_BIG_PY = SLEEP_UNTIL_PY + r"""
import os, sys, time
out, mib, cpu, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
os.sched_setaffinity(0, {cpu})
mem = bytearray(b"\x01") * (mib << 20)  # every page touched: the exit frees them
os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
t, ahead = time.monotonic(), 0
for i in range(n):
    t += 0.002
    # a sleep whose release is past (or under 0.1 ms ahead) ends no cycle
    ahead += t - time.monotonic() > 0.0001
    sleep_until(t)
with open(out, "w") as f:
    f.write("%d %d %f" % (os.getpid(), ahead, time.monotonic()))
os._exit(0)
"""

# A higher SCHED_FIFO thread woken every ms on that CPU for argv[2] s: it
# preempts the exiting process, which then switches in again and again
HOG_PY = r"""
import os, sys, time
os.sched_setaffinity(0, {int(sys.argv[1])})
os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(20))
end = time.monotonic() + float(sys.argv[2])
while time.monotonic() < end:
    time.sleep(0.001)
"""


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_exiting_thread_is_not_found_again(tmp_path, hook):
    """A thread's exit event comes before its process frees its memory; a
    sample in between reaps its entry, and the task still switches in while
    it frees. Without the policy hook --rt found it at such a switch-in and
    started it anew as a thread that no exit ends; the model then dropped
    the one with the cycles for it (rt-6.12, CI: 498 cycles reported as 8;
    here 98 as 1, 3 runs of 3 before the fix, 0 of 3 after). A task in
    do_exit is no new RT thread (rtfollow.h, rt_on_switch_in). Kernels
    before the exit event moved ahead of exit_mm (the RT guests' 6.1 and
    6.12) free the memory before it: there this test cannot open the window,
    which only a block later in do_exit opens (closing files: the CI's)."""
    n, cpu = 100, max(os.sched_getaffinity(0))
    mib = 1024 if EMULATED else 4096  # the guests have 2 GiB: 384 MiB freed in 0.13 s there
    for name, text in (("big.py", EXIT_BIG_PY), ("hog.py", HOG_PY)):
        (tmp_path / name).write_text(text)
    out = tmp_path / "exit"
    tr = Trace(["--rt", "-i", "50ms"] + RT_HOOKS[hook])
    hog = p = None
    try:
        hog = subprocess.Popen(["/usr/bin/python3", str(tmp_path / "hog.py"), str(cpu), "600"])
        p = subprocess.Popen(["/usr/bin/python3", str(tmp_path / "big.py"), str(out), str(mib),
                              str(cpu), str(n)])
        assert p.wait(timeout=300 if EMULATED else 60) == 0
        reaped = time.monotonic()
        time.sleep(0.3)  # a few intervals after the end
        intervals, summary, err = tr.stop()
    finally:
        for x in (p, hog):
            if x and x.poll() is None:
                x.kill()
                x.wait()
        if tr.proc.poll() is None:
            tr.proc.kill()
    pid, ahead, exit_at = out.read_text().split()
    pid, ahead, exit_s = int(pid), int(ahead), reaped - float(exit_at)
    # the race needs samples while it frees: else this test says nothing
    assert exit_s > 0.15, "its exit took %.3f s, 3 intervals at least were needed" % exit_s
    news = [i for i, iv in enumerate(intervals) for e in iv["events"]
            if e.get("tid") == pid and e["event"] == "new_thread"]
    exits = [i for i, iv in enumerate(intervals) for e in iv["events"]
             if e.get("tid") == pid and e["event"] == "exit"]
    trail = cycle_trail(intervals, summary, pid, err)
    assert len(exits) == 1 and len(news) <= 1 and all(i <= exits[0] for i in news), trail
    # its first sleep opens the first cycle, its exit cuts the last; a sleep
    # whose release was past when called (a host that held it) ends none
    got = threads_by_tid(summary)[pid]["total"]["cycles"]
    assert ahead - 2 <= got <= n, "%d sleeps ahead\n%s" % (ahead, trail)


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_follows_a_thread_back_in_rt(tmp_path, hook):
    """SCHED_FIFO, SCHED_OTHER for 20 ms, SCHED_FIFO again, inside 1 s
    intervals: let go when it leaves (by the policy hook, or at a switch-in
    it is seen at, rtfollow.h), then followed anew. Without the policy hook
    the switch-in that found it RT again went on with the let-go entry,
    which userspace then reported as "left RT (policy SCHED_FIFO)" and
    dropped. A sample inside the 20 ms may say it left, with SCHED_OTHER:
    true then (a 2 % chance). It is followed at its end."""
    n = 250
    pid, _, intervals, summary, err, _ = run_rt_policy(tmp_path, ["flip", str(n)],
                                                       interval="1s", hook=hook)
    left = [c["text"] for iv in intervals + [summary] for x in iv["threads"]
            if x["tid"] == pid for c in x["status"]["checks"] if "left RT" in c["text"]]
    assert all("SCHED_OTHER" in x for x in left), (left, err)
    t = threads_by_tid(summary).get(pid)
    assert t and not t.get("left_rt"), (t, err)


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_follows_a_thread_back_after_it_was_let_go(tmp_path, hook):
    """A periodic SCHED_FIFO thread goes SCHED_OTHER for 1 s, is let go (its
    entry dropped), and comes back to SCHED_FIFO: followed anew, all its
    second run's cycles. Without the policy hook its switch-ins were held
    for good (its tid's wakemask bit stayed clear once its entry was gone),
    so the per-switch policy read never saw it come back."""
    n = 500
    pid, _, intervals, summary, err, hooked = run_rt_policy(tmp_path, ["back", str(n)],
                                                            hook=hook)
    left = [c["text"] for iv in intervals for x in iv["threads"] if x["tid"] == pid
            for c in x["status"]["checks"] if "left RT" in c["text"]]
    assert left == ["left RT (policy SCHED_OTHER): no longer a --rt target"], (left, err)
    t = threads_by_tid(summary).get(pid)
    assert t and not t.get("left_rt"), cycle_trail(intervals, summary, pid, err)
    lead = 0 if hooked else int((tmp_path / "pid.lead").read_text())
    # and a sleep the host made late after that ends no cycle (CI 103: 497
    # of 500 beside 4 ms of machine latency, lead 0)
    late = int((tmp_path / "pid.late").read_text())
    assert n - 2 - lead - late <= t["total"]["cycles"] <= n, "lead %d late %d\n%s" % (
        lead, late, cycle_trail(intervals, summary, pid, err))


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_finds_the_rt_child_of_a_fork(tmp_path, hook):
    """An RT thread forks: the child inherits SCHED_FIFO without a
    sched_setscheduler of its own and is followed from its first cycle."""
    n = 500
    pid, _, intervals, summary, err, _ = run_rt_policy(tmp_path, ["fork", str(n)], hook=hook)
    got = threads_by_tid(summary)
    assert pid in got, err
    assert n - 2 <= got[pid]["total"]["cycles"] <= n, cycle_trail(intervals, summary, pid, err)


def test_rt_skips_a_child_reset_on_fork(tmp_path):
    """SCHED_FIFO | SCHED_RESET_ON_FORK: the child starts as SCHED_OTHER and
    is no target, its parent is."""
    pid, parent, _, summary, err, _ = run_rt_policy(tmp_path, ["fork-reset", "200"])
    got = threads_by_tid(summary)
    assert pid not in got, got[pid]
    assert parent in got, err


@pytest.mark.parametrize("hook", list(RT_HOOKS))
def test_rt_follows_an_rt_program_across_exec(tmp_path, hook):
    """RT, then exec of a new program (as chrt does): the new program is
    followed, its cycles counted from its start."""
    n = 500
    pid, _, _, summary, err, _ = run_rt_policy(tmp_path, ["exec", str(n)], hook=hook)
    got = threads_by_tid(summary)
    assert pid in got, err
    assert n - 2 <= got[pid]["total"]["cycles"] <= n, (got[pid]["total"], err)


def test_rt_lets_go_of_a_thread_that_leaves_rt(tmp_path):
    """SCHED_FIFO for n cycles, then SCHED_OTHER for m: --rt reports once
    that it left RT (STALE, no exit, no error) and stops following it."""
    n, m = 500, 1000
    pid, _, intervals, summary, err, _ = run_rt_policy(tmp_path, ["drop", str(n), str(m)])
    t = threads_by_tid(summary)[pid]
    assert t.get("left_rt") is True, t
    # no exit reported: the one exception is that it left RT. (The 2 ms loop
    # may miss deadlines on a busy or emulated machine: the timing checks
    # judge those like any other thread's.)
    exc = [c for c in t["status"]["checks"] if c["check"] == "exception"]
    assert [(c["level"], c["text"]) for c in exc] == [
        ("STALE", "left RT (policy SCHED_OTHER): no longer a --rt target")], exc
    # The kernel marks it at the policy change, userspace lets it go at its
    # next read of the map, one interval later (200 ms): the program waits
    # 1 s before its m SCHED_OTHER cycles, none of which may count. The
    # second after the drop is one more cycle (its sleep is a delimiter).
    cyc = t["total"]["cycles"]
    assert n - 2 <= cyc <= n + 1, (cyc, err)
    # not in the intervals after the one that reported it
    seen = [i for i, iv in enumerate(intervals) if any(x["tid"] == pid for x in iv["threads"])]
    assert seen and seen == list(range(seen[0], seen[-1] + 1)), seen
    assert seen[-1] < len(intervals) - 3, (seen, len(intervals))


# a thread's row: TID, COMM (15 wide), POL/PRI or "exited", CYCLES
TABLE_ROW = re.compile(r"^ *\d+ .{15} (\S+/-?\d+|exited) +\d+ ")


def table_run(tmp_path, nthreads, extra):
    """rtsup-trace's table (not JSON) over a generator of nthreads threads
    that runs about 2 s and is then parked: [(live threads in the title,
    [(tid, status, policy or 'exited')], cut)] per interval, and the
    summary's table alike."""
    go = tmp_path / "go"
    # 40 threads at 100 Hz (20 Hz emulated, where 100 Hz overwhelms the guest)
    period = 50000 if EMULATED else 10000
    lg = Loadgen(tmp_path, ["-n", str(nthreads), "-P", str(period), "-w", "100",
                            "-c", str(2000000 // period), "-r", "50", "--wait-file", str(go)])
    tr = subprocess.Popen([str(TRACE), "-p", str(lg.pid), "-i", "500ms", "--color", "never"]
                          + extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert "tracing with" in tr.stderr.readline()
        go.touch()
        lg.summary()
        time.sleep(1.2)  # two intervals with the threads parked
        tr.send_signal(__import__("signal").SIGINT)
        out, err = tr.communicate(timeout=60)
    finally:
        lg.stop()
        if tr.poll() is None:
            tr.kill()
    assert tr.returncode == 0, err
    tables, cur = [], None
    for line in out.splitlines():
        if line.startswith("rtsup-trace "):
            # an interval's title counts the threads alive, the summary's all
            m = re.search(r"  threads (\d+)  |: (\d+) threads,", line)
            cur = [int(m.group(1) or m.group(2)), [], 0]
            tables.append(cur)
        elif cur and TABLE_ROW.match(line):
            f = line.split()
            cur[1].append((int(f[0]), f[-1], TABLE_ROW.match(line).group(1)))
        elif cur and "more threads, all OK (--all shows every thread)" in line:
            cur[2] = int(line.split("...")[1].split()[0])
    assert tables, out
    return lg.pid, tables, out


def test_table_shows_not_ok_and_the_worst_10(tmp_path):
    """40 threads: each interval's table lists every thread that is not OK,
    10 of the OK ones and one line for the rest (issue 19)."""
    n = 40
    pid, tables, out = table_run(tmp_path, n, [])
    for live, rows, cut in tables:
        ok = [tid for tid, st, _ in rows if st == "OK"]
        # the title counts the threads alive; all of them are in the model
        assert len(rows) + cut == live, (live, rows, cut)
        assert len(ok) == min(10, live - (len(rows) - len(ok))), rows
        assert (cut > 0) == (live > len(rows)), (live, rows, cut)
    # with the generator's 41 threads alive and fewer than 31 not OK, a cut
    assert any(cut for live, rows, cut in tables if live == n + 1), out


def test_table_all_shows_every_thread(tmp_path):
    """--all: every thread in every interval, no cut line."""
    n = 40
    pid, tables, out = table_run(tmp_path, n, ["--all"])
    assert any(live == n + 1 for live, _, _ in tables), out
    for k, (live, rows, cut) in enumerate(tables):
        # an interval's title counts the threads alive; its rows are those and
        # the threads that exited in it ('exited', shown once). The summary's
        # title counts every thread it has, dead or alive.
        alive = [r for r in rows if r[2] != "exited" or k == len(tables) - 1]
        assert cut == 0 and len(alive) == live, (live, len(rows), cut, out)


def test_json_threads_active_lists_what_ran(tmp_path):
    """--json-threads active: while the generator runs its threads are in
    the intervals, once they are parked (no cycle, no switch) they are
    counted in threads_not_listed; the summary lists them all."""
    n = 8
    go = tmp_path / "go"
    lg = Loadgen(tmp_path, ["-n", str(n), "-c", str(1500000 // PERIOD_US),
                            "--wait-file", str(go)])
    tr = Trace(["-p", str(lg.pid), "-i", "300ms", "--json-threads", "active"])
    try:
        go.touch()
        truth = lg.summary()
        time.sleep(1.5)  # parked for five intervals
        intervals, summary, err = tr.stop()
    finally:
        lg.stop()
    workers = {t["tid"] for t in truth["threads"]}
    listed = [{t["tid"] for t in i["threads"]} for i in intervals]
    assert any(workers <= s for s in listed), listed
    # the last intervals: all parked, none listed, every one counted
    for i in intervals[-2:]:
        assert not workers & {t["tid"] for t in i["threads"]}, i["threads"]
        assert i["threads_not_listed"] >= n, i["threads_not_listed"]
    assert workers <= set(threads_by_tid(summary)), err


def verified_insns(pid):
    """The verifier's walk of each program a process holds, by name"""
    return {p["name"]: p.get("verified_insns", 0) for p in held_progs(pid)}


def sys_prog_runs(pid):
    """Runs of the syscall programs a tracer holds, summed (bpf_stats'
    run_cnt): the per-syscall stubs and bodies, or raw_syscalls' two. One
    bpftool for all: each process started meanwhile makes syscalls too."""
    return sum(p.get("run_cnt", 0) for p in held_progs(pid)
               if p.get("name", "").startswith("sys_"))


_AUTO = []


def auto_hooks():
    """What --syscall-hooks auto picks on this kernel: "per-syscall" where
    it loads and attaches them, "raw_syscalls" elsewhere (run once: a stop
    with per-syscall hooks costs 20 s or more in an emulated guest)"""
    if not _AUTO:
        r = subprocess.run([str(TRACE), "--syscall-hooks", "auto", "-p", "1", "-d", "0.1s",
                            "-j"], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr
        _AUTO.append(json.loads(r.stdout.splitlines()[-1])["supervisor"]["syscall_hooks"])
    return _AUTO[0]


def test_per_syscall_refusal_is_one_line_and_auto_falls_back():
    """Where the kernel refuses fentry programs (this project's 2-vCPU host:
    EPERM from a security module), per-syscall says so in one line and
    exits 1, and auto traces on raw_syscalls; where it attaches them (the
    RT guests), auto uses them."""
    if auto_hooks() == "per-syscall":
        return
    assert auto_hooks() == "raw_syscalls"
    r = subprocess.run([str(TRACE), "--syscall-hooks", "per-syscall", "-p", "1", "-d", "0.1s",
                        "-j"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 1 and len(r.stderr.splitlines()) == 1, r.stderr
    assert r.stderr.startswith("rtsup-trace: --syscall-hooks per-syscall: the kernel refuses "
                               "fentry programs on syscalls"), r.stderr


def runs_per_getppid(pid, n=50000):
    """Runs of the tracer's syscall programs per getppid of a thread that is
    no target: a Python making n calls against the same Python making none,
    so that its start-up's syscalls and this measure's own cancel out (what
    other threads of the machine do meanwhile does not: a few hundred runs
    either way, under 0.01 a call)."""
    runs = []
    for k in (0, n):
        before = sys_prog_runs(pid)
        subprocess.run(["/usr/bin/python3", "-c",
                        "import os\nfor _ in range(%d): os.getppid()" % k], check=True)
        runs.append(sys_prog_runs(pid) - before)
    return (runs[1] - runs[0]) / n


def test_per_syscall_hooks_count_exactly_and_spare_other_threads(tmp_path):
    """--syscall-hooks per-syscall (fentry stubs on the classified syscalls,
    docs/design.md): every injected fault is counted exactly as with
    raw_syscalls, and a thread that is no target making a syscall no stub
    is on (getppid) runs none of our syscall programs, where raw_syscalls
    runs one per syscall. Needs a kernel that attaches fentry to syscalls:
    the RT guests (test_guest.py runs this file there)."""
    if auto_hooks() != "per-syscall":
        pytest.skip("this kernel refuses fentry programs on syscalls "
                    "(test_per_syscall_refusal_is_one_line_and_auto_falls_back): the RT "
                    "guests run this test")
    with open("/proc/sys/kernel/bpf_stats_enabled") as f:
        assert f.read().strip() == "1", "run counts need kernel.bpf_stats_enabled=1 " \
            "(scripts/vm-test pins it)"
    prefix = unique_prefix()
    cycles = 3000000 // PERIOD_US
    faults = ["-f", "mmap/100,thread=1", "-f", "openat@50,thread=0", "-f", "write@80,thread=0",
              "-f", "block@120", "-f", "pagefault:2@60"]
    tr = Trace(["--syscall-hooks", "per-syscall", "--no-overhead"]
               + ["--comm=%s-%d" % (prefix, i) for i in range(2)])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "2", "-P", str(PERIOD_US), "-w", "100",
                            "-c", str(cycles)] + faults)
    try:
        truth = lg.summary()
        # getppid: what a syscall no stub is on costs the tracer's programs
        per_runs = runs_per_getppid(tr.proc.pid)
        walked = verified_insns(tr.proc.pid)
        time.sleep(0.2)
        # the stop releases each stub's trampoline: 20-30 s in an emulated guest
        intervals, summary, _ = tr.stop(timeout=300)
    finally:
        lg.stop()
        if tr.proc.poll() is None:
            tr.proc.kill()
    assert summary["supervisor"]["syscall_hooks"] == "per-syscall"
    # the start-up's walk: fifty stubs of 19 and two bodies, within the bounds above
    assert "sys_in_prog" in walked and "sys_enter_btf" not in walked, walked
    assert max(walked.values()) <= VERIFIED_PER_PROGRAM, walked
    assert sum(walked.values()) <= VERIFIED_TOTAL, walked
    got = threads_by_tid(summary)
    skipped_entries = 0
    for t in truth["threads"]:
        # blocks are sched_switch's, not the syscall hooks': the injected ones,
        # futex waits, exactly. But a fentry program runs preemptible (on
        # PREEMPT_RT, and on any preemptible kernel): preempted inside the
        # delimiter's stub, it makes the kernel skip that stub for the next
        # task on the CPU to enter the same syscall (its recursion check),
        # and a target whose delimiter entry was skipped sleeps in it "inside
        # its cycle": a block in clock_nanosleep (CI 43: 2 such, where the
        # generator made 1). A skipped return rtsup-trace recovers at the
        # thread's next syscall (health.hook_runs_recovered). The kernel
        # counts each skipped run, and so does rtsup-trace
        # (health.hook_runs_missed): the two kinds together are no more;
        # raw_syscalls' tracepoints run non-preemptible and skip none
        # (docs/design.md, "Runs the kernel skips")
        where = block_events(intervals, t["tid"])
        assert where.get("futex", 0) == t["blocks"], where
        assert set(where) <= {"futex", DELIM}, where
        skipped_entries += where.get(DELIM, 0)
        check_thread_matches(t, got[t["tid"]], extra_blocks=where.get(DELIM, 0))
    health = summary["health"]
    assert skipped_entries + health["hook_runs_recovered"] <= health["hook_runs_missed"], health
    # the same measure sees raw_syscalls' two runs per syscall: the check can fail
    raw = Trace(["--syscall-hooks", "raw", "--no-overhead", "--comm", prefix + "-none"])
    try:
        raw_runs = runs_per_getppid(raw.proc.pid)
    finally:
        raw.stop(timeout=300)
    print("getppid of a thread that is no target: %.4f runs of our syscall programs a call "
          "with per-syscall hooks, %.4f on raw_syscalls" % (per_runs, raw_runs))
    assert raw_runs >= 1.9, raw_runs
    # none: the rest is the other threads' hooked syscalls, under 0.01 a call
    assert per_runs < 0.05, per_runs
