# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""What arm64 must show, run inside the arm64 PREEMPT_RT guest by
test_guest_arm64.py with the cross-built binaries (RTSUP_BUILD=build-arm64).
Its name is not test_*: the host's own test run does not collect it.

Every assertion is a count that does not depend on timing: what the
generator injected, or how many frames cangen sent. Emulated time is slow
(RTSUP_TEST_EMULATED=1: the generator's period is 5 ms)."""
import platform
import subprocess
import time

import pytest

from conftest import IN_CI, Trace, run_supervised, threads_by_tid

pytestmark = pytest.mark.usefixtures("bpf")


def test_running_on_arm64():
    """The checks below mean something only on the other architecture."""
    assert platform.machine() == "aarch64"
    assert "PREEMPT_RT" in platform.version()


# tp_btf reads syscall arguments with plain loads (PT_REGS_PARM*_SYSCALL,
# orig_x0 for the first on arm64), raw_tp through CO-RE reads: both paths
@pytest.mark.parametrize("mode", ["tp_btf", "raw_tp"])
def test_injected_faults_reported_exactly(tmp_path, mode):
    """mmap, openat, write and page faults injected into cycles are reported
    with the generator's exact counts, mmap by its name: arm64 numbers it
    222 through __NR3264_mmap, a table that dropped the alias would miss it.
    The cycles end in clock_nanosleep(TIMER_ABSTIME): their count shows the
    timespec (third argument) read right."""
    faults = ["-f", "mmap/100,thread=1", "-f", "openat@50,thread=0",
              "-f", "write@60,thread=0", "-f", "write@70,thread=0",
              "-f", "pagefault:3@40", "-f", "pagefault:2@150,thread=1"]
    truth, _, summary = run_supervised(
        tmp_path, ["-w", "20", "-c", "300"] + faults,
        ["--raw-tp"] if mode == "raw_tp" else [])
    got = threads_by_tid(summary)
    t0, t1 = truth["threads"]
    # the truth is what we asked for
    assert t0["syscalls"].get("openat") == 1 and t0["syscalls"].get("write") == 2
    assert t1["syscalls"].get("mmap") == 3 and t1["page_faults"] == 5
    assert t0["page_faults"] == 3
    for t in truth["threads"]:
        tot = got[t["tid"]]["total"]
        assert got[t["tid"]]["mode"] == "delimiter"
        # as on x86 (test_trace.py): a cycle's edges seen by two clocks
        assert abs(tot["cycles"] - t["cycles"]) <= t["cycles"] * 0.01
        assert tot["page_faults"]["minor"] == t["page_faults"]
        assert tot["unsafe"]["minor_fault"] == t["page_faults"]
        unsafe_truth = {k: v for k, v in t["syscalls"].items() if k != "futex"}
        assert tot["unsafe_syscalls"] == unsafe_truth
        assert tot["unsafe"]["syscall"] == sum(unsafe_truth.values())
        # a compat (AArch32) syscall would be counted, not classified
        assert tot.get("compat_syscalls", 0) == 0
    assert got[t1["tid"]]["total"]["unsafe_syscalls"]["mmap"] == 3


FLOOD = 20000


def test_vcan_flood_counted_exactly(tmp_path):
    """cangen -g 0 floods FLOOD frames on a vcan: every one is counted, with
    its id and bytes, none lost, none counted twice (the loopback)."""
    r = subprocess.run("ip link add dev vcanarm type vcan && ip link set up vcanarm",
                       shell=True, capture_output=True, text=True)
    if r.returncode != 0:
        if IN_CI:
            pytest.fail("CI=true and no vcan here: " + r.stderr.strip())
        pytest.skip("no vcan: " + r.stderr.strip())
    try:
        tr = Trace(["--can", "vcanarm", "-i", "2s"])
        try:
            subprocess.run(["cangen", "vcanarm", "-I", "321", "-L", "8", "-g", "0",
                            "-n", str(FLOOD)], check=True, timeout=300)
            time.sleep(1)  # the last frames' events drain
        finally:
            _, s, _ = tr.stop()
    finally:
        subprocess.run(["ip", "link", "del", "vcanarm"])
    ids = {(i["interface"], i["id"], i["dir"]): i for i in s["can"]["ids"]}
    assert list(ids) == [("vcanarm", "0x321", "tx")]
    assert ids[("vcanarm", "0x321", "tx")]["frames"] == FLOOD
    f = {x["interface"]: x for x in s["can"]["interfaces"]}["vcanarm"]
    assert f["frames_tx"] == FLOOD and f["loopback"] == FLOOD and f["frames_rx"] == 0
    assert f["bytes"] == FLOOD * 8
    assert s["lost_events"] == 0 and s["can"]["frames_not_counted_by_id"] == 0
