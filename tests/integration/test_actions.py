# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""Actions on a level change (--on-level, actions:): what a command, a signal,
a FIFO and a Unix socket receive, compared with the level changes the tool
logged and with the fault the generator injected; a slow command does not
delay the intervals."""
import datetime
import json
import os
import socket
import stat
import subprocess
import sys
import time

import pytest

from conftest import CLEAN_DEFAULTS, LOADGEN, TRACE, Trace, level_changes, unique_prefix

pytestmark = pytest.mark.usefixtures("bpf")

# as test_status.py: strict on RT-unsafe events, tolerant of timing on a
# loaded machine (a timing WARN may come and go; it is a level change too)
CLEAN = CLEAN_DEFAULTS + """rules:
  - name: loop
    match: {thread: "PREFIX-*"}
    period: 1ms
"""
PINNED = ["-C", "0,1"]

# the script action: what it got, environment and stdin, one file per call
RECORDER = """#!/bin/sh
f=$(mktemp DIR/call.XXXXXX)
env | grep '^RTSUP_' > "$f.env"
cat > "$f.stdin"
mv "$f.stdin" "$f.json"
"""


def config(tmp_path, prefix):
    p = tmp_path / "rt.yaml"
    p.write_text(CLEAN.replace("PREFIX", prefix))
    return p


def run_check(args, timeout=120):
    """rtsup-trace --check -j -i 500ms ARGS: (exit code, JSON objects, stderr, seconds)."""
    t0 = time.monotonic()
    r = subprocess.run([str(TRACE), "--check", "-j", "-i", "500ms", "--no-overhead"] + args,
                       capture_output=True, text=True, timeout=timeout)
    objs = [json.loads(x) for x in r.stdout.splitlines() if x.startswith("{")]
    return r.returncode, objs, r.stderr, time.monotonic() - t0


def assert_rate_limited(entries, ran):
    """An action ran for each level change (time, component, from) in
    entries but those its limit skips: once a second per component
    (RATE_GAP_NS, actionspec.h), counted from its last run. The limit is on
    the monotonic clock and the times are printed to the ms: a change 1 s
    +- 2 ms after the last run (two intervals of 500 ms: the noise
    injector's run had 999 ms) may have run or not, and what it did is
    read from 'ran'."""
    def secs(t):
        return datetime.datetime.fromisoformat(t.replace("Z", "+00:00")).timestamp()
    ran = set(ran)
    last = {}
    for e in sorted(entries):
        gap = secs(e[0]) - last[e[1]] if e[1] in last else None
        if gap is None or gap >= 1.002:
            assert e in ran, ("not run", e, sorted(ran))
        elif gap <= 0.998:
            assert e not in ran, ("run within the second", e, sorted(ran))
        if e in ran:
            last[e[1]] = secs(e[0])
    assert ran <= set(entries), ("not a level change", ran - set(entries))


def calls(d):
    """The recorder's calls: (env dict, stdin JSON) in the order of their time."""
    out = []
    for f in sorted(d.glob("call.*.json")):
        env = dict(l.split("=", 1) for l in f.with_suffix(".env").read_text().splitlines())
        line = f.read_text()
        assert line.endswith("\n") and line.count("\n") == 1, line  # one JSON line
        out.append((env, json.loads(line)))
    return sorted(out, key=lambda c: (c[1]["time"], c[1]["component"], c[1]["from"]))


def test_script_action_one_call_per_transition(tmp_path):
    prefix = unique_prefix()
    rec = tmp_path / "rec.sh"
    rec.write_text(RECORDER.replace("DIR", str(tmp_path)))
    rec.chmod(0o755)
    code, objs, err, _ = run_check(
        ["--config", str(config(tmp_path, prefix)),
         "--on-level", "WARN:%s" % rec, "--on-level", "!WARN:%s" % rec,
         "--", str(LOADGEN), "--name", prefix, "-c", "1500", "-f", "mmap@300,thread=0"]
        + PINNED)
    assert code == 2, err  # the injected mmap is a WARN
    # nothing failed and nothing waited for a command (one started by the last
    # verdict may still run when the run ends: the end line may count it).
    # Under noise, misses can make a component enter or leave WARN again within
    # the second, and the rate limit skips those: make test-noisy's injector
    # made 54 misses in an interval of 491 cycles, over the 50 that warn.
    acts = [l for l in err.splitlines() if l.startswith("rtsup-trace: action '")]
    assert all("skipped: at most once a second per component" in l for l in acts), err
    summary = [o for o in objs if o["type"] == "summary"][0]
    t0 = [t for t in summary["threads"] if t["comm"] == prefix + "-0"][0]
    # one call per change into or out of WARN, of any component, but those the
    # limit skips: once a second per action (into WARN, out of it) and component
    changes = [(c[0], c[1], c[2], c[3]) for c in level_changes(err) if "WARN" in (c[2], c[3])]
    got = calls(tmp_path)
    ran = [(j["time"], j["component"], j["from"], j["level"]) for _, j in got]
    assert len(ran) == len(set(ran)) and set(ran) <= set(changes), (ran, changes)
    for side in (3, 2):  # into WARN, out of WARN
        assert_rate_limited([c[:3] for c in changes if c[side] == "WARN"],
                            [r[:3] for r in ran if r[side] == "WARN"])
    for env, j in got:
        # the environment says what the JSON line says
        assert env["RTSUP_COMPONENT"] == j["component"]
        assert env["RTSUP_LEVEL"] == j["level"] and env["RTSUP_FROM"] == j["from"]
        assert env["RTSUP_TIME"] == j["time"]
        assert env["RTSUP_MESSAGES"] == "; ".join(j["messages"])
        assert env["RTSUP_TID"] == str(j.get("tid", ""))
        assert env["RTSUP_PID"] == str(j.get("pid", ""))
        assert j["type"] == "level_change"
    # the injected fault: OK -> WARN for rt_unsafe (mmap), then back to OK
    mine = [j for _, j in got if j["component"] == "%s-0[%d]" % (prefix, t0["tid"])]
    assert [(j["from"], j["level"]) for j in mine][:2] == [("OK", "WARN"), ("WARN", "OK")], mine
    # by kind, not by position: under noise a deadline-miss message comes first
    assert "rt_unsafe" in mine[0]["checks"], mine
    assert any("mmap 1" in m for m in mine[0]["messages"]), mine
    assert mine[0]["tid"] == t0["tid"] and mine[0]["pid"] == t0["tgid"], mine
    assert mine[1]["messages"] == [] and mine[1]["checks"] == []


def test_slow_action_does_not_delay_intervals(tmp_path):
    prefix = unique_prefix()
    # output to /dev/null (exec: the shell's own too): the command's stdout
    # and stderr are rtsup-trace's stderr, which subprocess.run would wait on
    slow = ("WARN:exec >/dev/null 2>&1; touch %s/started.$RTSUP_TID; sleep 10; touch %s/done"
            % (tmp_path, tmp_path))
    code, objs, err, secs = run_check(
        ["--config", str(config(tmp_path, prefix)), "--on-level", slow,
         "--", str(LOADGEN), "--name", prefix, "-c", "3000",
         "-f", "mmap@300,thread=0", "-f", "mmap@1500,thread=1"] + PINNED)
    assert code == 2, err
    # both faults started a sleeping command (through the shell, so these
    # files are written within the run: the run lasts > 1 s after the second)
    assert len(list(tmp_path.glob("started.*"))) >= 2, err
    assert not (tmp_path / "done").exists()
    intervals = [o for o in objs if o["type"] == "interval"]
    assert len(intervals) >= 6, err
    # no interval is longer than its 500 ms (the last ones are cut short by
    # the command's end): the main loop never waited for the commands.
    # Tolerance 250 ms: the loop wakes at least every 100 ms, plus what a
    # loaded 2-CPU host does to a SCHED_OTHER process's wake-up
    lens = [o["interval_s"] for o in intervals]
    assert max(lens) < 0.75, lens
    # and rtsup-trace itself ended with the command, not after the sleeps
    assert secs < 9, secs
    assert "still running" in err  # the end-of-run line counts them


SIGTARGET = r"""
import ctypes, json, mmap, signal, sys, threading, time
libc = ctypes.CDLL(None, use_errno=True)
sigs = {signal.SIGRTMIN + 1, signal.SIGRTMIN + 2}
signal.pthread_sigmask(signal.SIG_BLOCK, sigs)  # every thread, waited for below
def loop():
    libc.prctl(15, sys.argv[1].encode() + b"-0", 0, 0, 0)  # PR_SET_NAME
    t = time.monotonic()
    for i in range(1500):
        if i == 300:
            mmap.mmap(-1, 4096).close()  # the fault: mmap + munmap
        t += 0.001
        time.sleep(max(0.0, t - time.monotonic()))  # clock_nanosleep
sys.stdin.readline()  # rtsup-trace is attached
th = threading.Thread(target=loop)
th.start()
got, end = [], None
while end is None or time.monotonic() < end:
    if end is None and not th.is_alive():
        end = time.monotonic() + 2.5  # the verdict comes at the end of an interval
    info = signal.sigtimedwait(sigs, 0.05)
    if info:
        got.append({"signo": info.si_signo - signal.SIGRTMIN, "pid": info.si_pid})
json.dump(got, open(sys.argv[2], "w"))
"""


def test_signal_action_reaches_process(tmp_path):
    prefix = unique_prefix()
    out = tmp_path / "signals.json"
    prog = tmp_path / "target.py"
    prog.write_text(SIGTARGET)
    target = subprocess.Popen(["/usr/bin/python3", str(prog), prefix, str(out)],
                              stdin=subprocess.PIPE, text=True)
    # 1 s intervals: a component enters WARN at most every 2 s, so the rate
    # limit (once a second) never applies and every entry is one signal; RT
    # signals queue, so none merges with another
    tr = Trace(["-i", "1s", "--no-overhead", "--pid", str(target.pid),
                "--config", str(config(tmp_path, prefix)),
                "--on-level", "WARN:signal=RTMIN+1",
                "--on-level", "WARN:signal=RTMIN+2@%d" % target.pid])
    try:
        target.stdin.write("go\n")
        target.stdin.flush()
        assert target.wait(timeout=60) == 0
        time.sleep(0.2)
        _, summary, err = tr.stop()
    finally:
        if tr.proc.poll() is None:
            tr.proc.kill()
        if target.poll() is None:
            target.kill()
    got = json.loads(out.read_text())
    tids = {t["tid"] for t in summary["threads"] if t["tgid"] == target.pid}
    entered = [c for c in level_changes(err) if c[3] == "WARN" and
               int(c[1].rsplit("[", 1)[1].rstrip("]")) in tids]
    # the injected mmap made the loop thread WARN
    assert any(c[1].startswith(prefix + "-0[") and "mmap 1" in (c[4] or "") for c in entered), err
    # each entry into WARN: one signal to the component's process, one to the pid given
    assert sorted(g["signo"] for g in got) == [1] * len(entered) + [2] * len(entered), (got, err)
    assert {g["pid"] for g in got} == {tr.proc.pid}  # sent by rtsup-trace
    assert "rtsup-trace: action '" not in err and "skipped" not in err, err


def test_fifo_and_socket_actions_write_json_lines(tmp_path):
    prefix = unique_prefix()
    fifo, lonely, sock = tmp_path / "alarm.fifo", tmp_path / "lonely.fifo", tmp_path / "s"
    os.mkfifo(fifo)
    os.mkfifo(lonely)
    # the reader is there before the writer (non-blocking open), and keeps
    # what it gets in the FIFO's buffer until the run is over
    rfd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    srv = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    srv.bind(str(sock))
    try:
        code, _, err, _ = run_check(
            ["--config", str(config(tmp_path, prefix)),
             "--on-level", "WARN:fifo=%s" % fifo, "--on-level", "WARN:unix=%s" % sock,
             "--on-level", "WARN:fifo=%s" % lonely,
             "--", str(LOADGEN), "--name", prefix, "-c", "1500", "-f", "mmap@300,thread=0"]
            + PINNED)
        data = b""
        while True:
            try:
                chunk = os.read(rfd, 65536)
            except BlockingIOError:
                break
            if not chunk:
                break
            data += chunk
        srv.setblocking(False)
        dgrams = []
        while True:
            try:
                dgrams.append(srv.recv(65536).decode())
            except BlockingIOError:
                break
    finally:
        os.close(rfd)
        srv.close()
    assert code == 2, err  # a FIFO without reader is logged, not fatal
    # every entry into WARN writes one line, but those the rate limit skips
    # (under noise, misses make a component WARN again within the second)
    want = [(c[0], c[1], c[2]) for c in level_changes(err) if c[3] == "WARN"]
    lines = [json.loads(l) for l in data.decode().splitlines()]
    got = sorted((j["time"], j["component"], j["from"]) for j in lines)
    assert len(got) == len(set(got)), got
    assert_rate_limited(want, got)
    assert any(j["component"].startswith(prefix + "-0[") and "rt_unsafe" in j["checks"]
               for j in lines), lines
    # a datagram socket: the same lines, one per datagram
    assert [json.loads(d) for d in dgrams] == lines
    assert all(d.endswith("\n") and d.count("\n") == 1 for d in dgrams)
    # the FIFO nobody reads: one line per attempt, the run goes on
    noreader = [l for l in err.splitlines() if "lonely.fifo" in l and "skipped:" not in l]
    assert len(noreader) == len(got) and all(l.endswith(": no reader on the FIFO")
                                              for l in noreader), err
    assert stat.S_ISFIFO(os.stat(lonely).st_mode)
