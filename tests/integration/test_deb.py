# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""The Debian packages (make deb, debian/): lintian finds no error (make deb
fails otherwise); what each package holds; and in a vm-test guest under a
real systemd, on a root where rtsup never was: apt install ./rtsup_*.deb
enables and starts the service, which reports READY and STATUS; apt remove
stops it and keeps /etc/rtsup; apt purge removes /etc/rtsup."""
import json
import subprocess

import pytest

from conftest import IN_CI, ROOT

DEB_DIR = ROOT / "build" / "deb"


@pytest.fixture(scope="module")
def debs():
    r = subprocess.run(["make", "-C", str(ROOT), "deb"], capture_output=True, text=True,
                       timeout=1200)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "E: " not in r.stdout + r.stderr  # lintian's errors (--fail-on error too)
    found = {p.name.split("_")[0]: p for p in DEB_DIR.glob("*.deb")}
    assert {"rtsup", "rtsup-tools"} <= set(found), found
    return found


def contents(deb):
    r = subprocess.run(["dpkg-deb", "-c", str(deb)], capture_output=True, text=True,
                       check=True)
    return {l.split()[-1].lstrip(".") for l in r.stdout.splitlines()}


def control(deb, field):
    r = subprocess.run(["dpkg-deb", "-f", str(deb), field], capture_output=True, text=True,
                       check=True)
    return r.stdout.strip()


# the module's make deb (1200 s) counts here: pytest.ini's 600 s would cut it first
@pytest.mark.timeout(1300)
def test_packages_hold_what_they_should(debs, tmp_path):
    main = contents(debs["rtsup"])
    for f in ("/usr/bin/rtsup-trace", "/usr/share/man/man8/rtsup-trace.8.gz",
              "/lib/systemd/system/rtsup-trace.service", "/etc/rtsup/rtsup.yaml",
              "/etc/rtsup/rtsup-trace.env", "/etc/rtsup/listen.conf.example",
              "/etc/rtsup/ros2-diagnostics.conf.example"):
        assert f in main, sorted(main)
    assert "/usr/bin/rtsup-loadgen" not in main
    tools = contents(debs["rtsup-tools"])
    assert {"/usr/bin/rtsup-loadgen", "/usr/bin/rtsup-cansim"} <= tools, sorted(tools)
    # every file in /etc is a conffile; the unit's ExecStart names /usr/bin
    subprocess.run(["dpkg-deb", "-e", str(debs["rtsup"]), str(tmp_path / "ctl")], check=True)
    conf = (tmp_path / "ctl" / "conffiles").read_text().split()
    assert sorted(conf) == sorted(f for f in main if f.startswith("/etc/") and
                                  not f.endswith("/")), conf
    assert "deb-systemd-helper enable 'rtsup-trace.service'" in \
        (tmp_path / "ctl" / "postinst").read_text()
    subprocess.run(["dpkg-deb", "-x", str(debs["rtsup"]), str(tmp_path / "root")], check=True)
    unit = (tmp_path / "root/lib/systemd/system/rtsup-trace.service").read_text()
    assert "ExecStart=/usr/bin/rtsup-trace " in unit and "@BINDIR@" not in unit
    # the dlopen'ed libraries are suggested, never required: the default
    # install does not pull a DDS stack or an HTTP server
    assert "libddsc" not in control(debs["rtsup"], "Depends")
    assert "libddsc0debian" in control(debs["rtsup"], "Suggests")


# a guest set up (1800 s) and run (900 s): pytest.ini's 600 s would cut it first
@pytest.mark.timeout(2800)
def test_apt_install_starts_service_remove_purge_in_vm(debs):
    vmtest = ROOT / "scripts" / "vm-test"
    kernels = subprocess.run([str(vmtest), "kernels"], capture_output=True, text=True,
                             timeout=60).stdout
    if not kernels or "not set up" in kernels.splitlines()[0]:
        r = subprocess.run([str(vmtest), "setup"], capture_output=True, text=True, timeout=1800)
        if r.returncode != 0:
            msg = "scripts/vm-test setup failed: " + r.stderr[-2000:]
            if IN_CI:
                pytest.fail(msg)
            pytest.skip(msg)
    out = ROOT / "build" / "vm-deb"
    r = subprocess.run([str(vmtest), "run", "--init", "--timeout", "500", "--",
                        str(ROOT / "tests" / "integration" / "vm" / "deb-boot")],
                       capture_output=True, text=True, timeout=900)
    log = (out / "check.log").read_text() if (out / "check.log").exists() else ""
    assert (out / "result.json").exists(), "no result; vm-test said: %s\n%s\n%s" % (
        r.returncode, r.stderr[-3000:], log)
    res = json.loads((out / "result.json").read_text())
    for check in ("clean_root", "installed", "enabled", "started", "status", "conffiles",
                  "removed", "conf_kept", "purged"):
        assert res.get(check) == "1", "%s failed:\n%s" % (check, log)
    assert res["failed"] == 0, log
    # systemd was the guest's init (vm-test --init): it powered off, no exit status
    assert r.returncode == 125 and "without an exit status" in r.stderr, r.stderr[-2000:]
