# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""The bad-input and fault matrix (issue 16, docs/reliability.md): each row
checks a one-line error (file:line where there is a file), the documented
exit code (docs/rtsup-trace.8, EXIT STATUS) and that nothing recorded so far
is lost. Where a generator or a small program of our own did something, the
counts are compared with what it did."""
import json
import os
import random
import re
import signal
import socket
import subprocess
import threading
import time
from pathlib import Path

import pytest

from conftest import (BUILD, CLEAN_DEFAULTS, EMULATED, LEVEL_CHANGE, LOADGEN, PERIOD_US, TRACE,
                      Loadgen, Trace, proc_status, prog_ids, threads_by_tid, unique_prefix)

pytestmark = pytest.mark.usefixtures("bpf")

PROGS = BUILD / "progs"


def run_cli(args, timeout=60, **kw):
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout, **kw)


def one_line(stderr, start):
    """The only line on stderr, which starts with 'start'."""
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(start), lines
    return lines[0]


def reports(out):
    """The interval reports and the summary of -j output (level changes,
    JSON lines too, aside); the summary is None when there is none."""
    objs = [json.loads(x) for x in out.splitlines() if x.strip()]
    summary = [o for o in objs if o.get("type") == "summary"]
    return ([o for o in objs if o.get("type") == "interval"],
            summary[-1] if summary else None)


def gaps(intervals):
    """The length of each interval as the tool's own clock saw it; the last,
    ended by the stop, is shorter unless it came late too."""
    return [i["interval_s"] for i in intervals]


def lateness(intervals, period):
    """How late each interval but the last (ended by the stop) came against
    the main loop's own schedule: slots at start + k * period; a slot the
    loop is already past when an interval ends is skipped, and the next is
    one period from then (main.c). Never negative: the loop samples only
    once its slot has come."""
    due, late = period, []
    for i in intervals[:-1]:
        t = i["elapsed_s"]
        late.append(round(t - due, 6))
        due += period
        if due <= t:
            due = t + period
    return late


# --- privileges and the kernel -------------------------------------------

def test_not_root():
    """An ordinary user (nobody, via setpriv): one line that says what to do."""
    r = run_cli(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups",
                 str(TRACE), "-p", "1", "-d", "1s"])
    assert r.returncode == 1
    one_line(r.stderr, "rtsup-trace: not allowed to load BPF programs: run as root or "
             "grant CAP_BPF and CAP_PERFMON")
    assert r.stdout == ""


def test_no_btf():
    """A kernel without BTF, as rtsup-trace sees it: /sys/kernel/btf hidden
    under an empty tmpfs in a private mount namespace (the machine's own
    mounts are untouched)."""
    r = run_cli(["unshare", "--mount", "--propagation", "private", "sh", "-c",
                 'mount -t tmpfs none /sys/kernel/btf && exec "$0" -p 1 -d 1s', str(TRACE)])
    assert r.returncode == 1
    one_line(r.stderr, "rtsup-trace: this kernel has no BTF (/sys/kernel/btf/vmlinux): "
             "it needs CONFIG_DEBUG_INFO_BTF=y")


@pytest.mark.parametrize("how,cmd,msg", [
    # root without any capability: refused before loading
    ("capabilities dropped", ["setpriv", "--inh-caps=-all", "--bounding-set=-all"],
     "rtsup-trace: not allowed to load BPF programs"),
    # root of a user namespace holds every capability there, and the kernel
    # still refuses bpf(): what lockdown, seccomp or an LSM do too
    ("user namespace", ["unshare", "--user", "--map-root-user"],
     "rtsup-trace: the kernel refuses BPF: Operation not permitted"),
])
def test_bpf_forbidden(how, cmd, msg):
    """BPF disallowed. kernel.unprivileged_bpf_disabled only concerns users
    without CAP_BPF (the row above); lockdown cannot be set on this machine
    without a reboot (and never lifted), so the kernel's refusal is made
    real with a user namespace."""
    r = run_cli(cmd + [str(TRACE), "-p", "1", "-d", "1s"])
    assert r.returncode == 1, (how, r.stderr)
    one_line(r.stderr, msg)


def test_raw_tp_forced(tmp_path):
    """The raw_tp fallback (--raw-tp, what a kernel without tp_btf gets):
    the banner says so and the counts stay exact."""
    prefix = unique_prefix()
    tr = Trace(["--raw-tp", "--comm", prefix + "-0"])
    assert "raw tracepoint" in tr.banner
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", "1000", "-f", "overrun@100",
                            "-f", "mmap@200"])
    try:
        truth = lg.summary()
        time.sleep(0.2)
        _, summary, _ = tr.stop()
    finally:
        lg.stop()
    t = truth["threads"][0]
    got = threads_by_tid(summary)[t["tid"]]["total"]
    assert got["cycles"] == t["cycles"]
    assert got["unsafe_syscalls"].get("mmap") == t["syscalls"]["mmap"]
    assert got["overruns"] >= t["overruns"]
    assert summary["health"]["ok"], summary["health"]


# --- targets ---------------------------------------------------------------

@pytest.mark.parametrize("args,msg", [
    (["--pid", "4194000"], "rtsup-trace: --pid 4194000: no such process"),
    (["--tid", "4194000"], "rtsup-trace: --tid 4194000: no such thread"),
    (["--cgroup", "/sys/fs/cgroup/no-such-group"],
     "rtsup-trace: --cgroup '/sys/fs/cgroup/no-such-group'"),
])
def test_unknown_target_refused(args, msg):
    """A pid, tid or cgroup that does not exist: exit 1, one line."""
    r = run_cli([str(TRACE)] + args + ["-d", "1s"])
    assert r.returncode == 1
    one_line(r.stderr, msg)
    assert r.stdout == ""


@pytest.mark.parametrize("args,note", [
    (["--comm", "no-such-thing"], None),
    (["--unit", "no-such-unit-x.service"],
     "rtsup-trace: --unit no-such-unit-x.service: not running; waiting for it"),
])
def test_unknown_name_waits(args, note):
    """A name (--comm, --unit) may come later: the run waits for it, reports
    no thread, exits 0 with its health whole."""
    r = run_cli([str(TRACE), "-j", "-d", "1s", "--no-overhead"] + args)
    assert r.returncode == 0, r.stderr
    lines = r.stderr.strip().splitlines()
    assert lines[0].startswith("rtsup-trace: tracing with"), lines
    assert lines[1:] == ([note] if note else []), lines
    _, summary = reports(r.stdout)
    assert summary["threads"] == []
    assert summary["health"]["ok"], summary["health"]


def test_target_exits_at_start_up(tmp_path):
    """-- CMD that fails at once: its exit status is ours, and its one thread
    is in the summary; a command that cannot run: 127, one line of why."""
    r = run_cli([str(TRACE), "-j", "--no-overhead", "--", "/bin/false"])
    assert r.returncode == 1
    assert r.stderr.strip().splitlines()[-1] == "rtsup-trace: /bin/false exited with status 1"
    _, summary = reports(r.stdout)
    assert [(t["comm"], t["alive"], t["exit_code"]) for t in summary["threads"]] == \
        [("false", False, 1 << 8)]  # the kernel's exit code: status in bits 8-15
    r = run_cli([str(TRACE), "--no-overhead", "--", str(tmp_path / "missing")])
    assert r.returncode == 127
    assert "rtsup-trace: cannot run '%s': No such file or directory" % (tmp_path / "missing") \
        in r.stderr.splitlines()


# --- load --------------------------------------------------------------------

# The issue asks for a minute at 10 000 threads a second; CI gets 8 s (the
# whole file has 2 minutes), `RTSUP_STORM_S=60` runs the minute.
STORM_S = int(os.environ.get("RTSUP_STORM_S", "8"))


def loop_sleeps(pid):
    """How often the tool's loop (its main thread) slept: it sleeps only to
    wait for the kernel's events or its next interval."""
    return proc_status(pid, "voluntary_ctxt_switches")


def test_thread_storm(tmp_path):
    """10 000 threads created and gone a second, next to a periodic thread:
    the periodic thread's counts stay exact, every interval comes on time
    (before the fix one took 9.9 s), memory stays bounded, and what the
    thread map could not hold is counted in the health."""
    prefix = unique_prefix()
    out = tmp_path / "storm.json"
    # the storm by its program's name at exec: a --comm process has all its
    # threads followed from their fork
    # stdout to a file: the storm's intervals are 2-7 MB of JSON each, and a
    # pipe would time pytest's reader thread, not the loop
    tr = Trace(["-i", "500ms", "--no-overhead", "--comm", prefix + "-0", "--comm",
                "thread_storm"], out_file=tmp_path / "trace.jsonl")
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", str(STORM_S * 1000000 //
                                                                     PERIOD_US)])
    sleeps0, t0 = loop_sleeps(tr.proc.pid), time.monotonic()
    storm = subprocess.run([str(PROGS / "thread_storm"), "thread_storm", "10000",
                            str(STORM_S), str(out)], timeout=STORM_S * 10)
    sleeps, storm_s = loop_sleeps(tr.proc.pid) - sleeps0, time.monotonic() - t0
    try:
        truth = lg.summary()
        hwm = proc_status(tr.proc.pid, "VmHWM")
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    assert storm.returncode == 0
    made = json.loads(out.read_text())
    assert made["created"] == 10000 * STORM_S and made["failed"] == 0
    t = truth["threads"][0]
    assert threads_by_tid(summary)[t["tid"]]["total"]["cycles"] == t["cycles"]
    # the loop's own work stays of the fixed kind: each interval it reads up
    # to 4096 thread entries and writes every thread of the interval. Before
    # the fix one interval took 9.9 s of CPU (the model kept its ~10 KiB
    # entries in the array it sorted: the sorts moved ~1 GB an interval).
    # This is no speed claim (make bench measures the loop at 1000 threads):
    # its CPU time is the machine's as much as ours. Quiet, 0.15 s an interval
    # on average and 0.20 s at most. A late interval holds more threads, so
    # the loop's work must not grow faster than the interval: a CI machine
    # saw 0.2, 0.5, 0.7, 0.9, 1.9 s, each interval later than the last, when
    # the loop was woken for every event (~14 000 a second) and pruned its
    # untracked threads by a walk that began again at bucket 0 after each
    # delete (mapprune.c). The bound is the bug's scale over five. What a
    # slow interval does to the schedule is asserted just below.
    loop = [(i["supervisor"]["loop_cpu_s"], i["supervisor"]["loop_wait_s"])
            for i in intervals]
    cpu = [c for c, _ in loop]
    assert max(cpu) < 9.9 / 5, loop
    # and the schedule held: no slot was lost but after a late interval, none
    # came early, none late by more than the gap bound allows, once the time
    # the loop waited for a CPU is taken off. The race: the storm's threads
    # and the loop share 2 CPUs, so the loop can wait on a run queue (CI runs
    # saw intervals 0.88 s and 1.03 s late); the kernel's schedstat of the
    # loop's own thread counts that wait (loop_wait_s).
    g = gaps(intervals)
    assert all(g[k] - loop[k][1] < 1.5 for k in range(len(g))), (g, loop)
    # How late each interval came is the loop's own doing: its slot is always
    # after the last interval's end (main.c), so an interval is late only by
    # the loop's busy time since then, its CPU and its run-queue wait. 50 ms
    # for what schedstat does not count: the poll's timeout rounds up to the
    # next ms, the timer's slack and its expiry latency (ms-scale spikes on
    # these machines), and the page-cache writes of the output.
    late = lateness(intervals, 0.5)
    assert all(0 <= x <= loop[k][0] + loop[k][1] + 0.05 for k, x in enumerate(late)), \
        (late, loop)
    # the loop is not woken for each event: it wakes for its polls (every
    # 100 ms at least), its intervals, and a quarter-full event buffer
    # (rb_wakeup: 2 MiB / 4 of 424-byte records). Here the terms give 240
    # sleeps in 8 s and the loop slept 301-307 times (the rest not
    # explained); the bound is three times the terms. Woken for each
    # event, as before the fix, it slept 85 386 times (350 times the terms).
    nev = sum(len(i.get("events", [])) for i in intervals) + summary["health"]["events_not_kept"]
    woken = storm_s * (1 / 0.1 + 1 / 0.5) + nev * 424 / (2 * 1024 * 1024 / 4)
    assert sleeps <= 3 * woken, (sleeps, woken, nev, storm_s)
    # the model keeps MODEL_KEEP_DEAD (1024) dead threads, ~9 KiB each
    assert hwm < 200 * 1024, hwm
    # the storm was followed: every thread it made is in the model (the
    # last MODEL_KEEP_DEAD of the dead are kept), or was counted untracked
    storm_threads = [x for x in summary["threads"] if x["comm"] == "thread_storm"]
    assert len(storm_threads) >= 1000, len(storm_threads)
    h = summary["health"]
    assert h["untracked_threads"] <= made["created"], h
    assert h["ok"] == (h["untracked_threads"] == 0 and h["lost_events"] == 0), h


def test_start_up_memory_given_back(tmp_path):
    """What the start-up freed goes back to the kernel before the first
    interval: the start-up reads the kernel's BTF whole (libbpf, for each
    object it relocates) and frees it, and glibc kept those pages (RssAnon
    12.9 MiB with five targets on the 6.18 host, 1.7 MiB given back)."""
    lg = Loadgen(tmp_path, ["-n", "5", "-c", "20"])
    tr = Trace(["-i", "200ms", "--no-overhead", "--pid", str(lg.pid)])
    try:
        # two intervals out: the loop runs, past the start-up
        end = time.monotonic() + (120 if EMULATED else 30)
        while sum('"interval"' in x for x in tr.out) < 2 and time.monotonic() < end:
            time.sleep(0.05)
        anon = proc_status(tr.proc.pid, "RssAnon")
        lg.summary()
        tr.stop()
    finally:
        lg.stop()
    btf_kb = Path("/sys/kernel/btf/vmlinux").stat().st_size // 1024
    # the bound is the BTF's raw size: kept, its pages alone (and libbpf's
    # index of it) are more; given back, the rest (the models of five
    # threads, the libraries' own data) is a fraction of it
    assert anon < btf_kb, (anon, btf_kb)


def test_comm_leader_rename_brings_its_threads(tmp_path):
    """A process whose leader names itself (prctl) like a --comm target
    after the tool started: the start-up scan would take such a process
    whole, so the kernel side does too, and every thread it then creates is
    followed (before the fix: only the leader)."""
    name = "rn-" + unique_prefix()
    out = tmp_path / "storm.json"
    tr = Trace(["--comm", name, "--no-overhead"])
    storm = subprocess.run([str(PROGS / "thread_storm"), name, "1000", "1", str(out)],
                           timeout=60)
    time.sleep(0.3)
    _, summary, _ = tr.stop()
    assert storm.returncode == 0
    made = json.loads(out.read_text())["created"]
    ours = [t for t in summary["threads"] if t["comm"] == name]
    # the leader and every thread it made (at most MODEL_KEEP_DEAD dead kept)
    assert len(ours) == made + 1 <= 1024, (len(ours), made, summary["health"],
                                           sorted(set(t["comm"] for t in summary["threads"])))


def test_max_threads_reached(tmp_path):
    """--max-threads 4 and 8 target threads: 4 tracked with exact counts, the
    other 4 counted once each, the map shown full."""
    prefix = unique_prefix()
    tr = Trace(["--max-threads", "4", "--no-overhead"] +
               ["--comm=%s-%d" % (prefix, i) for i in range(8)])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "8", "-c", "1000"])
    try:
        truth = lg.summary()
        time.sleep(0.2)
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    got = threads_by_tid(summary)
    ours = {t["tid"]: t for t in truth["threads"]}
    tracked = set(got) & set(ours)
    assert len(tracked) == 4, sorted(got)
    for tid in tracked:
        assert got[tid]["total"]["cycles"] == ours[tid]["cycles"]
    h = summary["health"]
    assert h["untracked_threads"] == 4, h
    fill = dict(h["thread_map"])
    # the entries the last read copied, whole or short: those that changed
    # (threadread.h, threadmem.h); a short copy refused is copied whole too
    assert 0 <= fill.pop("copied") + fill.pop("short") <= 4, h
    assert 0 <= fill.pop("short_refused") <= 4, h
    # those the read looked at: all, or those the hooks named (threadread.h)
    visited = fill.pop("visited")
    whole = fill.pop("whole")
    assert visited == 4 if whole else 0 <= visited <= 4, h
    # a whole read reads its tasks through the iterator, or in batches:
    # every task, or none (threadread.h, thread_read_tasks)
    batch, tasks = fill.pop("batch"), fill.pop("tasks")
    assert tasks in (0, 4) and (whole or (not batch and tasks == 0)), h
    # the task iterator walks every task only where the thread map's iterator
    # reads none (thread_walk_tasks); of the 4, those asked of the kernel one by one
    walk, asked = fill.pop("task_walk"), fill.pop("tasks_asked")
    assert not walk or summary["supervisor"]["task_attrs"] == "task_walk", summary["supervisor"]
    assert 0 <= asked <= 4, h
    assert fill == {"entries": 4, "capacity": 4, "fill_pct": 100.0, "near_full": True}, h
    assert not h["ok"]
    # every report carries it, and the counter never goes back
    counts = [i["health"]["untracked_threads"] for i in intervals] + [4]
    assert counts == sorted(counts)


def test_ring_buffer_overrun(tmp_path):
    """A thread mapping and unmapping a page 300 times a millisecond: more
    rare events than the ring buffer holds. The losses are counted; the
    cycles and the unsafe syscalls, aggregated in the kernel, stay exact;
    the intervals add up and come on time."""
    out = tmp_path / "flood.json"
    # the smallest ring (64 KiB, about 170 events): the default 2 MiB ring is
    # read faster than this flood fills it on an idle machine
    r = run_cli([str(TRACE), "-j", "-i", "500ms", "--no-overhead", "--event-buffer", "64K",
                 "--", str(PROGS / "unsafe_flood"), "flood", "1000", "300", str(out)],
                timeout=120)
    assert r.returncode == 0, r.stderr
    truth = json.loads(out.read_text())
    intervals, summary = reports(r.stdout)
    h = summary["health"]
    assert h["lost_events"] > 0 and not h["ok"], h
    assert h["lost_events"] == summary["lost_events"]
    t = threads_by_tid(summary)[truth["tid"]]
    # its 1000 sleeps bound 999 whole cycles (the last one ends in its exit)
    assert t["total"]["cycles"] == truth["cycles"] - 1
    assert t["total"]["unsafe_syscalls"]["mmap"] == 300 * t["total"]["cycles"]
    assert t["total"]["unsafe_syscalls"]["munmap"] == 300 * t["total"]["cycles"]
    assert sum(x["interval"]["cycles"] for i in intervals for x in i["threads"]) == \
        t["total"]["cycles"]
    # a poll stops consuming at its time, so the loop goes on reporting; what
    # is left of a late interval is the tool's wait for a CPU: it is
    # SCHED_OTHER next to the flood on 2 shared CPUs (seen on a quiet
    # machine: 0.54 s with the fix, 1.0 s without; at load 15: 1.54 s)
    assert max(gaps(intervals)) < 2.0, gaps(intervals)
    assert len(intervals) >= summary["elapsed_s"] / 0.5 - 2


# --- recording and replay -----------------------------------------------------

@pytest.fixture
def small_fs(tmp_path):
    """Mount a tmpfs with the given options at tmp_path/fs; unmounted after."""
    mounted = []

    def mount(opts):
        d = tmp_path / "fs"
        d.mkdir()
        subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(d)], check=True)
        mounted.append(d)
        return d
    yield mount
    for d in mounted:
        subprocess.run(["umount", str(d)], check=False)


def test_record_disk_full(tmp_path, small_fs):
    """The disk fills while recording: one line, the supervision goes on to
    its summary with exact counts, exit 1; the trace replays up to its last
    whole record and names the offset where it ends."""
    rec = small_fs("size=256k") / "run.rtsup"
    lg_out = tmp_path / "lg.json"
    # --hold: the generator parks its thread after its last cycle, so every
    # cycle is whole when -d ends the run (and the generator). The file
    # fills at about 0.5 MB/s (an event of ~420 bytes per mmap and munmap,
    # a cycle record per cycle): intervals of 100 ms put several interval
    # marks in 256 KiB, where 500 ms had put the first one near the end
    r = run_cli([str(TRACE), "-j", "-i", "100ms", "--no-overhead", "--record", str(rec),
                 "-d", "%ds" % (3 * PERIOD_US // 1000 + 2), "--", str(LOADGEN), "-s",
                 str(lg_out), "-n", "1", "-c", "3000", "-P", str(PERIOD_US), "-f", "mmap/2",
                 "--hold"], timeout=120)
    assert r.returncode == 1
    # the banner and level changes (a deadline miss on a noisy machine) aside
    lines = [x for x in r.stderr.splitlines() if not x.startswith("rtsup-trace: tracing") and
             not re.match(r"rtsup-trace: \d{4}-\d\d-\d\dT", x)]
    assert lines == ["rtsup-trace: --record: %s: write: No space left on device: "
                     "recording stopped, supervision goes on" % rec], lines
    truth = json.loads(lg_out.read_text())["threads"][0]
    _, summary = reports(r.stdout)
    assert threads_by_tid(summary)[truth["tid"]]["total"]["cycles"] == truth["cycles"]
    rp = run_cli([str(TRACE), "replay", "-j", str(rec)])
    assert rp.returncode == 1
    last = rp.stderr.strip().splitlines()[-1]
    assert last.startswith("rtsup-trace: %s: offset " % rec), last
    intervals, summary = reports(rp.stdout)
    assert summary is not None  # of the whole intervals it read
    assert any(i["threads"] for i in intervals)


def test_record_read_only(small_fs):
    """A read-only file system: exit 1 before anything is loaded."""
    rec = small_fs("ro,size=64k") / "run.rtsup"
    r = run_cli([str(TRACE), "-p", "1", "-d", "1s", "--record", str(rec)])
    assert r.returncode == 1
    one_line(r.stderr, "rtsup-trace: %s: Read-only file system" % rec)


def test_replay_damaged_traces(tmp_path):
    """A trace cut at 40 random places, and 20 copies with 1 000 bytes
    flipped at random offsets each: replay never crashes, exits 0 or 1, and
    a damaged record is named by its byte offset."""
    rec = tmp_path / "run.rtsup"
    r = run_cli([str(TRACE), "-j", "-i", "200ms", "--no-overhead", "--record", str(rec), "--",
                 str(LOADGEN), "-s", str(tmp_path / "lg.json"), "-n", "2", "-c", "600",
                 "-P", str(PERIOD_US), "-f", "mmap/50", "-f", "overrun/100"], timeout=120)
    assert r.returncode == 0, r.stderr
    data = rec.read_bytes()
    rnd = random.Random(16)
    cases = {"cut-%d" % n: data[:n] for n in sorted(rnd.sample(range(len(data)), 40))}
    for i in range(20):
        b = bytearray(data)
        for off in rnd.sample(range(len(b)), 1000):
            b[off] ^= 1 << rnd.randrange(8)
        cases["flip-%d" % i] = bytes(b)
    for name, blob in cases.items():
        bad = tmp_path / (name + ".rtsup")
        bad.write_bytes(blob)
        rp = run_cli([str(TRACE), "replay", "-j", str(bad)])
        assert rp.returncode in (0, 1), (name, rp.returncode, rp.stderr[-500:])
        if rp.returncode == 0:
            continue
        last = rp.stderr.strip().splitlines()[-1]
        assert last.startswith("rtsup-trace: %s: " % bad), (name, last)
        # past the header, every damage names its offset
        if "header" not in last and "magic" not in last and "version" not in last and \
                "empty file" not in last:
            assert "offset " in last or "cut short" in last, (name, last)
        bad.unlink()


# --- configuration reload -----------------------------------------------------

def test_sighup_reload_bad_files(tmp_path):
    """SIGHUP with a broken, an empty, a 10 MB and a 10 000-rule file: the
    broken and the too large ones are refused with one line (file:line) and
    the rules kept, the others taken; the run goes on, its counts exact."""
    prefix = unique_prefix()
    cfg = tmp_path / "rt.yaml"
    good = CLEAN_DEFAULTS + "rules:\n  - name: ctl\n    match: {thread: %s-0}\n" % prefix
    cfg.write_text(good)
    rules = "".join("  - name: r%d\n    match: {thread: \"x%d-*\"}\n    period: 1ms\n" %
                    (i, i) for i in range(10000))
    files = [
        ("broken", "defaults:\n  ewma_weight: 0.1\n  thresholds: [\n",
         "rtsup-trace: %s:4:1: " % cfg, False),
        ("empty", "", None, True),
        ("10 MB", ("#" + "x" * 99 + "\n") * 104858,
         "rtsup-trace: %s: cannot read: File too large" % cfg, False),
        ("10 000 rules", good + rules, None, True),
    ]
    tr = Trace(["--config", str(cfg), "--comm", prefix + "-0", "-i", "200ms"])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", "6000"])
    try:
        time.sleep(0.5)
        for name, text, err, ok in files:
            cfg.write_text(text)
            before = len(tr.err)
            tr.proc.send_signal(signal.SIGHUP)
            end = time.time() + 10
            while time.time() < end and not any("SIGHUP" in x for x in tr.err[before:]):
                time.sleep(0.05)
            # the reload's own lines, picked by kind: a noisy machine adds level
            # changes of any kind (a noisy run logged "WARN -> ERROR" here)
            new = [x.strip() for x in tr.err[before:] if not LEVEL_CHANGE.match(x.strip())]
            if ok:
                assert new == ["rtsup-trace: SIGHUP: reloaded %s" % cfg], (name, new)
            else:
                assert len(new) == 2 and new[0].startswith(err), (name, new)
                assert new[1] == "rtsup-trace: SIGHUP: keeping the previous rules", (name, new)
            assert tr.proc.poll() is None, name
        truth = lg.summary()
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    t = truth["threads"][0]
    assert threads_by_tid(summary)[t["tid"]]["total"]["cycles"] == t["cycles"]
    # a reload is parsed in the main loop: the 10 000 rules take ~0.4 s here
    # (--check-config's time), so one interval may be that much longer
    assert max(gaps(intervals)) < 0.2 + 1.0, gaps(intervals)


# --- Prometheus ---------------------------------------------------------------

def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def test_prometheus_port_taken():
    """The port is bound before any BPF is loaded: one line, exit 1."""
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    s.listen()
    port = s.getsockname()[1]
    try:
        r = run_cli([str(TRACE), "-p", "1", "-d", "1s", "--listen", "127.0.0.1:%d" % port])
    finally:
        s.close()
    assert r.returncode == 1
    one_line(r.stderr, "rtsup-trace: --listen '127.0.0.1:%d': cannot serve HTTP there: "
             "Address already in use" % port)


def http_get(port, path="/metrics", timeout=10):
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    s.sendall(b"GET %s HTTP/1.0\r\n\r\n" % path.encode())
    data = b""
    while True:
        b = s.recv(65536)
        if not b:
            break
        data += b
    s.close()
    return data


def test_prometheus_hostile_clients(tmp_path):
    """Slowloris (more half-sent requests than connections allowed), 10 000
    requests, a 1 MB request: the server thread takes them, the main loop
    keeps its interval, and /metrics still answers afterwards."""
    port = free_port()
    prefix = unique_prefix()
    tr = Trace(["--listen", "127.0.0.1:%d" % port, "--comm", prefix + "-0", "-i", "200ms",
                "--no-overhead"])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "1", "-c", "8000"])
    served = [0]
    try:
        time.sleep(0.5)
        # slowloris: 24 connections (the limit is 16) dribbling a header
        slow = []
        for _ in range(24):
            try:
                c = socket.create_connection(("127.0.0.1", port), timeout=2)
                c.sendall(b"GET /metrics HTTP/1.1\r\nHost: x\r\n")
                slow.append(c)
            except OSError:
                pass
        for _ in range(10):
            for c in slow:
                try:
                    c.sendall(b"X-a: b\r\n")
                except OSError:
                    pass
            time.sleep(0.2)
        for c in slow:
            c.close()

        # 10 000 requests from 4 threads
        def many(n):
            for _ in range(n):
                try:
                    if b" 200 " in http_get(port)[:16]:
                        served[0] += 1
                except OSError:
                    pass
        ts = [threading.Thread(target=many, args=(2500,)) for _ in range(4)]
        for t in ts:
            t.start()
        for t in ts:
            t.join(timeout=300)
        # an oversized request: a 1 MB request line
        c = socket.create_connection(("127.0.0.1", port), timeout=10)
        try:
            c.sendall(b"GET /" + b"a" * (1 << 20) + b" HTTP/1.1\r\n\r\n")
            reply = c.recv(100)
        except OSError:
            reply = b""  # the server closed the connection: a refusal too
        c.close()
        assert not reply.startswith(b"HTTP/1.1 200"), reply
        metrics = http_get(port)
        assert b"rtsup_" in metrics and b" 200 " in metrics.split(b"\r\n")[0], metrics[:200]
        truth = lg.summary()
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
    assert served[0] >= 10000 * 0.99, served  # a request may meet a closing connection
    t = truth["threads"][0]
    assert threads_by_tid(summary)[t["tid"]]["total"]["cycles"] == t["cycles"]
    # the HTTP server has its own thread: the main loop's intervals stay
    # within 0.15 s of 0.2 s (two CPUs shared with the Python clients)
    assert max(gaps(intervals)) < 0.35, gaps(intervals)


# --- kill -9 -----------------------------------------------------------------

def test_kill9_leaves_nothing_attached():
    """kill -9: the kernel frees our programs with the process (no pinning,
    links held by fds only): `bpftool prog show id N` finds none of them;
    a new run starts at once."""
    tr = Trace(["-p", "1", "--no-overhead"])
    ids = prog_ids(tr.proc.pid)
    assert len(ids) >= 5, ids
    tr.proc.kill()
    tr.proc.wait(timeout=10)
    # programs are freed after an RCU grace period: up to 5 s
    left = ids
    end = time.time() + 5
    while left and time.time() < end:
        left = {i for i in left if subprocess.run(
            ["bpftool", "prog", "show", "id", str(i)], capture_output=True).returncode == 0}
        time.sleep(0.1)
    assert not left, left
    t0 = time.time()
    tr2 = Trace(["-p", "1", "-d", "1s", "--no-overhead"])
    assert time.time() - t0 < 30
    tr2.proc.wait(timeout=30)
    _, summary, _ = tr2.stop()
    assert summary["health"]["ok"]


# --- inside the RT guest only ---------------------------------------------------
# A clock step and a CPU going offline change the whole machine: never on a
# host shared with others. test_guest.py runs these two inside a PREEMPT_RT
# guest (scripts/vm-test), whose kernel command line carries this marker.
GUEST_MARK = "rtsup_faults_guest"


def in_guest():
    try:
        return GUEST_MARK in Path("/proc/cmdline").read_text().split()
    except OSError:
        return False


guest_only = pytest.mark.skipif(not in_guest(), reason="changes the machine's clock or CPUs: "
                                "only inside the RT guest (test_guest.py runs it)")


# the error of a step the tool says: each of its two offsets (before, after)
# within half of CLOCKOFF_WINDOW_NS (user/collect/clockoff.h: the clock read
# between two monotonic reads no more than 20 us apart). A CI guest said
# +5.000073 s for a step of at most 5 s when they were two plain reads.
STEP_ERR_S = 2 * 10e-6


def stepped_by(err):
    """The one step of the wall clock rtsup-trace said on stderr, in s."""
    said = [line for line in err.splitlines() if "the wall clock was stepped by" in line]
    assert len(said) == 1, err
    return float(said[0].split("stepped by ")[1].split(" s;")[0])


def realtime_loop_across_step(tmp_path, name, step_s):
    """realtime_loop for 3 s under rtsup-trace, CLOCK_REALTIME stepped by
    step_s 1.5 s in: (its n cycles, what it saw, the tool's totals for it,
    the tool's stderr)."""
    out = tmp_path / "rt.json"
    n = 3000000 // PERIOD_US  # 3 s of cycles
    tr = Trace(["--comm", name, "-i", "500ms", "--no-overhead"])
    prog = subprocess.Popen([str(PROGS / "realtime_loop"), name, str(PERIOD_US), str(n),
                             str(out)])
    try:
        time.sleep(1.5)
        time.clock_settime(time.CLOCK_REALTIME, time.time() + step_s)
        assert prog.wait(timeout=120) == 0
        time.sleep(0.5)
        _, summary, err = tr.stop()
    finally:
        if prog.poll() is None:
            prog.kill()
    t = [x for x in summary["threads"] if x["comm"] == name]
    assert len(t) == 1, summary["threads"]
    return n, json.loads(out.read_text()), t[0]["total"], err


@guest_only
def test_in_guest_clock_step_forward(tmp_path):
    """The clock steps forward 5 s (NTP after a boot in 1970) under a loop
    sleeping to CLOCK_REALTIME deadlines: the loop starts its schedule again;
    the step released the sleep in progress, at a time no hook saw: no
    latency, not 5 s of it; the cycles stay exact, the run goes on, and the
    step is said once on stderr."""
    n, truth, tot, err = realtime_loop_across_step(tmp_path, "rtloop", +5)
    assert truth["restarts"] == 1, truth  # it saw the step once
    # n sleeps bound n - 1 whole cycles; the restart is one of them
    assert tot["cycles"] == n - 1, (tot["cycles"], n)
    # the tool stamps the switch-in, the loop reads its clock after it: its
    # lateness is the larger; 1 ms for a TCG guest's clock reads. Without
    # the early-release rule the step would show as a 5 s latency. Its
    # lateness on its own clock: a step forward adds nothing to it once the
    # schedule restarts. (A CI guest: the tool 11.7 ms, the loop 9.4 ms on
    # CLOCK_MONOTONIC, when the loop paired its deadlines on the two clocks
    # by two plain reads, ms apart when preempted; realtime_loop.c's pair()
    # now brackets them.) A step between a wakeup and the loop's clock read
    # (stepped_after_wake) leaves that cycle on CLOCK_MONOTONIC: before, the
    # loop took it for the restart and left its lateness out (CI: the tool
    # 11.5 ms, the loop 6.3 ms).
    assert tot["latency_ns"]["max"] <= truth["worst_late_rt_ns"] + 1000000, (tot, truth)
    assert tot["latency_ns"]["max"] < 1e9
    # said once, with its size: 5 s less the moments between our clock read
    # and the set, within the tool's two offsets' error
    assert 4.5 < stepped_by(err) <= 5.0 + STEP_ERR_S, err


@guest_only
def test_in_guest_clock_step_backward(tmp_path):
    """The clock steps back 2 s under a loop sleeping to CLOCK_REALTIME
    deadlines: the sleep in progress lasts 2 s more, as the kernel's timer
    follows the clock. On the loop's clock it woke on time, so the tool
    reports no 2 s latency (before: the kernel side judged the release with
    the offset of the sleep's entry); the loop keeps its schedule, the
    cycles stay exact, the step is said once on stderr."""
    n, truth, tot, err = realtime_loop_across_step(tmp_path, "rtback", -2)
    assert truth["restarts"] == 0 and truth["stretched"] == 1, truth
    assert tot["cycles"] == n - 1, (tot["cycles"], n)
    # the loop's lateness on its own clock, the step's sleep included, bounds
    # the tool's; 1 ms for a TCG guest's clock reads (as above). Without the
    # fix the tool says 2 s. A step between a wakeup and the loop's clock
    # read (stepped_after_wake) leaves that cycle on CLOCK_MONOTONIC: before
    # it, the loop left it out (CI: the tool 9.97 ms, the loop 7.51 ms).
    assert tot["latency_ns"]["max"] <= truth["worst_late_rt_ns"] + 1000000, (tot, truth)
    # 2 s and the moments between our clock read and the set, within the
    # tool's two offsets' error
    assert -2.5 < stepped_by(err) <= -2.0 + STEP_ERR_S, err


@guest_only
def test_in_guest_cpu_offline(tmp_path):
    """A CPU taken offline and back under a thread pinned to it: the kernel
    moves the thread, the run goes on, the counts stay exact and the move is
    seen as a migration."""
    cpu = Path("/sys/devices/system/cpu/cpu1/online")
    prefix = unique_prefix()
    tr = Trace(["--comm", prefix + "-0", "--comm", prefix + "-1", "-i", "500ms",
                "--no-overhead"])
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", "2", "-C", "0,1",
                            "-c", str(4000000 // PERIOD_US)])
    try:
        time.sleep(1.0)
        cpu.write_text("0")
        time.sleep(1.0)
        cpu.write_text("1")
        truth = lg.summary()
        time.sleep(0.2)
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
        cpu.write_text("1")
    got = threads_by_tid(summary)
    for t in truth["threads"]:
        assert got[t["tid"]]["total"]["cycles"] == t["cycles"], (t, got[t["tid"]]["total"])
    moved = got[truth["threads"][1]["tid"]]["total"]["migrations"]
    assert moved >= 1, moved


@pytest.mark.parametrize("size", ["32K", "3M", "512M", "64Q", ""])
def test_bad_event_buffer_one_line(size):
    """--event-buffer: a power of two from 64K to 256M, else one line and 1."""
    r = subprocess.run([str(TRACE), "--event-buffer", size, "-p", "1"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 1
    assert r.stderr.splitlines() == [
        "rtsup-trace: --event-buffer '%s': want a power of two from 64K to 256M (e.g. 4M)"
        % size], r.stderr


@pytest.mark.parametrize("args,why", [
    (["--top", "x"], "--top 'x': want a number from 0 to 1048576"),
    (["--top", "-1"], "--top '-1': want a number from 0 to 1048576"),
    (["--json-threads", "some"], "--json-threads 'some': want all or active"),
    (["--json-threads", ""], "--json-threads '': want all or active"),
    (["--syscall-hooks", "fentry"], "--syscall-hooks 'fentry': want auto, per-syscall or raw"),
    (["--raw-tp", "--syscall-hooks", "per-syscall"],
     "--syscall-hooks per-syscall: they are BTF programs: not with --raw-tp"),
])
def test_bad_row_options_one_line(args, why):
    """--top, --json-threads and --syscall-hooks: a bad value (or pair) is
    one line and exit 1."""
    r = subprocess.run([str(TRACE)] + args + ["-p", "1"], capture_output=True, text=True,
                       timeout=30)
    assert r.returncode == 1
    assert r.stderr.splitlines() == ["rtsup-trace: " + why], r.stderr
