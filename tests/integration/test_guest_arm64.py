# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""arm64: the cross-built rtsup (make cross-arm64, build-arm64/) inside
Debian's arm64 PREEMPT_RT kernel under qemu-system-aarch64 (scripts/vm-test
--kernel rt-arm64, TCG), on an arm64 Debian 12 root file system.

One boot runs a shell script (the guest has no Python: its root file system
stays small and quick to build); it writes what rtsup-trace reported and
what the generators did under build/, and the host compares them. Every
assertion is a count that does not depend on timing: what rtsup-loadgen
injected, how many frames cangen sent.

Not the whole thread and CAN suites: an emulated arm64 CPU on this x86 host
is several times slower than the x86 guests, and CI's budget for arm64 is a
few minutes (docs/arm64.md says what is left out)."""
import json
import shutil
import subprocess
import uuid

import pytest

from conftest import IN_CI, ROOT, threads_by_tid

VM = ROOT / "scripts" / "vm-test"
KERNEL = "rt-arm64"
BUILD = "build-arm64"
# the generator's period in the guest: 5 ms, as in the x86 guests (conftest)
PERIOD_US = 5000
CYCLES = 300
FAULTS = ("-f mmap/100,thread=1 -f openat@50,thread=0 -f write@60,thread=0 "
          "-f write@70,thread=0 -f pagefault:3@40 -f pagefault:2@150,thread=1")
FLOOD = 20000

# $B: the cross-built binaries, $O: the output directory (shared with the host)
SCRIPT = r"""
set -e
uname -m > $O/machine
uname -v > $O/version
# started () - wait for rtsup-trace's banner (its programs are attached)
started() {
	for i in $(seq 600); do grep -q "tracing with" $1 && return 0; sleep 0.1; done
	cat $1 >&2; return 1
}
# the loadgen's two periodic threads by name, as conftest.run_supervised does:
# --hold parks them after the last cycle, so the tracer sees only whole cycles
for mode in tp_btf raw_tp; do
	P=a64$mode
	X=; [ $mode = raw_tp ] && X=--raw-tp
	$B/rtsup-trace -j $X --comm=$P-0 --comm=$P-1 > $O/$mode.json 2> $O/$mode.err &
	TP=$!
	started $O/$mode.err
	$B/rtsup-loadgen --audit --hold --name $P -n 2 -P %(period)d -w 20 -c %(cycles)d \
		%(faults)s -s $O/$mode.truth > $O/$mode.lg.out 2>&1 &
	LP=$!
	for i in $(seq 3000); do
		[ -s $O/$mode.truth ] && break
		kill -0 $LP 2>/dev/null || { cat $O/$mode.lg.out >&2; exit 1; }
		sleep 0.1
	done
	sleep 1 # the summary written whole, the last events drained
	kill -INT $TP; rc=0; wait $TP || rc=$?; echo $rc > $O/$mode.rc
	kill $LP; wait $LP || true
done
ip link add dev vcanarm type vcan
ip link set up vcanarm
$B/rtsup-trace -j --can vcanarm -i 2s > $O/can.json 2> $O/can.err &
TP=$!
started $O/can.err
cangen vcanarm -I 321 -L 8 -g 0 -n %(flood)d
sleep 1
kill -INT $TP; rc=0; wait $TP || rc=$?; echo $rc > $O/can.rc
""" % {"period": PERIOD_US, "cycles": CYCLES, "faults": FAULTS, "flood": FLOOD}


def not_ready():
    """Why the arm64 guest cannot run here, or None."""
    r = subprocess.run([str(VM), "kernels"], capture_output=True, text=True)
    if not any(line.split()[:1] == [KERNEL] and " boot " in line
               for line in r.stdout.splitlines()):
        return "the %s VM is not set up (scripts/vm-test setup)" % KERNEL
    for b in ("rtsup-trace", "rtsup-loadgen"):
        if not (ROOT / BUILD / b).exists():
            return "%s/%s is not built (make cross-arm64)" % (BUILD, b)
    return None


@pytest.fixture(scope="module")
def guest():
    """Run SCRIPT in the arm64 guest once; the directory of what it wrote."""
    why = not_ready()
    if why:
        if IN_CI:
            pytest.fail("CI=true and " + why)
        pytest.skip(why)
    out = ROOT / "build" / ("arm64-test-" + uuid.uuid4().hex[:8])
    out.mkdir(parents=True)
    body = "cd %s\nB=%s\nO=%s\n%s" % (ROOT, BUILD, out, SCRIPT)
    r = subprocess.run([str(VM), "run", "--kernel", KERNEL, "--timeout", "400", "-v", "--",
                        "sh", "-c", body], capture_output=True, text=True, timeout=700)
    print(r.stderr[-600:])
    assert r.returncode == 0, r.stdout[-1000:] + r.stderr[-3000:]
    yield out
    shutil.rmtree(out, ignore_errors=True)


def trace_summary(path):
    objs = [json.loads(x) for x in open(path) if x.startswith("{")]
    summary = [o for o in objs if o["type"] == "summary"]
    assert len(summary) == 1, path
    return summary[0]


# the module's guest run (700 s) counts here: pytest.ini's 600 s would cut it first
@pytest.mark.timeout(800)
def test_running_on_arm64(guest):
    """The checks below mean something only on the other architecture."""
    assert (guest / "machine").read_text().strip() == "aarch64"
    assert "PREEMPT_RT" in (guest / "version").read_text()


# tp_btf reads syscall arguments with plain loads (PT_REGS_PARM*_SYSCALL,
# orig_x0 for the first on arm64), raw_tp through CO-RE reads: both paths
@pytest.mark.parametrize("mode", ["tp_btf", "raw_tp"])
def test_injected_faults_reported_exactly(guest, mode):
    """mmap, openat, write and page faults injected into cycles are reported
    with the generator's exact counts, mmap by its name: arm64 numbers it
    222 through __NR3264_mmap, a table that dropped the alias would miss it.
    The cycles end in clock_nanosleep(TIMER_ABSTIME): their count shows its
    timespec (third argument) read right."""
    assert (guest / (mode + ".rc")).read_text().strip() == "0", \
        (guest / (mode + ".err")).read_text()
    want = "tp_btf" if mode == "tp_btf" else "raw tracepoint"
    assert "tracing with %s programs" % want in (guest / (mode + ".err")).read_text()
    truth = json.loads((guest / (mode + ".truth")).read_text())
    got = threads_by_tid(trace_summary(guest / (mode + ".json")))
    t0, t1 = truth["threads"]
    # the truth is what we asked for
    assert t0["syscalls"].get("openat") == 1 and t0["syscalls"].get("write") == 2
    assert t1["syscalls"].get("mmap") == 3 and t1["page_faults"] == 5
    assert t0["page_faults"] == 3
    for t in truth["threads"]:
        tot = got[t["tid"]]["total"]
        assert got[t["tid"]]["mode"] == "delimiter"
        # as in test_trace.py: a cycle's edges, seen by two clocks
        assert abs(tot["cycles"] - t["cycles"]) <= t["cycles"] * 0.01
        assert tot["page_faults"]["minor"] == t["page_faults"]
        assert tot["unsafe"]["minor_fault"] == t["page_faults"]
        unsafe_truth = {k: v for k, v in t["syscalls"].items() if k != "futex"}
        assert tot["unsafe_syscalls"] == unsafe_truth
        assert tot["unsafe"]["syscall"] == sum(unsafe_truth.values())
        # an AArch32 syscall would be counted here, not classified
        assert tot["compat_syscalls"] == 0
    assert got[t1["tid"]]["total"]["unsafe_syscalls"]["mmap"] == 3


def test_vcan_flood_counted_exactly(guest):
    """cangen -g 0 floods FLOOD frames on a vcan: every one is counted, with
    its id and bytes, none lost, the loopback not counted twice."""
    assert (guest / "can.rc").read_text().strip() == "0", (guest / "can.err").read_text()
    s = trace_summary(guest / "can.json")
    ids = {(i["interface"], i["id"], i["dir"]): i for i in s["can"]["ids"]}
    assert list(ids) == [("vcanarm", "0x321", "tx")]
    assert ids[("vcanarm", "0x321", "tx")]["frames"] == FLOOD
    f = {x["interface"]: x for x in s["can"]["interfaces"]}["vcanarm"]
    assert f["frames_tx"] == FLOOD and f["loopback"] == FLOOD and f["frames_rx"] == 0
    assert f["bytes"] == FLOOD * 8
    assert s["lost_events"] == 0 and s["can"]["frames_not_counted_by_id"] == 0
