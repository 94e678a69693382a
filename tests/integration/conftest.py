# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""Integration test helpers: real BPF programs on this machine's kernel.

Every test runs rtsup-trace against rtsup-loadgen and compares what the
tracer reports with the JSON summary of what the generator did.
With CI=true a test that cannot load BPF fails; elsewhere it is skipped.
"""
import json
import os
import re
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# RTSUP_BUILD: another build directory; RTSUP_TRACE: only another rtsup-trace
# (make sanitize: the tool under ASan+UBSan, the generators as they ship, so
# the shadow memory's page faults are not counted against the generator's truth)
BUILD = ROOT / os.environ.get("RTSUP_BUILD", "build")
TRACE = Path(os.environ["RTSUP_TRACE"]).resolve() if os.environ.get("RTSUP_TRACE") \
    else BUILD / "rtsup-trace"
LOADGEN = BUILD / "rtsup-loadgen"
NOISE = BUILD / "rtsup-noise"
HANGS = BUILD / "vm" / "hangs.log"  # scripts/vm-test: boots that hung or panicked
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")
# Inside a qemu TCG guest (tests/integration/test_guest.py) time is slow and
# noisy: tests keep their count assertions and relax the timing ones.
EMULATED = os.environ.get("RTSUP_TEST_EMULATED") == "1"
# The generator's period: 1 ms; 5 ms in a guest, where 1 kHz FIFO threads
# leave the generator's own SCHED_OTHER helper no emulated CPU to run on.
PERIOD_US = 5000 if EMULATED else 1000


# RTSUP_TEST_NOISE="-b 3ms -e 30ms" (make test-noisy): our own noise injector
# runs on every CPU for the whole session (scripts/noise/noise.c).
NOISE_ARGS = os.environ.get("RTSUP_TEST_NOISE", "")


def noise_gauge(duration="1s"):
    """The machine's wakeup latency now: a SCHED_FIFO 90 probe per CPU."""
    if not NOISE.exists() or os.geteuid() != 0:
        return None
    r = subprocess.run([str(NOISE), "gauge", "-d", duration], capture_output=True,
                       text=True, timeout=60)
    return json.loads(r.stdout) if r.returncode == 0 else None


def _gauge_line(g):
    if not g:
        return "noise gauge: not measured (needs root and build/rtsup-noise)"
    return ("noise gauge: wakeup latency of a 1 ms SCHED_FIFO probe on %d CPUs: "
            "p50 %.0f us, p99 %.0f us, max %.0f us" % (g["cpus"], g["p50_us"], g["p99_us"],
                                                       g["max_us"]))


def pytest_sessionstart(session):
    """Start the noise injector (if asked), then gauge the noise the tests meet."""
    session.config._rtsup_noise = None
    if NOISE_ARGS and NOISE.exists():
        session.config._rtsup_noise = subprocess.Popen(
            [str(NOISE), "inject"] + NOISE_ARGS.split(), stdout=subprocess.PIPE, text=True)
        time.sleep(0.2)
    session.config._rtsup_gauge = [noise_gauge()]
    session.config._rtsup_hangs_at = HANGS.stat().st_size if HANGS.exists() else 0


def pytest_report_header(config):
    lines = [_gauge_line(config._rtsup_gauge[0])]
    if NOISE_ARGS:
        lines.append("noise injector: SCHED_FIFO 99 per CPU, " + NOISE_ARGS)
    return lines


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """Every report ends with how noisy the machine was, at the start and now."""
    g = noise_gauge()
    terminalreporter.write_line("at the start: " + _gauge_line(config._rtsup_gauge[0]))
    terminalreporter.write_line("at the end:   " + _gauge_line(g))
    # guest boots that hung and were booted again (scripts/vm-test): where they stopped
    if HANGS.exists() and HANGS.stat().st_size > config._rtsup_hangs_at:
        with open(HANGS, errors="replace") as f:
            f.seek(config._rtsup_hangs_at)
            for line in f.read().splitlines():
                terminalreporter.write_line(line)


def pytest_unconfigure(config):
    p = getattr(config, "_rtsup_noise", None)
    if p and p.poll() is None:
        p.terminate()
        out, _ = p.communicate(timeout=10)
        print("noise injector: " + out.strip())


# Thresholds for tests that judge what a program does (RT-unsafe events,
# deaths, scheduling), not timing: a noisy machine may make a timing check
# WARN, none of them can reach ERROR (docs/testing.md). Tests add rules:.
CLEAN_DEFAULTS = """
defaults:
  thresholds:
    deadline_miss: {warn: 50, error_rate: 100%}
    exec_near_period: {warn: 1000%}
    starvation: {warn_periods: 0, error_periods: 0}
    overhead: {warn: 0%, error: 0%}
"""


def _bpf_unavailable_reason():
    """Why rtsup-trace cannot attach here, or None if it can."""
    if not TRACE.exists() or not LOADGEN.exists():
        return "build/rtsup-trace is not built (run make)"
    if os.geteuid() != 0:
        return "loading BPF needs root"
    r = subprocess.run([str(TRACE), "--tid", str(os.getpid()), "-d", "0.2s", "-j"],
                       capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        return "rtsup-trace cannot load BPF: " + r.stderr.strip()
    return None


@pytest.fixture(scope="session")
def bpf():
    """Fail (CI) or skip (elsewhere) when BPF cannot be loaded."""
    why = _bpf_unavailable_reason()
    if why:
        if IN_CI:
            pytest.fail("CI=true and " + why)
        pytest.skip(why)


class Trace:
    """A running rtsup-trace with JSON output. Its stdout and stderr are read
    while it runs: a full pipe would stall its main loop. 'out_file' sends
    stdout to a file instead, for a test that times the main loop while it
    writes megabytes an interval: a pipe's writer waits on the reader, here
    a Python thread sharing the CPUs with the load, and the loop's lateness
    would be pytest's."""

    def __init__(self, args, out_file=None):
        self.out_file = out_file
        sink = open(out_file, "w") if out_file else subprocess.PIPE
        self.proc = subprocess.Popen([str(TRACE), "-j"] + args, stdout=sink,
                                     stderr=subprocess.PIPE, text=True)
        if out_file:
            sink.close()
        # the banner on stderr says the programs are attached
        line = self.proc.stderr.readline()
        if "tracing with" not in line:
            out, err = self.proc.communicate(timeout=30)
            raise AssertionError("rtsup-trace did not start: " + line + err)
        self.banner = line
        self.out, self.err = [], []
        pipes = ((self.proc.stderr, self.err),)
        if not out_file:
            pipes = ((self.proc.stdout, self.out),) + pipes
        self.readers = [threading.Thread(target=self._drain, args=(f, buf), daemon=True)
                        for f, buf in pipes]
        for t in self.readers:
            t.start()

    @staticmethod
    def _drain(f, buf):
        for line in f:
            buf.append(line)

    def stop(self, sig=signal.SIGINT, timeout=120 if EMULATED else 30):
        """End the run; return (interval objects, summary object, stderr)."""
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        self.proc.wait(timeout=timeout)
        for t in self.readers:
            t.join(timeout=timeout)
        out, err = "".join(self.out), "".join(self.err)
        if self.out_file:
            out = open(self.out_file).read()
        objs = [json.loads(x) for x in out.splitlines() if x.strip()]
        intervals = [o for o in objs if o.get("type") == "interval"]
        summary = [o for o in objs if o.get("type") == "summary"]
        assert self.proc.returncode == 0, err
        assert len(summary) == 1, out
        return intervals, summary[0], err


class Loadgen:
    """rtsup-loadgen with --hold: it parks its threads after the last cycle,
    writes its summary and waits for SIGTERM, so the tracer sees only
    whole cycles."""

    def __init__(self, tmp_path, args, hold=True):
        self.summary_path = tmp_path / "loadgen.json"
        if "-P" not in args:
            args = ["-P", str(PERIOD_US)] + args
        # the generator counts the cycles a tracer may judge otherwise than it
        # did (deadline_misses_near, overruns_near): the tolerance of timing checks
        args = ["--audit"] + args
        cmd = [str(LOADGEN), "-s", str(self.summary_path)] + args
        if hold:
            cmd.append("--hold")
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True)
        self.pid = self.proc.pid

    def summary(self, timeout=300 if EMULATED else 60):
        """Wait for the generator's summary (written once every thread is done)."""
        end = time.time() + timeout
        while time.time() < end:
            if self.summary_path.exists():
                try:
                    return json.loads(self.summary_path.read_text())
                except json.JSONDecodeError:
                    pass  # being written
            if self.proc.poll() is not None:
                # it exited: the summary is whole now or never will be (a
                # failure after its fopen leaves it empty: the madvise EINVAL
                # of a kernel without THP waited out the whole timeout so)
                try:
                    return json.loads(self.summary_path.read_text())
                except (OSError, json.JSONDecodeError):
                    raise AssertionError("rtsup-loadgen failed: " + self.proc.stderr.read())
            time.sleep(0.05)
        raise AssertionError("rtsup-loadgen wrote no summary in time")

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
        self.proc.communicate(timeout=30)


# a logged level change: "rtsup-trace: TIME name[tid]: WARN -> ERROR: why"
LEVELS = "OK|WARN|ERROR|STALE"
LEVEL_CHANGE = re.compile(r"^rtsup-trace: (\S+Z) (.+?): (%s) -> (%s)(?:: (.*))?$"
                          % (LEVELS, LEVELS))


def level_changes(stderr):
    """Every level change the tool logged: (time, component, from, to, why)."""
    return [m.groups() for m in map(LEVEL_CHANGE.match, stderr.splitlines()) if m]


def threads_by_tid(summary):
    return {t["tid"]: t for t in summary["threads"]}


def unique_prefix():
    """A thread name prefix no other test or process uses."""
    unique_prefix.n += 1
    return "t%d%02d" % (os.getpid() % 10000, unique_prefix.n % 100)


unique_prefix.n = 0


def proc_status(pid, field):
    """A number of /proc/PID/status (VmHWM and RssAnon in KiB, a count of
    switches); a field the kernel does not give fails the test."""
    for line in Path("/proc/%d/status" % pid).read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1])
    raise AssertionError("no %s in /proc/%d/status" % (field, pid))


def run_supervised(tmp_path, lg_args, trace_args=None, nthreads=2):
    """Trace the generator's periodic threads by name, started before the
    generator (so --comm must pick them up), wait for its summary, stop
    the tracer; return (truth, intervals, summary)."""
    prefix = unique_prefix()
    names = ["--comm=%s-%d" % (prefix, i) for i in range(nthreads)]
    trace_args = list(trace_args or [])
    audit = None
    if not EMULATED:
        # every cycle from both sides, for the message of a timing count that
        # differs (cycle_audit.py); not in the emulated guests, whose checks
        # of timing are loose and whose every cycle costs
        record = tmp_path / "audit.rtsup"
        if "--record" in trace_args:
            record = trace_args[trace_args.index("--record") + 1]
        else:
            trace_args += ["--record", str(record)]
        audit = (str(record), str(tmp_path / "cycles.txt"))
        lg_args = ["--cycle-log", audit[1]] + lg_args
    tr = Trace(trace_args + names)
    lg = Loadgen(tmp_path, ["--name", prefix, "-n", str(nthreads)] + lg_args)
    try:
        truth = lg.summary()
        time.sleep(0.2)  # let the last interval's events drain
        intervals, summary, _ = tr.stop()
    finally:
        lg.stop()
        if tr.proc.poll() is None:
            tr.proc.kill()
    for t in truth["threads"]:
        t["_audit"] = audit
    return truth, intervals, summary


def fdinfo_values(pid, key):
    """The values of key ("prog_id", "run_time_ns") in the fdinfo of every
    fd a process holds: BPF program fds say both"""
    vals = []
    for fd in os.listdir("/proc/%d/fdinfo" % pid):
        try:
            with open("/proc/%d/fdinfo/%s" % (pid, fd)) as f:
                vals += [int(line.split()[1]) for line in f if line.startswith(key + ":")]
        except OSError:
            continue
    return vals


def prog_ids(pid):
    """The ids of the BPF programs a process holds"""
    return set(fdinfo_values(pid, "prog_id"))


def block_events(intervals, tid):
    """A thread's blocks as its block events say them, by the syscall each
    waits in (None: none, a page fault): every one, those folded in floods
    too (a flood keeps its first and last events and counts the rest)."""
    by = {}
    for i in intervals:
        for e in i["events"]:
            if e["event"] == "unsafe" and e["reason"] == "block" and e["tid"] == tid:
                by[e["syscall"]] = by.get(e["syscall"], 0) + 1
        for f in i["events_folded"]:
            if f["event"] == "unsafe" and f["reason"] == "block" and f["tid"] == tid:
                by[f["syscall"]] = by.get(f["syscall"], 0) + f["folded"]
    return by
