# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""rtsup-trace supervising rtsup-cansim's simulated CAN nodes on a vcan bus,
inside the PREEMPT_RT VM (scripts/vm-test): the simulator's JSON summary is
the truth the tracer's CAN numbers and verdicts are compared with.

One VM boot runs the whole scenario (two simulators side by side, one plain
with 29-bit ids and one CANopen, under one rtsup-trace, with candump as a
second witness; a third on vcan1 is ended by SIGTERM); the tests below each
check one part of the result.
Emulated time is slow and noisy: counts and verdicts are asserted, not
timing. With CI=true a missing VM setup fails, never skips."""
import collections
import datetime
import json
import re
import shutil
import subprocess
import uuid

import pytest

from conftest import IN_CI, ROOT, TRACE
from test_can import VM, can_ids, can_ifs, summary_of, vm_ready

CANSIM = ROOT / "build" / "rtsup-cansim"

CONFIG = """
defaults:
  allow_syscalls: [write]
can:
  canopen: true
  heartbeat_timeout: 500ms
  defaults: {learn: 0.5s}
  nodes:
    - {name: cs-ok, interface: vcan0, id: 0x18fef100, direction: tx, period: 20ms,
       not_responding: {warn_periods: 50, error_periods: 100}}
    - {name: cs-gone, interface: vcan0, id: 0x0cf00400, direction: tx, period: 20ms,
       not_responding: {warn_periods: 5, error_periods: 10}}
    - {name: cs-absent, interface: vcan0, id: 0x201, direction: tx, period: 20ms,
       init_timeout: 1s}
"""

# vcan echoes every send through af_can: everything here is "tx" to the
# tracer. vcan1 carries a third simulator the tracer does not watch, ended
# by SIGTERM.
SCRIPT = """
cat > $O/can.yaml <<'EOF2'
""" + CONFIG + """EOF2
for i in vcan0 vcan1; do ip link add dev $i type vcan; ip link set up $i; done
candump -L -d vcan0,0:0,#FFFFFFFF > $O/bus.log 2> $O/bus.err &
CD=$!
$S -i vcan1 -n cs-term:0x100:10 -s $O/term.json &
SP=$!
$T -j --can vcan0 --config $O/can.yaml --check -i 500ms --comm cs-ok --comm cs-drive \
    > $O/trace.json 2> $O/trace.err &
TP=$!
for i in $(seq 100); do grep -q "tracing with" $O/trace.err 2>/dev/null && break; sleep 0.1; done
$S -i vcan0 -d 2000 -n cs-ok:0x18fef100:20 -n cs-gone:0x0cf00400:20:4 -n cs-absent:0x201:20 \
    --fault cs-ok:burst@5:20 --fault cs-gone:stop@15 --fault cs-absent:never \
    --fault errframe@300 -s $O/plain.json &
A=$!
# no -d: it runs until SIGINT, so it cannot end before the SDO requests
# however slowly the guest gets them out
$S -i vcan0 --canopen -n cs-drive:5:20 -n cs-hb:6:20 \
    --fault cs-drive:emcy@10:0x8130 --fault cs-hb:hbstop@10 -s $O/canopen.json &
B=$!
# the SDO socket is bound before the threads start: requests from now on are answered
for i in $(seq 200); do grep -qx cansim-sdo /proc/$B/task/*/comm 2>/dev/null && break; sleep 0.05; done
cansend vcan0 605#4018100100000000
cansend vcan0 605#4017100000000000
cansend vcan0 605#2b17100064000000
wait $A
kill -INT $B
wait $B
kill -INT $TP
wait $TP || echo $? > $O/trace.exit
kill -TERM $SP
wait $SP
kill $CD || true
wait $CD || true
"""

SDO_REQUESTS = 3


def when(iso):
    """An ISO 8601 UTC time with milliseconds, as both tools write it."""
    return datetime.datetime.strptime(iso, "%Y-%m-%dT%H:%M:%S.%fZ")


def canopen_comp(comp, n):
    """canopen:N, or canopen:IFACE:N (per-interface CANopen state)."""
    return re.fullmatch(r"canopen:(vcan0:)?%d" % n, comp) is not None


@pytest.fixture(scope="module")
def run():
    """The scenario, once: (trace summary, plain, canopen, term, out dir)."""
    if not CANSIM.exists() or not TRACE.exists():
        if IN_CI:
            pytest.fail("CI=true and build/rtsup-cansim or rtsup-trace is not built")
        pytest.skip("build/rtsup-cansim is not built (run make)")
    if not vm_ready("rt-6.1"):
        if IN_CI:
            pytest.fail("CI=true and the rt-6.1 VM is not set up (make deps runs "
                        "scripts/vm-test setup)")
        pytest.skip("rt-6.1 VM not set up: scripts/vm-test setup")
    out = ROOT / "build" / ("cansim-test-" + uuid.uuid4().hex[:8])
    out.mkdir(parents=True)
    body = "set -e\ncd %s\nT=%s\nS=%s\nO=%s\n%s" % (ROOT, TRACE, CANSIM, out, SCRIPT)
    r = subprocess.run([str(VM), "run", "--timeout", "90", "--", "sh", "-c", body],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    _, summary = summary_of(out / "trace.json")
    truth = [json.loads((out / f).read_text())
             for f in ("plain.json", "canopen.json", "term.json")]
    yield (summary,) + tuple(truth) + (out,)
    shutil.rmtree(out, ignore_errors=True)


def nodes_of(*sims):
    return {n["name"]: n for s in sims for n in s["nodes"]}


def violations(summary, comp=None, level=None):
    return [v for v in summary["violations"]
            if (comp is None or (comp(v["component"]) if callable(comp)
                                 else v["component"] == comp))
            and (level is None or v["level"] == level)]


def test_frames_per_id_exact(run):
    s, plain, co, _, _ = run
    truth = collections.Counter(plain["frames_sent"]) + collections.Counter(co["frames_sent"])
    ids = can_ids(s)
    seen = {cid: v["frames"] for (iface, cid, d), v in ids.items() if d == "tx"}
    # cansend's requests are the only frames not from a simulator
    assert seen.pop("0x605") == SDO_REQUESTS
    assert seen == dict(truth)
    assert not [k for k in ids if k[2] == "rx"]
    f = can_ifs(s)["vcan0"]
    assert f["frames_tx"] == plain["frames_total"] + co["frames_total"] + SDO_REQUESTS
    assert f["bytes"] == plain["bytes_total"] + co["bytes_total"] + 8 * SDO_REQUESTS
    assert s["lost_events"] == 0 and s["can"]["frames_not_counted_by_id"] == 0
    # each identifier's last sender is the node's thread (responses: the SDO thread)
    for n in nodes_of(plain, co).values():
        sdo = n["node_id"] and "0x%x" % (0x580 + n["node_id"])
        for cid, frames in n["frames_sent"].items():
            if frames:
                want = co["sdo_thread"]["tid"] if cid == sdo else n["tid"]
                assert ids[("vcan0", cid, "tx")]["sender"]["tid"] == want, cid


def test_supervised_node_threads_send_inside_their_cycles(run):
    s, plain, co, _, _ = run
    nodes = nodes_of(plain, co)
    ids = can_ids(s)
    ok, drive = nodes["cs-ok"], nodes["cs-drive"]
    assert ok["comm"] == "cs-ok" and ok["cycles"] > 50
    # every frame, the burst too, comes after a clock_nanosleep of the thread
    assert ids[("vcan0", "0x18fef100x", "tx")]["sender"]["in_cycle"] == \
        ok["frames_sent"]["0x18fef100x"]
    assert ids[("vcan0", "0x185", "tx")]["sender"]["in_cycle"] == drive["pdos_sent"]
    # the boot-up goes out before the first sleep: in a cycle only if the
    # tracer already had the thread in activation mode (wakeup to block)
    assert drive["bootup_sent"] == 1
    assert drive["heartbeats_sent"] <= ids[("vcan0", "0x705", "tx")]["sender"]["in_cycle"] \
        <= drive["heartbeats_sent"] + 1
    threads = {t["tid"]: t for t in s["threads"]}
    for n in (ok, drive):
        assert threads[n["tid"]]["comm"] == n["name"]
        assert threads[n["tid"]]["mode"] == "delimiter"
        # the last sleep is cut by the end of the run
        assert n["cycles"] - 1 <= threads[n["tid"]]["total"]["cycles"] <= n["cycles"]


def test_candump_sees_exactly_what_cansim_claims(run):
    _, plain, co, _, out = run
    assert not (out / "bus.err").read_text().strip()
    lines = (out / "bus.log").read_text().splitlines()
    assert lines and all(x.startswith("(") for x in lines), "candump dropped frames"
    frames = collections.Counter()
    data = collections.defaultdict(list)
    errs = []
    for x in lines:
        cid, payload = x.split()[2].split("#")
        v = int(cid, 16)
        if len(cid) == 8 and v & 0x20000000:  # CAN_ERR_FLAG
            errs.append((v & 0x1FFFFFFF, payload))
            continue
        key = "0x%x%s" % (v, "x" if len(cid) == 8 else "")
        frames[key] += 1
        data[key].append(bytes.fromhex(payload))
    assert frames.pop("0x605") == SDO_REQUESTS
    assert frames == collections.Counter(plain["frames_sent"]) + \
        collections.Counter(co["frames_sent"])
    assert errs == [(0x4, "0010000000000000")]
    assert plain["error_frames_sent"] == 1
    # the payload is the frame's sequence number, bursts included: no gap
    for n in nodes_of(plain, co).values():
        seqs = [int.from_bytes(d, "little") for d in data[n["id"]]]
        if n["len"]:
            assert seqs == [i % 256 ** n["len"] for i in range(len(seqs))], n["name"]
    # SDO answers: upload 0x1018:01 (the cycle count), 0x1017 (heartbeat period), download
    answers = data["0x585"]
    assert [a[:4].hex() for a in answers] == ["43181001", "43171000", "60171000"]
    assert int.from_bytes(answers[1][4:], "little") == 20


def test_stopped_node_is_not_responding(run):
    s, plain, _, _, _ = run
    gone = nodes_of(plain)["cs-gone"]
    assert gone["stopped_after"] == 15 and gone["frames_total"] == 15
    assert gone["cycles"] == 15
    node = {n["name"]: n for n in s["can"]["nodes"]}["cs-gone"]
    assert node["frames"] == 15
    assert node["status"]["worst_level"] == "ERROR"
    v = violations(s, "node:cs-gone", "ERROR")
    assert v and all("not responding" in x["what"] for x in v)
    # only after its last frame (both times in ms)
    last = when(plain["start"]) + datetime.timedelta(
        milliseconds=(gone["last_frame_ns"] - plain["start_ns"]) / 1e6 - 1)
    assert when(v[0]["time"]) >= last


def test_healthy_node_is_not_flagged_while_it_sends(run):
    s, plain, _, _, _ = run
    ok = nodes_of(plain)["cs-ok"]
    assert ok["burst_frames"] == 20
    assert ok["frames_total"] == ok["cycles"] + 20
    end = when(plain["end"])
    assert not [v for v in violations(s, "node:cs-ok") if when(v["time"]) < end]


def test_never_started_node_is_not_initialized(run):
    s, plain, _, _, _ = run
    absent = nodes_of(plain)["cs-absent"]
    assert not absent["started"] and absent["tid"] is None
    assert absent["frames_total"] == 0
    node = {n["name"]: n for n in s["can"]["nodes"]}["cs-absent"]
    assert node["frames"] == 0 and node["last_ago_ms"] is None
    assert node["status"]["worst_level"] == "WARN"
    v = violations(s, "node:cs-absent")
    assert v and all(x["level"] == "WARN" and x["what"].startswith("not initialized")
                     for x in v)


def test_emcy_is_an_error_naming_its_code(run):
    s, _, co, _, _ = run
    drive = nodes_of(co)["cs-drive"]
    assert drive["emcy_sent"] == 1
    assert drive["emcy"] == [{"after_cycle": 10, "code": 0x8130, "register": 1}]
    n5 = [c for c in s["can"]["canopen"] if c["node"] == 5][0]
    assert n5["emcy_frames"] == 1 and n5["emcy_code"] == 0x8130 and n5["emcy_register"] == 1
    assert n5["nmt_state"] == "operational"
    assert any("EMCY error code 0x8130" in v["what"]
               for v in violations(s, lambda c: canopen_comp(c, 5), "ERROR"))


def test_sdo_requests_answered(run):
    s, _, co, _, _ = run
    drive = nodes_of(co)["cs-drive"]
    assert drive["sdo_requests_received"] == SDO_REQUESTS
    assert drive["sdo_requests_answered"] == SDO_REQUESTS
    assert drive["frames_sent"]["0x585"] == SDO_REQUESTS
    assert co["sdo_thread"]["socket_drops"] == 0
    n5 = [c for c in s["can"]["canopen"] if c["node"] == 5][0]
    assert n5["sdo_responses"] == SDO_REQUESTS and n5["sdo_max_ns"] > 0


def test_heartbeat_stop_is_no_heartbeat(run):
    s, _, co, _, _ = run
    hb = nodes_of(co)["cs-hb"]
    assert hb["heartbeats_sent"] == 10 and hb["bootup_sent"] == 1
    assert hb["frames_sent"]["0x706"] == 11
    assert hb["pdos_sent"] == hb["cycles"] > 10  # the PDOs go on
    n6 = [c for c in s["can"]["canopen"] if c["node"] == 6][0]
    assert n6["status"]["worst_level"] == "ERROR"
    v = violations(s, lambda c: canopen_comp(c, 6), "ERROR")
    assert v and v[0]["what"].startswith("no heartbeat for ")


def test_error_frame_makes_the_controller_error_passive(run):
    s, plain, _, _, _ = run
    assert [e["sent"] for e in plain["error_frames"]] == [True]
    f = can_ifs(s)["vcan0"]
    assert f["error_frames"] == plain["error_frames_sent"] == 1
    assert f["error_classes"]["controller"] == 1
    assert sum(f["error_classes"].values()) == 1
    what = " | ".join(v["what"] for v in violations(s, "vcan0"))
    assert "1 error frames in the last interval" in what
    assert "controller error-passive (rx)" in what


def test_check_exits_2(run):
    s, _, _, _, out = run
    assert (out / "trace.exit").read_text().strip() == "2"
    assert s["worst_level"] == "ERROR"


def test_signals_still_write_the_summary(run):
    _, plain, co, term, _ = run
    assert plain["ended_by"] == "duration" and plain["duration_ms"] == 2000
    assert co["ended_by"] == "SIGINT" and co["duration_ms"] == 0
    assert term["ended_by"] == "SIGTERM" and term["duration_ms"] == 0
    n = term["nodes"][0]
    assert n["frames_sent"] == {"0x100": n["frames_total"]} and n["frames_total"] > 0


@pytest.mark.parametrize("args, msg", [
    (["-n", "a:0x181:10"], "-i: which CAN interface?"),
    (["-i", "vcan0", "-n", "a:0x18g:10"], "'0x18g' is not a valid hex number"),
    (["-i", "vcan0", "-n", "a:5:10", "--fault", "a:emcy@3:1"], "emcy needs --canopen"),
    (["-i", "vcan0", "-n", "a:1:10", "--fault", "b:stop@3"], "no node named 'b'"),
    (["-i", "vcan0", "--canopen", "-n", "a:128:10"], "must be in 1..127"),
    (["-i", "vcan0", "-n", "a:1:10", "-d", "100", "--fault", "errframe@100"],
     "not before the end"),
    (["-i", "no-such-if0", "-n", "a:1:10"], "no-such-if0: no such network interface"),
])
def test_cli_errors_are_one_line(args, msg):
    """No VM needed: bad arguments fail before any CAN socket is opened."""
    if not CANSIM.exists():
        if IN_CI:
            pytest.fail("CI=true and build/rtsup-cansim is not built")
        pytest.skip("build/rtsup-cansim is not built (run make)")
    r = subprocess.run([str(CANSIM)] + args, capture_output=True, text=True, timeout=10)
    assert r.returncode == 1
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("rtsup-cansim: ")
    assert msg in r.stderr
