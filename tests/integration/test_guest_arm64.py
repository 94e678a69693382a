# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""arm64: the cross-built rtsup (make cross-arm64, build-arm64/) inside
Debian's arm64 PREEMPT_RT kernel under qemu-system-aarch64 (scripts/vm-test
--kernel rt-arm64, TCG), on an arm64 Debian 12 root file system.

The guest runs guest_arm64_checks.py: injected faults counted exactly, mmap
by name, a vcan flood counted exactly. Not the whole thread and CAN suites:
an emulated arm64 CPU on this x86 host is several times slower than the x86
guests, and CI's budget for arm64 is a few minutes (docs/arm64.md)."""
import re
import subprocess

import pytest

from conftest import IN_CI, ROOT

VM = ROOT / "scripts" / "vm-test"
KERNEL = "rt-arm64"
BUILD = "build-arm64"
CHECKS = "tests/integration/guest_arm64_checks.py"
# what the checks file holds: every one must pass, none may be skipped
EXPECTED = 4


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


def test_arm64_checks_pass_in_guest():
    why = not_ready()
    if why:
        if IN_CI:
            pytest.fail("CI=true and " + why)
        pytest.skip(why)
    r = subprocess.run([str(VM), "run", "--kernel", KERNEL, "--timeout", "600", "-v", "--",
                        "env", "CI=true", "RTSUP_TEST_EMULATED=1", "RTSUP_BUILD=" + BUILD,
                        "PYTHONDONTWRITEBYTECODE=1", "/usr/bin/python3", "-m", "pytest",
                        "-v", "-rs", "-p", "no:cacheprovider", CHECKS],
                       capture_output=True, text=True, timeout=900, cwd=ROOT)
    tail = "\n".join(r.stdout.splitlines()[-40:])
    print(tail + "\n" + r.stderr[-600:])
    assert r.returncode == 0, tail + r.stderr[-2000:]
    m = re.search(r"(\d+) passed", tail)
    assert m and int(m.group(1)) == EXPECTED, tail
    assert "skipped" not in tail and "failed" not in tail, tail
