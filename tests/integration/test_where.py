# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""Where in the code (issue 15): the user stack of each RT-unsafe event,
symbolized, counted per (thread, reason, stack).

progs/where_loop.c maps and unmaps a page from ctrl_update() every other
cycle of its thread "ctrl" and prints how often it did (on stderr). Built with frame
pointers (where_loop_fp) and -O2 -g without them (where_loop_dwarf). The
truth: the program's own counts, and the source lines marked WHERE_MMAP,
WHERE_MUNMAP and WHERE_CALL in it.
"""
import json
import platform
import shutil
import signal
import subprocess

import pytest

from conftest import BUILD, ROOT, TRACE

pytestmark = pytest.mark.usefixtures("bpf")

SRC = ROOT / "tests" / "integration" / "progs" / "where_loop.c"
PROGS = {"fp": BUILD / "progs" / "where_loop_fp", "dwarf": BUILD / "progs" / "where_loop_dwarf",
         "lib": BUILD / "progs" / "where_loop_lib"}
LIB_SRC = ROOT / "tests" / "integration" / "progs" / "where_lib.c"
CYCLES, PERIOD_US, EVERY = 200, 5000, 4


def marker_line(tag, src=SRC):
    """The source line that carries the /* tag */ comment."""
    [n] = [i for i, line in enumerate(src.read_text().splitlines(), 1) if tag in line]
    return n


def run(prog, stacks, extra=()):
    """rtsup-trace --stacks over the program: (its truth, the JSON summary)."""
    r = subprocess.run([str(TRACE), "-j", "--stacks", stacks, *extra, "--", str(prog),
                        str(CYCLES), str(PERIOD_US), str(EVERY)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    # the program's truth on stderr, with the tracer's banner
    truth = [json.loads(x) for x in r.stderr.splitlines() if x.startswith('{"tid"')][0]
    summary = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]
    return truth, summary


def ctrl_stacks(truth, summary, syscall):
    """The stacks of one syscall of the ctrl thread."""
    [t] = [t for t in summary["threads"] if t["tid"] == truth["tid"]]
    return t, [s for s in t["stacks"] if s.get("syscall") == syscall]


def named(frames):
    """(function, file name, line) of each frame, what is known of it."""
    return [(f.get("function"), f.get("file", "").rsplit("/", 1)[-1] or None, f.get("line"))
            for f in frames]


def check_frames(frames, innermost_line):
    """ctrl_update() at the unsafe call, its caller ctrl_loop() at the call to it."""
    names = named(frames)
    fn = [n[0] for n in names]
    assert "ctrl_update" in fn and "ctrl_loop" in fn, names
    i = fn.index("ctrl_update")
    # frame i+1 is ctrl_update's caller: nothing skipped, nothing invented
    assert fn[i + 1] == "ctrl_loop", names
    assert names[i] == ("ctrl_update", "where_loop.c", innermost_line), names
    assert names[i + 1] == ("ctrl_loop", "where_loop.c", marker_line("WHERE_CALL")), names


@pytest.mark.parametrize("mode", ["fp", "dwarf"])
@pytest.mark.parametrize("raw_tp", [False, True], ids=["tp_btf", "raw_tp"])
def test_mmap_named_with_line_and_counted_exactly(mode, raw_tp):
    truth, summary = run(PROGS[mode], mode, ["--raw-tp"] if raw_tp else [])
    assert truth["mmap"] == truth["munmap"] == CYCLES // EVERY
    health = summary["stack_records"]
    # none lost: 150 events a second (mmap, its page fault, munmap) stay in the
    # budget of 256 per thread and interval; the ring holds a budget's worth
    assert health["lost"] == health["over_budget"] == 0, health
    # unreadable: DWARF copies from the stack pointer, and a fault on a stack
    # page not yet there (a stack growing) has nothing to copy. Each is
    # counted, and is a page fault's stack without frames: no syscall's
    empty = [s for t in summary["threads"] for s in t["stacks"] if not s["frames"]]
    assert all(s["reason"] == "page_fault" for s in empty), empty
    assert sum(s["count"] for s in empty) == health["unreadable"], (empty, health)
    if mode == "fp":
        assert health["unreadable"] == 0, health
    for syscall, tag in (("mmap", "WHERE_MMAP"), ("munmap", "WHERE_MUNMAP")):
        t, st = ctrl_stacks(truth, summary, syscall)
        # each call, one stack: the count is the program's own, exactly
        assert len(st) == 1, [named(s["frames"]) for s in st]
        assert st[0]["count"] == truth[syscall], st[0]
        assert t["total"]["unsafe_syscalls"][syscall] == truth[syscall]
        check_frames(st[0]["frames"], marker_line(tag))
        if mode == "fp":
            # the syscall instruction is ours (WHERE_RAW_SYSCALL): in do_mmap/do_munmap
            assert st[0]["frames"][0]["function"].startswith("do_" + syscall)
        else:
            # DWARF unwinds through glibc's wrapper, built without frame pointers
            assert st[0]["frames"][0]["module"].rsplit("/", 1)[-1].startswith("libc.so")


@pytest.mark.skipif(platform.machine() != "x86_64",
                    reason="exceptions:page_fault_user is x86's tracepoint")
@pytest.mark.parametrize("mode", ["fp", "dwarf"])
def test_page_fault_named_at_the_touch(mode):
    """The first touch of each fresh page faults once, at WHERE_TOUCH."""
    truth, summary = run(PROGS[mode], mode)
    [t] = [t for t in summary["threads"] if t["tid"] == truth["tid"]]
    touch = [s for s in t["stacks"] if s["reason"] == "page_fault" and s["frames"] and
             named(s["frames"])[0] == ("ctrl_update", "where_loop.c", marker_line("WHERE_TOUCH"))]
    # one stack, one fault per page mapped: the program's count exactly
    assert len(touch) == 1, [named(s["frames"]) for s in t["stacks"]]
    assert touch[0]["count"] == truth["mmap"]
    # the fault's pc is exact (no return address): its caller is ctrl_loop
    assert named(touch[0]["frames"])[1] == ("ctrl_loop", "where_loop.c", marker_line("WHERE_CALL"))
    # and the cycle counters saw at least those faults
    assert t["total"]["page_faults"]["minor"] >= truth["mmap"]


def test_shared_library_frames_named():
    """The unsafe call inside a .so of ours: its frame and the program's, both named."""
    truth, summary = run(PROGS["lib"], "dwarf")
    for syscall, lib_fn, lib_tag, tag in (("mmap", "lib_map", "LIB_MMAP", "WHERE_MMAP"),
                                          ("munmap", "lib_unmap", "LIB_MUNMAP", "WHERE_MUNMAP")):
        _, st = ctrl_stacks(truth, summary, syscall)
        assert len(st) == 1 and st[0]["count"] == truth[syscall], st
        frames = st[0]["frames"]
        names = named(frames)
        i = [n[0] for n in names].index(lib_fn)
        assert names[i] == (lib_fn, "where_lib.c", marker_line(lib_tag, LIB_SRC)), names
        assert frames[i]["module"].endswith("/libwhere.so"), frames[i]
        # its caller, in the program: nothing skipped between the two modules
        assert names[i + 1] == ("ctrl_update", "where_loop.c", marker_line(tag)), names
        assert frames[i + 1]["module"] == str(PROGS["lib"]), frames[i + 1]


def test_stripped_binary_gives_module_and_offset(tmp_path):
    """No symbols: module+offset, which addr2line on the unstripped build names."""
    prog = tmp_path / "where_loop_stripped"
    shutil.copy(PROGS["dwarf"], prog)
    subprocess.run(["strip", "-s", str(prog)], check=True)
    truth, summary = run(prog, "dwarf")
    _, [st] = ctrl_stacks(truth, summary, "mmap")
    assert st["count"] == truth["mmap"]
    ours = [f for f in st["frames"] if f.get("module") == str(prog)]
    # the .eh_frame survives strip: the unwind still reaches ctrl_loop and main's thread
    assert len(ours) >= 3, st["frames"]
    for f in ours:
        # never a wrong name: without symbols none at all
        assert "function" not in f and "line" not in f, f
    # ctrl_update's frame is a return address: the call is the byte before it
    r = subprocess.run(["addr2line", "-f", "-e", str(PROGS["dwarf"]),
                        hex(ours[0]["offset"] - 1)], capture_output=True, text=True, check=True)
    func, where = r.stdout.split()
    assert func == "ctrl_update" and where.endswith(":%d" % marker_line("WHERE_MMAP")), r.stdout


def test_budget_counts_what_it_does_not_capture():
    """Beyond --stack-budget per thread and interval: counted, not captured."""
    truth, summary = run(PROGS["dwarf"], "dwarf", ["--stack-budget", "5", "-i", "60s"])
    [t] = [t for t in summary["threads"] if t["tid"] == truth["tid"]]
    captured = sum(s["count"] for s in t["stacks"])
    # one interval for the whole run: the thread's first 5 events only
    assert captured == 5, t["stacks"]
    assert summary["stack_records"]["over_budget"] >= truth["mmap"] + truth["munmap"] - 5


def test_stacks_off_by_default():
    r = subprocess.run([str(TRACE), "-j", "--", str(PROGS["dwarf"]), "10", "1000", "2"],
                       capture_output=True, text=True, timeout=60)
    summary = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]
    assert "stack_records" not in summary
    assert all("stacks" not in t for t in summary["threads"])


@pytest.mark.parametrize("size", ["100", "1M", "65537", "8K1"])
def test_bad_stack_size_one_line(size):
    r = subprocess.run([str(TRACE), "--stacks", "dwarf", "--stack-size", size, "-p", "1"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 1
    assert len(r.stderr.splitlines()) >= 1 and "--stack-size" in r.stderr.splitlines()[0], \
        r.stderr


def test_perfetto_shows_the_stack(tmp_path):
    """--perfetto: an instant event per captured stack, the frames in its args."""
    pf = tmp_path / "where.json"
    truth, _ = run(PROGS["dwarf"], "dwarf", ["--perfetto", str(pf)])
    ev = [e for e in json.loads(pf.read_text())["traceEvents"]
          if e.get("name") == "where: mmap" and e["tid"] == truth["tid"]]
    assert len(ev) == truth["mmap"]
    assert all("<- ctrl_update() where_loop.c:%d\n" % marker_line("WHERE_MMAP")
               in e["args"]["stack"] for e in ev), ev[0]


def test_replay_gives_the_same_stacks(tmp_path):
    """--record keeps the stacks' pcs and the mappings; replay symbolizes them again."""
    rec = tmp_path / "where.rtsup"
    truth, live = run(PROGS["dwarf"], "dwarf", ["--record", str(rec)])
    r = subprocess.run([str(TRACE), "replay", str(rec), "-j"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    replayed = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]

    def stacks(summary):
        return sorted((t["tid"], s["reason"], s.get("syscall", ""), s["count"],
                       repr(named(s["frames"]))) for t in summary["threads"]
                      for s in t.get("stacks", []))
    assert stacks(replayed) == stacks(live)
    _, [st] = ctrl_stacks(truth, replayed, "mmap")
    assert st["count"] == truth["mmap"]
    check_frames(st["frames"], marker_line("WHERE_MMAP"))


def test_replay_with_another_build_names_nothing_wrong(tmp_path):
    """At replay the program's path holds another build: its frames keep module,
    offset and the recorded build-id, and name no function."""
    prog, rec = tmp_path / "where_loop", tmp_path / "where.rtsup"
    shutil.copy(PROGS["dwarf"], prog)
    truth, live = run(prog, "dwarf", ["--record", str(rec)])
    _, [lst] = ctrl_stacks(truth, live, "mmap")
    shutil.copy(PROGS["fp"], prog)	# another build at the same path
    r = subprocess.run([str(TRACE), "replay", str(rec), "-j"], capture_output=True, text=True,
                       timeout=60)
    replayed = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]
    _, [st] = ctrl_stacks(truth, replayed, "mmap")
    assert st["count"] == truth["mmap"]
    ours = [f for f in st["frames"] if f.get("module") == str(prog)]
    live_ours = [f for f in lst["frames"] if f.get("module") == str(prog)]
    assert len(ours) == len(live_ours) >= 3, st["frames"]
    for f, lf in zip(ours, live_ours):
        assert "function" not in f and "line" not in f, f
        assert f["offset"] == lf["offset"] and f["build_id"] == lf["build_id"], (f, lf)
    # libc is the same build here: still named
    assert st["frames"][0]["function"] == lst["frames"][0]["function"]


def test_cpp_member_function_named_demangled():
    """C++: operator new of a big block in ctrl::Loop::update(), -O2 -g, no frame pointers."""
    src = ROOT / "tests" / "integration" / "progs" / "where_cpp.cpp"
    r = subprocess.run([str(TRACE), "-j", "--stacks", "dwarf", "--", str(BUILD / "progs" / "where_cpp"),
                        "200", "10000"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    truth = [json.loads(x) for x in r.stderr.splitlines() if x.startswith('{"tid"')][0]
    summary = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]
    assert truth["news"] == 100
    # 50 blocks a second, each an mmap, a fault and a munmap: within the budget
    assert summary["stack_records"]["over_budget"] == 0, summary["stack_records"]
    t, st = ctrl_stacks(truth, summary, "mmap")
    # every mmap of the thread came from update(): its blocks, and once the
    # thread's malloc arena (its first allocation), another path in glibc
    assert all("ctrl::Loop::update(long)" in [n[0] for n in named(s["frames"])] for s in st), st
    assert sum(s["count"] for s in st) == t["total"]["unsafe_syscalls"]["mmap"]
    blocks = [s for s in st if s["count"] == truth["news"]]
    assert len(blocks) == 1, st
    names = named(blocks[0]["frames"])
    fn = [n[0] for n in names]
    i = fn.index("ctrl::Loop::update(long)")
    assert names[i] == ("ctrl::Loop::update(long)", "where_cpp.cpp", marker_line("CPP_NEW", src))
    assert names[i + 1] == ("ctrl::Loop::run()", "where_cpp.cpp", marker_line("CPP_CALL", src))
    # through glibc's malloc and libstdc++'s operator new, both without frame pointers
    assert "operator new(unsigned long)" in fn[:i], names


# ---- issue 15's second part: auto, a rule's stacks, the vDSO ----

NOLIBC, NOLIBC_SRC = BUILD / "progs" / "where_nolibc", ROOT / "tests/integration/progs/where_nolibc.c"
VDSO, VDSO_SRC = BUILD / "progs" / "where_vdso", ROOT / "tests/integration/progs/where_vdso.c"


def run_cmd(argv, args, comm):
    """rtsup-trace ARGS --pid over the program: (its truth, the JSON summary).

    The program waits on its stdin before its first cycle. It is let go once
    rtsup-trace has printed two intervals with its thread COMM: the rule of a
    thread is matched in one interval and written into the kernel right after
    it (collector_apply_rules), and auto's verdict is in since the start-up
    scan read its mappings. Nothing before depends on the time it takes (a
    slow guest's first interval may last seconds)."""
    prog = subprocess.Popen([str(a) for a in argv], stdin=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    tr = subprocess.Popen([str(TRACE), "-j", "-i", "200ms", *args, "--pid", str(prog.pid)],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        seen = 0
        for line in tr.stdout:
            if line.startswith('{"type":"interval"') and any(
                    t["comm"] == comm for t in json.loads(line)["threads"]):
                seen += 1
                if seen == 2:
                    break
        assert seen == 2, tr.stderr.read()
        prog.stdin.write("go\n")
        prog.stdin.close()
        err = prog.stderr.read()
        assert prog.wait(timeout=120) == 0, err
    finally:
        prog.kill()
        tr.send_signal(signal.SIGINT)
        out, trerr = tr.communicate(timeout=120)
    assert tr.returncode == 0, trerr
    truth = [json.loads(x) for x in err.splitlines() if x.startswith('{"tid"')][0]
    summary = [json.loads(x) for x in out.splitlines() if '"summary"' in x][0]
    return truth, summary


def vdso_config(tmp_path, stacks=None):
    """clock_gettime unsafe for the thread ctrl; its stacks: when given."""
    cfg = tmp_path / "where.yaml"
    cfg.write_text("rules:\n  - name: ctrl\n    match: {thread: ctrl}\n"
                   "    forbid_syscalls: [clock_gettime]\n" +
                   ("    stacks: %s\n" % stacks if stacks else ""))
    return cfg


def thread_of(truth, summary):
    [t] = [t for t in summary["threads"] if t["tid"] == truth["tid"]]
    return t


@pytest.mark.skipif(platform.machine() != "x86_64", reason="where_nolibc makes x86 syscalls")
def test_auto_takes_fp_where_every_module_keeps_them():
    """No C library, frame pointers: the program and the vDSO keep them, auto walks them."""
    truth, summary = run_cmd([NOLIBC, 100, 5000, 2], ["--stacks", "auto"], "where_nolibc")
    assert truth["mmap"] == truth["munmap"] == 50
    for syscall, tag in (("mmap", "WHERE_NOLIBC_MMAP"), ("munmap", "WHERE_NOLIBC_MUNMAP")):
        _, st = ctrl_stacks(truth, summary, syscall)
        assert len(st) == 1 and st[0]["count"] == truth[syscall], st
        # every one by frame pointers: the verdict was in before the first cycle
        assert st[0]["unwinders"] == ["fp"], st[0]
        names = named(st[0]["frames"])
        fn = [n[0] for n in names]
        i = fn.index("ctrl_update")
        assert names[i] == ("ctrl_update", "where_nolibc.c", marker_line(tag, NOLIBC_SRC)), names
        assert names[i + 1] == ("ctrl_loop", "where_nolibc.c",
                                marker_line("WHERE_NOLIBC_CALL", NOLIBC_SRC)), names
        # the syscall's own frame above it (sys, maybe a clone of it): nothing skipped
        assert i == 1 and fn[0].startswith("sys"), names


def test_auto_takes_dwarf_when_a_module_omits_them(tmp_path):
    """where_vdso_fp keeps frame pointers, Debian's glibc does not: auto is DWARF,
    and the stack through glibc and the vDSO is whole."""
    fp = BUILD / "progs" / "where_vdso_fp"
    truth, summary = run_cmd([fp, 100, 5000, 2],
                             ["--stacks", "auto", "--config", str(vdso_config(tmp_path))], "ctrl")
    _, st = ctrl_stacks(truth, summary, "clock_gettime")
    assert len(st) == 1 and st[0]["count"] == truth["cputime"] == 50, st
    assert st[0]["unwinders"] == ["dwarf"], st[0]
    names = named(st[0]["frames"])
    fn = [n[0] for n in names]
    i = fn.index("ctrl_update")
    assert names[i] == ("ctrl_update", "where_vdso.c", marker_line("WHERE_CPUTIME", VDSO_SRC)), names
    assert names[i + 1] == ("ctrl_loop", "where_vdso.c",
                            marker_line("WHERE_VDSO_CALL", VDSO_SRC)), names


def test_vdso_frame_named(tmp_path):
    """The unsafe syscall made inside the vDSO: its frame is named, and the unwind
    goes on through it to the program."""
    truth, summary = run_cmd([VDSO, 100, 5000, 2],
                             ["--stacks", "dwarf", "--config", str(vdso_config(tmp_path))], "ctrl")
    assert truth["cputime"] == 50
    t, st = ctrl_stacks(truth, summary, "clock_gettime")
    assert t["total"]["unsafe_syscalls"]["clock_gettime"] == truth["cputime"]
    assert len(st) == 1 and st[0]["count"] == truth["cputime"], [
        (s["count"], [(f.get("module", "").rsplit("/", 1)[-1], f.get("function"), f.get("line"))
                      for f in s["frames"]]) for s in st]
    frames = st[0]["frames"]
    names = named(frames)
    # the syscall instruction is the vDSO's: its function, module [vdso], its build-id
    assert frames[0]["module"] == "[vdso]", frames[0]
    assert frames[0]["function"].endswith("clock_gettime"), frames[0]
    assert len(frames[0].get("build_id", "")) == 40, frames[0]
    fn = [n[0] for n in names]
    i = fn.index("ctrl_update")
    assert names[i] == ("ctrl_update", "where_vdso.c", marker_line("WHERE_CPUTIME", VDSO_SRC)), names
    assert names[i + 1] == ("ctrl_loop", "where_vdso.c",
                            marker_line("WHERE_VDSO_CALL", VDSO_SRC)), names
    # between them only glibc's clock_gettime
    assert all(f["module"].rsplit("/", 1)[-1].startswith("libc.so") for f in frames[1:i]), frames


def test_vdso_frame_named_at_replay(tmp_path):
    """The recorded trace keeps the vDSO's build-id; replay names its frames from
    the vDSO of the replaying process when the kernel build is the same."""
    rec = tmp_path / "where.rtsup"
    truth, live = run_cmd([VDSO, 60, 5000, 2],
                          ["--stacks", "dwarf", "--config", str(vdso_config(tmp_path)),
                           "--record", str(rec)], "ctrl")
    r = subprocess.run([str(TRACE), "replay", str(rec), "-j"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    replayed = [json.loads(x) for x in r.stdout.splitlines() if '"summary"' in x][0]
    _, [lst] = ctrl_stacks(truth, live, "clock_gettime")
    _, [st] = ctrl_stacks(truth, replayed, "clock_gettime")
    assert st["count"] == lst["count"] == truth["cputime"]
    assert named(st["frames"]) == named(lst["frames"])
    assert st["frames"][0]["module"] == "[vdso]"
    assert st["frames"][0]["function"] == lst["frames"][0]["function"]
    assert st["unwinders"] == ["dwarf"]


def test_rule_turns_stacks_on_for_its_threads(tmp_path):
    """--stacks off, a rule's stacks: dwarf: its thread's stacks, all of them."""
    truth, summary = run_cmd([VDSO, 100, 5000, 2],
                             ["--config", str(vdso_config(tmp_path, "dwarf"))], "ctrl")
    _, st = ctrl_stacks(truth, summary, "clock_gettime")
    assert len(st) == 1 and st[0]["count"] == truth["cputime"], st
    assert st[0]["unwinders"] == ["dwarf"]
    assert "ctrl_update" in [n[0] for n in named(st[0]["frames"])]


def test_rule_turns_stacks_off_for_its_threads(tmp_path):
    """--stacks dwarf, a rule's stacks: off: its thread's events counted, no stack."""
    truth, summary = run_cmd([VDSO, 100, 5000, 2],
                             ["--stacks", "dwarf", "--config", str(vdso_config(tmp_path, "off"))], "ctrl")
    t = thread_of(truth, summary)
    assert t["total"]["unsafe_syscalls"]["clock_gettime"] == truth["cputime"] == 50
    assert not t.get("stacks"), t["stacks"]
    # the other threads' stacks are all the records taken: none was ctrl's
    others = sum(s["count"] for o in summary["threads"] for s in o.get("stacks", []))
    assert summary["stack_records"]["records"] == others, summary["stack_records"]


def test_rule_picks_the_unwinder(tmp_path):
    """--stacks dwarf, a rule's stacks: fp: its thread's stacks by frame pointers."""
    truth, summary = run_cmd([VDSO, 100, 5000, 2],
                             ["--stacks", "dwarf", "--config", str(vdso_config(tmp_path, "fp"))], "ctrl")
    _, st = ctrl_stacks(truth, summary, "clock_gettime")
    assert sum(s["count"] for s in st) == truth["cputime"], st
    assert all(s["unwinders"] == ["fp"] for s in st), st
    # the vDSO keeps frame pointers: its frame first, named, and its caller in glibc
    assert all(s["frames"][0]["module"] == "[vdso]" for s in st), st


@pytest.mark.parametrize("value, why", [
    ("lbr", "unknown stacks 'lbr' (want off, fp, dwarf or auto)"),
    ("dwarf\n    stack_size: 100",
     "bad stack_size '100' (want bytes, a multiple of 8 from 512 to 64K, e.g. 8K)")])
def test_bad_rule_stacks_one_line(tmp_path, value, why):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("rules:\n  - name: ctrl\n    stacks: %s\n" % value)
    r = subprocess.run([str(TRACE), "--config", str(cfg), "-p", "1"], capture_output=True,
                       text=True, timeout=30)
    assert r.returncode == 1
    [line] = r.stderr.splitlines()
    assert line.startswith("rtsup-trace: %s:" % cfg) and line.endswith(why), line
