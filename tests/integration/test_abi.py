# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""A 32-bit program's syscalls have other numbers: counted, never classified
with the 64-bit table (issue 12, item 10)."""
import json
import subprocess

import pytest

from conftest import ROOT, TRACE

pytestmark = pytest.mark.usefixtures("bpf")

PROG32 = ROOT / "build" / "progs32" / "abi32_loop"


def test_32bit_program_not_classified_wrongly(tmp_path):
    # i386 write is x86_64 stat and close is lstat: read with our table, a
    # 32-bit loop writing to /dev/null would be 500 RT-unsafe "stat" calls
    cfg = tmp_path / "rt.yaml"
    cfg.write_text("rules:\n  - name: loop32\n    match: {thread: abi32_loop}\n")
    r = subprocess.run([str(TRACE), "-j", "--config", str(cfg), "--", str(PROG32), "500"],
                       capture_output=True, text=True, timeout=120)
    objs = [json.loads(x) for x in r.stdout.splitlines() if x.startswith("{")]
    truth = [o for o in objs if "writes" in o][0]
    summary = [o for o in objs if o.get("type") == "summary"][0]
    [t] = [t for t in summary["threads"] if t["tid"] == truth["tid"]]
    tot = t["total"]
    assert truth["writes"] == 500
    # nothing of the 32-bit program classified, no delimiter (activations only).
    # Only the 64-bit execve that makes the child the program may count: on a
    # noisy machine the child waits for a CPU before it, which opens an activation
    sys64 = tot["unsafe_syscalls"]
    assert set(sys64) <= {"execve"} and sys64.get("execve", 0) <= 1, sys64
    assert tot["unsafe"]["syscall"] <= 1, tot["unsafe"]
    assert t["mode"] != "delimiter"
    # every sleep and write of the loop was seen and counted as 32-bit
    assert tot["compat_syscalls"] >= 2 * truth["cycles"]
    # and the verdict says so, by check
    abi = [c for c in t["status"]["checks"] if c["check"] == "abi"] or \
        [c for v in summary["violations"] for c in v["checks"] if c["check"] == "abi"]
    assert abi and abi[0]["level"] == "WARN", (t["status"], summary["violations"])
    assert abi[0]["counts"]["compat_syscalls"] >= 2 * truth["cycles"]
