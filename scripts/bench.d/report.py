#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""report.py - docs/performance.md and docs/bench-*.png from the raw results
of scripts/bench (docs/bench-results.json). Nothing here measures: every
number in the report is computed from that file.

    python3 scripts/bench.d/report.py docs/bench-results.json
"""
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
DOCS = ROOT / "docs"
NOTES = Path(__file__).resolve().parent / "notes.md"

# the targets
T_PIPE_VS_FLOOR = 1.5
T_PIPE_ABS = 0.05
T_PEER_FACTOR = 2.0
T_NS = {"sched_switch": 60, "sched_wakeup": 30, "sys_enter": 10}
T_CAN_PCT = 2.0
T_USER_CPU_PCT = 0.1
T_VS_OWN_FLOOR = 1.2	# issue 19: --rt and per-syscall hooks against their floors
T_SYSCALL_PCT = 2.0	# issue 19: getppid with per-syscall hooks, against the baseline
T_USER_RSS_MIB = 16
# rtsup-trace's statistics window (user/main.c): 100 ms in every 30th 1 s interval
STATS_DUTY = 0.1 / 30

MAIN = ["floor", "rtsup", "floor_nostats", "rtsup_nostats"]
GUEST_LABEL = {"base": "without", "rtsup": "rtsup-trace as shipped",
               "nostats": "rtsup-trace --no-overhead",
               "floor": "floor: empty programs, --no-overhead"}
# the guest's getppid runs (guest.sh): the syscall hooks, ours and the floor's
GUEST_SYS_LABEL = {"raw": "rtsup-trace --no-overhead on raw_syscalls",
                   "per": "rtsup-trace --no-overhead, per-syscall hooks",
                   "rawfloor": "floor on raw_syscalls", "perfloor": "floor, per-syscall hooks"}
GUEST_SYS_HOOKS = {"raw": "raw_syscalls", "rawfloor": "raw_syscalls", "per": "per-syscall",
                   "perfloor": "per-syscall"}


def sys_slowdown(g, v):
    """The guest's getppid runs of variant v against the same round's run
    without rtsup-trace: time ratio - 1, per round. A run whose hooks were
    not the variant's (a fallback) is left out."""
    runs = [x for x in g.get("syscall", []) if x["rc"] == 0]
    out = []
    for x in runs:
        if x["variant"] != v or x.get("hooks") != GUEST_SYS_HOOKS[v]:
            continue
        b = [y for y in runs if y["variant"] == "base" and y["rep"] == x["rep"]]
        if b and b[0]["ns"] > 0:
            out.append(x["ns"] / b[0]["ns"] - 1)
    return out


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt(x, spec="%.3f", none="-"):
    return none if x is None else spec % x


def spread(xs, spec="%.3f"):
    xs = [x for x in xs if x is not None]
    if not xs:
        return "-"
    return "%s [%s–%s]" % (spec % statistics.median(xs), spec % min(xs), spec % max(xs))


def yes(ok):
    return "**met**" if ok else ("**missed**" if ok is not None else "not measured")


class R:
    """Indexed results."""

    def __init__(self, res):
        self.res = res
        self.wl = {w["name"]: w for w in res["workloads"]}
        self.var = {v["name"]: v for v in res["variants"]}
        self.unavailable = res.get("unavailable", {})
        self.runs = {}
        for r in res["runs"]:
            if r["rc"] == 0 and r["cpu_s"]:
                self.runs[(r["variant"], r["workload"], r["round"])] = r
        self.rounds = sorted({r["round"] for r in res["runs"]})

    def ran(self, v):
        return any(k[0] == v for k in self.runs)

    def paired(self, v, w, key):
        """per round: baseline / variant of one metric (a throughput ratio)"""
        out = []
        for rnd in self.rounds:
            b, x = self.runs.get(("baseline", w, rnd)), self.runs.get((v, w, rnd))
            if b and x and b.get(key) and x.get(key):
                out.append(b[key] / x[key])
        return out

    def slowdown(self, v, w, key="cpu_s"):
        return med([1 / r - 1 for r in self.paired(v, w, key)])

    def extra_ns_per_op(self, v, w, per=1):
        """CPU time a variant adds per unit of work, paired by round"""
        out = []
        for rnd in self.rounds:
            b, x = self.runs.get(("baseline", w, rnd)), self.runs.get((v, w, rnd))
            if b and x:
                out.append((x["cpu_s"] - b["cpu_s"]) / (self.wl[w]["ops"] * per) * 1e9)
        return out

    def progs(self, v, w):
        """program name -> [runs, ns] summed over the rounds"""
        tot = {}
        for (vv, ww, _), r in self.runs.items():
            if vv == v and ww == w:
                for n, (c, t) in r.get("progs", {}).items():
                    s = tot.setdefault(n, [0, 0])
                    s[0] += c
                    s[1] += t
        return tot

    def ns(self, v, w, prog):
        s = self.progs(v, w).get(prog)
        return s[1] / s[0] if s and s[0] else None

    def tool_cpu_ms(self, v, w):
        return med([r["tool_cpu_s"] * 1000 for (vv, ww, _), r in self.runs.items()
                    if vv == v and ww == w])


def hook(prog):
    """sched_switch_btf -> sched_switch"""
    for sfx in ("_btf", "_raw"):
        if prog.endswith(sfx):
            return prog[:-len(sfx)]
    return prog


def prog_of(r, v, w, h):
    for n in r.progs(v, w):
        if hook(n) == h:
            return n
    return None


def per_event_pair(r):
    """The variants per-event costs come from: rtsup-trace and the floor with
    BPF statistics on throughout (older results: the shipped variants)."""
    if r.ran("rtsup_stats") and r.ran("floor_stats"):
        return "rtsup_stats", "floor_stats"
    return "rtsup", "floor"


def target_only(r, w, h, v="rtsup", floor="floor"):
    """Per target event: the loadgen workload mixes target events with the
    machine's other events; take the non-target cost from sched_pipe (where no
    thread is a target) out. Returns (net ns per target event, share)."""
    p = prog_of(r, v, w, h)
    if not p:
        return None, None
    runs = r.progs(v, w)[p][0]
    nrounds = len([1 for (vv, ww, _) in r.runs if vv == v and ww == w])
    ops = r.wl[w]["ops"] * nrounds
    # per cycle of a target: one wakeup, a switch in and a switch out
    n_t = {"sched_wakeup": ops, "sched_switch": 2 * ops}.get(h)
    if not n_t or not runs:
        return None, None
    share = min(1.0, n_t / runs)
    avg = r.ns(v, w, p) - (r.ns(floor, w, prog_of(r, floor, w, h)) or 0)
    pn = prog_of(r, v, "sched_pipe", h)
    fn = prog_of(r, floor, "sched_pipe", h)
    non = (r.ns(v, "sched_pipe", pn) or 0) - (r.ns(floor, "sched_pipe", fn) or 0) if pn else 0
    return (avg - (1 - share) * non) / share, share


def target_cycle_ns(r, v, floor):
    """All our programs' net cost in loadgen, per target cycle."""
    nrounds = len([1 for (vv, ww, _) in r.runs if vv == v and ww == "loadgen"])
    if not nrounds or "loadgen" not in r.wl:
        return None
    tot = 0.0
    for p, (c, t) in r.progs(v, "loadgen").items():
        f = r.ns(floor, "loadgen", prog_of(r, floor, "loadgen", hook(p)) or "") or 0
        tot += t - c * f
    return tot / (r.wl["loadgen"]["ops"] * nrounds)


def plots(r, res):
    """PNG plots; None when matplotlib is not there."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    made = []
    wls = [w for w in r.wl]
    vs = [v["name"] for v in res["variants"] if v["name"] != "baseline"
          and not v.get("per_event_only") and r.ran(v["name"])]
    fig, ax = plt.subplots(figsize=(11, 4.8))
    width = 0.8 / max(1, len(vs))
    for i, v in enumerate(vs):
        meds, lo, hi, xs = [], [], [], []
        for j, w in enumerate(wls):
            p = r.paired(v, w, "cpu_s")
            if not p:
                continue
            m = statistics.median(p)
            xs.append(j + (i - (len(vs) - 1) / 2) * width)
            meds.append(m)
            lo.append(m - min(p))
            hi.append(max(p) - m)
        ax.bar(xs, meds, width, yerr=[lo, hi], capsize=2, label=r.var[v]["label"])
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.set_xticks(range(len(wls)))
    ax.set_xticklabels(wls)
    ax.set_ylabel("throughput / baseline (CPU time)")
    ax.set_ylim(0, 1.1)
    ax.set_title("Throughput relative to nothing attached (median, min–max over rounds)")
    ax.legend(fontsize=7, ncol=3, loc="lower left")
    fig.tight_layout()
    fig.savefig(DOCS / "bench-throughput.png", dpi=90)
    plt.close(fig)
    made.append("bench-throughput.png")

    # per event, per program: rtsup vs floor, by workload
    hooks = ["sched_switch", "sched_wakeup", "sys_enter", "sys_exit"]
    wl_ev = [w for w in ("sched_pipe", "syscall", "loadgen") if w in r.wl]
    fig, axs = plt.subplots(1, len(wl_ev), figsize=(11, 3.6), sharey=True)
    if len(wl_ev) == 1:
        axs = [axs]
    for ax, w in zip(axs, wl_ev):
        pr_, pf_ = per_event_pair(r)
        for k, (v, lab) in enumerate(((pf_, "floor (empty)"), (pr_, "rtsup-trace"))):
            # a program that ran only a few thousand times here says little
            ys = [r.ns(v, w, prog_of(r, v, w, h))
                  if prog_of(r, v, w, h) and r.progs(v, w)[prog_of(r, v, w, h)][0] >= 20000
                  else 0 for h in hooks]
            ax.bar([x + (k - 0.5) * 0.38 for x in range(len(hooks))], ys, 0.38, label=lab)
        ax.set_xticks(range(len(hooks)))
        ax.set_xticklabels(hooks, fontsize=7)
        ax.set_title(w, fontsize=9)
    axs[0].set_ylabel("ns per event (bpf_stats)")
    axs[0].legend(fontsize=7)
    fig.suptitle("run_time_ns / run_cnt per program (includes bpf_stats' own clock reads; "
                 "programs with fewer than 20 000 runs left out)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(DOCS / "bench-per-event.png", dpi=90)
    plt.close(fig)
    made.append("bench-per-event.png")

    g = res.get("guest", {})
    if g.get("can") or g.get("cyclictest"):
        fig, axs = plt.subplots(1, 2, figsize=(10, 3.4))
        for v, mk in (("base", "o"), ("rtsup", "s"), ("nostats", "^"), ("floor", "x")):
            xs = [c["rep"] for c in g.get("can", []) if c["variant"] == v]
            ys = [c["frames"] / (c["ns"] / 1e9) / 1000 for c in g.get("can", [])
                  if c["variant"] == v]
            axs[0].plot(xs, ys, mk, label=GUEST_LABEL[v])
            xs = [c["rep"] for c in g.get("cyclictest", []) if c["variant"] == v and c["threads"]]
            ys = [statistics.mean(t["avg_us"] for t in c["threads"])
                  for c in g.get("cyclictest", []) if c["variant"] == v and c["threads"]]
            axs[1].plot(xs, ys, mk, label=GUEST_LABEL[v])
        axs[0].set_title("CAN flood in the guest (kframes/s)", fontsize=9)
        axs[1].set_title("cyclictest average latency in the guest (us)", fontsize=9)
        for ax in axs:
            ax.set_xlabel("round")
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(DOCS / "bench-guest.png", dpi=90)
        plt.close(fig)
        made.append("bench-guest.png")
    return made


def reexec_for_matplotlib():
    """Debian's python3-matplotlib lives with Debian's python3; another python3
    may come first in PATH. Run this script again with one that has it."""
    try:
        import matplotlib  # noqa: F401
        return None
    except ImportError:
        pass
    seen = {os.path.realpath(sys.executable)}
    for d in os.environ.get("PATH", "").split(os.pathsep):
        exe = os.path.join(d, "python3")
        if not os.access(exe, os.X_OK) or os.path.realpath(exe) in seen:
            continue
        seen.add(os.path.realpath(exe))
        if subprocess.run([exe, "-c", "import matplotlib"], capture_output=True).returncode == 0:
            return exe
    return None


def main():
    path = Path(sys.argv[1] if len(sys.argv) > 1 else DOCS / "bench-results.json")
    if not os.environ.get("BENCH_REPORT_REEXEC"):
        exe = reexec_for_matplotlib()
        if exe:
            os.environ["BENCH_REPORT_REEXEC"] = "1"
            os.execv(exe, [exe] + sys.argv)
    res = json.loads(path.read_text())
    r = R(res)
    made = plots(r, res)
    doc = render(r, res, made)
    (DOCS / "performance.md").write_text(doc)
    print("bench: wrote docs/performance.md%s" % (
        " and " + ", ".join("docs/" + m for m in made) if made else " (no matplotlib: no plots)"))
    return 0


def stack_records(res, v):
    """records taken per round by a --stacks variant (its summary's stack_records)"""
    return {x["round"]: x["records"] for x in res.get("stack_records", []) if x["variant"] == v}


def per_record(r, res, v, base, cost):
    """cost(variant, round) - cost(base, round) per record v took in the round, medians"""
    out = []
    for rnd, n in stack_records(res, v).items():
        x, b = cost(v, rnd), cost(base, rnd)
        if n and x is not None and b is not None:
            out.append((x - b) / n)
    return out


def per_thread(us, a):
    """What a thread costs the loop, from the table modes: 5 running alone (the fixed
    part), 1000 running, 5 running and 900 parked; medians, µs of CPU a second"""
    def cpu_us(mode, n):
        xs = [u["cpu_s"] / u["seconds"] * 1e6 for u in us
              if u.get("output") == mode and u.get("threads_target") == n]
        return med(xs) if xs else None
    few, run, parked = cpu_us("table, 5", 5), cpu_us("table", 1000), \
        cpu_us("table, 5 and 900 idle", 905)
    if few is None or run is None or parked is None:
        return
    a("Per thread, table output (medians; a thread's share is the difference from 5 "
      "running alone, so read it with the rounds' spread):")
    a("")
    a("| | µs of CPU a second |")
    a("|---|---:|")
    a("| 5 running alone: the part that does not grow with threads | %.0f |" % few)
    a("| each running thread (1000 running, less the 5) | %.2f |" % ((run - few) / 995))
    a("| each parked thread (5 running and 900 parked, less the 5) | %.2f |"
      % ((parked - few) / 900))
    a("")


def stacks_section(r, res, a):
    """--stacks: per captured event (kernel side, userspace), clean cycles, sizes"""
    vs = [v for v in ("stacks_fp", "stacks_dwarf", "stacks_auto") if r.ran(v)]
    if not vs:
        return

    def tool_cpu(v, rnd):
        x = r.runs.get((v, "where_loop", rnd))
        return x["tool_cpu_s"] if x else None

    def prog_ns(v, rnd):
        x = r.runs.get((v, "where_loop", rnd))
        return sum(t for _, t in x["progs"].values()) / 1e9 if x else None

    w = r.wl["where_loop"]
    a("## Where in the code (`--stacks`)")
    a("")
    a("The workload `where_loop` (`tests/integration/progs/where_loop.c` built with frame "
      "pointers, so that both unwinders walk it whole; %d cycles of 1 ms, each with an mmap, "
      "the first touch of its page and a munmap: three RT-unsafe events, every one captured, "
      "no budget) under rtsup-trace with `--stacks off` (`rtsup_nostats`, `rtsup_stats`), "
      "`fp`, `dwarf` and `auto` (DWARF here: Debian's glibc has no frame pointers). Per "
      "stack record (the records each run's summary counts): rtsup-trace's own CPU time "
      "beyond `--stacks off` in the same round (unwinding and symbols), and our programs' "
      "run time beyond it with BPF statistics on (the capture: `bpf_get_task_stack`, or the "
      "registers and %s of stack copied into the ring buffer)." % (w["ops"], "8 KiB"))
    a("")
    a("| variant | stack records per run | userspace per record | kernel side per record |")
    a("|---|---:|---:|---:|")
    for v in vs:
        st = v + "_stats" if r.ran(v + "_stats") else None
        recs = med(list(stack_records(res, v).values()))
        a("| %s | %s | %s | %s |" % (
            r.var[v]["label"], fmt(recs, "%.0f"),
            spread([x * 1e6 for x in per_record(r, res, v, "rtsup_nostats", tool_cpu)],
                   "%.1f us"),
            spread([x * 1e9 for x in per_record(r, res, st, "rtsup_stats", prog_ns)], "%.0f ns")
            if st else "-"))
    a("")
    a("Clean cycles: `loadgen` (targets, no RT-unsafe event) costs the same with `--stacks`: "
      "ns per run of each hook with BPF statistics on. The fault hook is attached only with "
      "`--stacks`: in `page_fault` (no target) every user fault of the machine runs it.")
    a("")
    hooks = ("sys_enter", "sys_exit", "sched_switch", "sched_wakeup", "page_fault_user")
    a("| variant | " + " | ".join(hooks) + " |")
    a("|---|" + "---:|" * len(hooks))
    for v in ("rtsup_stats", "stacks_fp_stats", "stacks_dwarf_stats"):
        if not r.ran(v):
            continue
        cells = []
        for h in hooks:
            wl = "page_fault" if h == "page_fault_user" else "loadgen"
            p = prog_of(r, v, wl, h)
            cells.append(fmt(r.ns(v, wl, p) if p else None, "%.1f"))
        a("| %s | %s |" % (r.var[v]["label"], " | ".join(cells)))
    a("")
    sizes = res.get("prog_sizes", {})
    if "rtsup_nostats" in sizes:
        a("Instructions the verifier kept (`bytes_xlated` / 8): without `--stacks` the "
          "capture is a test of a rodata constant the verifier removes.")
        a("")
        cols = [v for v in ("rtsup_nostats", "stacks_fp", "stacks_dwarf", "stacks_auto")
                if v in sizes]
        a("| program | " + " | ".join(cols) + " |")
        a("|---|" + "---:|" * len(cols))
        for p in sorted(sizes["rtsup_nostats"]):
            a("| %s | %s |" % (p, " | ".join(
                fmt((sizes[v].get(p) or [None])[0] and sizes[v][p][0] / 8, "%.0f")
                for v in cols)))
        a("")


def render(r, res, made):
    m = res["machine"]
    L = []
    a = L.append
    a("# Performance: what rtsup-trace costs the threads it watches")
    a("")
    a("Written by `make bench` (`scripts/bench`, report by `scripts/bench.d/report.py`) from "
      "the raw results in [`bench-results.json`](bench-results.json); every number below "
      "comes from that one run, started %s and finished %s (%.1f minutes)."
      % (res["started"], res["finished"], res["seconds"] / 60))
    a("")
    a("## Machine, kernel and what else was running")
    a("")
    a("| | |")
    a("|---|---|")
    a("| CPU | %s, %d vCPUs, %d MiB (%s) |" % (m["cpu_model"], m["cpus"], m["mem_mib"], m["virt"]))
    a("| OS, kernel | %s, Linux %s (%s) |" % (m["os"], m["kernel"], m["kernel_version"]))
    a("| clock source | %s |" % m["clocksource"])
    a("| instruction counts | %s |" % (
        "available" if m["instructions_counter"] else
        "not available: `perf stat -e instructions true` says `%s` (no PMU in this VM), so "
        "every ratio uses CPU time (`perf stat -e task-clock`) instead, which does not count "
        "the time a workload waits for a CPU that other processes hold" % m["instructions_probe"]))
    a("| tools | %s |" % ", ".join("%s" % v for v in m["tools"].values() if v))
    if res.get("guest", {}).get("info"):
        gi = res["guest"]["info"]
        a("| guest | Debian's PREEMPT_RT kernel %s under qemu TCG (`scripts/vm-test`), %d vCPUs |"
          % (gi["kernel"], gi["cpus"]))
    ld = res["load"]
    for when in ("start", "end"):
        s = ld.get(when)
        if s:
            busy = ", ".join("%s %.0f %%" % (b["comm"], b["cpu_pct"]) for b in s["busiest"])
            a("| load at %s | load average %s; busiest: %s; qemu processes: %d |"
              % (when, " ".join(s["loadavg"]), busy or "-", s["qemu_running"]))
    la = [float(x["loadavg"][0]) for x in ld.get("rounds", [])]
    if la:
        a("| load during the rounds | 1-minute load average %.2f to %.2f |" % (min(la), max(la)))
    foreign = sorted({p for x in res["runs"] for p in x.get("foreign_progs", [])})
    nf = sum(1 for x in res["runs"] if x.get("foreign_progs"))
    a("| other BPF tracing programs | %s |" % (
        "none seen" if not foreign else "%d of %d measurements saw programs of other tools "
        "attached (%s): another developer's tests" % (nf, len(res["runs"]), ", ".join(foreign[:8]))))
    a("")
    busy = max(la) > 1.5 if la else True
    a("%s Each round "
      "starts every variant once, in a new random order, and runs every workload under it; "
      "a ratio is taken within one round (variant against that round's baseline) and the "
      "table gives the median and the range over the %d rounds." % (
          "The machine is shared with other developers' work (qemu VMs, tests): this run "
          "saw real load (above), so wall-clock times are noisy; CPU time is the steadier "
          "measure here." if busy else
          "The machine is shared with other developers' work, but it was quiet during this "
          "run's rounds (load above); CPU time is still the main measure.", len(r.rounds)))
    a("")

    # ------------------------------------------------------------ targets
    a("## Targets")
    a("")
    a("| target | measured | |")
    a("|---|---|---|")
    sd = {v: r.slowdown(v, "sched_pipe") for v in MAIN + ["bpftrace"]}
    for v, f in (("rtsup", "floor"), ("rtsup_nostats", "floor_nostats")):
        if sd.get(v) is not None and sd.get(f) is not None:
            ok = sd[v] <= T_PIPE_VS_FLOOR * sd[f]
            a("| sched pipe: %s slows it ≤ 1.5× the floor's slowdown | %.1f %% vs %.1f %% "
              "(%s): %.2f× | %s |" % (r.var[v]["label"], sd[v] * 100, sd[f] * 100,
                                     r.var[f]["label"], sd[v] / sd[f] if sd[f] > 0 else 0, yes(ok)))
            a("| sched pipe: %s slows it ≤ 5 %% | %.1f %% (the floor alone: %.1f %%) | %s |"
              % (r.var[v]["label"], sd[v] * 100, sd[f] * 100, yes(sd[v] <= T_PIPE_ABS)))
    # issue 19: --rt and the per-syscall hooks against their own floors
    for v, f in (("rtsup_rt", "floor_rt"), ("rtsup_per", "floor_per")):
        for w in ("sched_pipe", "sched_messaging"):
            x, y = r.slowdown(v, w), r.slowdown(f, w)
            if r.ran(v) and r.ran(f) and x is not None and y is not None:
                a("| %s: %s slows it ≤ %.1f× the floor's slowdown | %.1f %% vs %.1f %% (%s): "
                  "%.2f× | %s |" % (w, r.var[v]["label"], T_VS_OWN_FLOOR, x * 100, y * 100,
                                    r.var[f]["label"], x / y if y > 0 else 0,
                                    yes(x <= T_VS_OWN_FLOOR * y or x <= 0)))
    for v in ("rtsup_per", "floor_per", "floor", "rtsup"):
        x = r.slowdown(v, "syscall") if r.ran(v) else None
        if x is not None:
            a("| syscall basic (getppid, a syscall no hook is on): %s slows it ≤ %.0f %% | "
              "%.1f %% | %s |" % (r.var[v]["label"], T_SYSCALL_PCT, x * 100,
                                  yes(x * 100 <= T_SYSCALL_PCT)))
    for v in ("rtsup_per", "floor_per"):
        if v in r.unavailable:
            a("| %s | does not run here: %s | not measured |" % (v, r.unavailable[v][:200]))
    st = r.slowdown("rtsup_stats", "sched_pipe") if r.ran("rtsup_stats") else None
    if sd.get("rtsup") is not None and st is not None:
        am = (1 - STATS_DUTY) * sd["rtsup"] + STATS_DUTY * st
        a("| sched pipe: rtsup-trace as shipped, its statistics window weighted in, ≤ 5 %% | "
          "%.1f %% (between windows %.1f %%, inside one %.1f %%, on %.2f %% of the time) | %s |"
          % (am * 100, sd["rtsup"] * 100, st * 100, STATS_DUTY * 100, yes(am <= T_PIPE_ABS)))
    bt = med(r.extra_ns_per_op("bpftrace", "sched_pipe", 2))
    for v in ("rtsup", "rtsup_nostats"):
        x = med(r.extra_ns_per_op(v, "sched_pipe", 2))
        if bt is not None and x is not None:
            a("| per context switch ≥ 2× cheaper than bpftrace's runqlat: %s | %s | %s |" % (
                r.var[v]["label"],
                "%.0f ns vs %.0f ns: %.1f× cheaper" % (x, bt, bt / x) if x > 0 else
                "%.0f ns vs %.0f ns: no cost above the noise" % (x, bt),
                yes(x > 0 and bt / x >= T_PEER_FACTOR or x <= 0)))
    for h, w, what in (("sched_switch", "loadgen", "of a target (loadgen)"),
                       ("sched_switch", "sched_pipe", "of a thread that is not a target"),
                       ("sched_wakeup", "loadgen", "of a target (loadgen)"),
                       ("sched_wakeup", "sched_pipe", "of a thread that is not a target"),
                       ("sys_enter", "syscall", "of a thread that is not a target")):
        vr, vf = per_event_pair(r)
        if w == "loadgen":
            net, share = target_only(r, w, h, vr, vf)
        else:
            pr, pf = prog_of(r, vr, w, h), prog_of(r, vf, w, h)
            net = r.ns(vr, w, pr) - r.ns(vf, w, pf) if pr and pf else None
            share = None
        if net is None:
            continue
        raw = r.ns(vr, w, prog_of(r, vr, w, h))
        a("| %s %s ≤ %d ns | %.1f ns net of the floor (%.1f ns measured, bpf_stats' clock reads included%s) | %s |"
          % (h, what, T_NS[h], net, raw, "; derived: about %.0f %% of the events involved a target"
             % (share * 100) if share else "", yes(net <= T_NS[h])))
    g = res.get("guest", {})
    can_r = [c for c in g.get("can", []) if c["variant"] not in ("base", "floor")]
    if can_r:
        acc = [c.get("accounted_pct") for c in can_r]
        a("| CAN: 100 %% of the frames accounted | %d floods of %d frames: %s | %s |" % (
            len(acc), res["args"]["frames"],
            "every one 100.00 %" if all(x == 100.0 for x in acc) else
            ", ".join(fmt(x, "%.2f %%") for x in acc),
            yes(all(x is not None and x == 100.0 for x in acc))))
        for v in ("rtsup", "nostats", "floor"):
            ratio = can_ratio(g, v)
            if ratio:
                a("| CAN: flood throughput within 2 %% of baseline, %s | %.1f %% slower (median "
                  "of %d paired rounds; range %.1f to %.1f %%) | %s |"
                  % (GUEST_LABEL[v], (1 - med(ratio)) * 100, len(ratio), (1 - max(ratio)) * 100,
                     (1 - min(ratio)) * 100, yes((1 - med(ratio)) * 100 <= T_CAN_PCT)))
    for v in ("per", "perfloor", "raw", "rawfloor"):
        d = sys_slowdown(g, v)
        if not d:
            continue
        what = ("| syscall basic in the guest (getppid by a thread that is no target, no hook "
                "on it): %s slows it ≤ %.0f %% | %.1f %% (median of %d paired rounds; range "
                "%.1f to %.1f %%) |" % (GUEST_SYS_LABEL[v], T_SYSCALL_PCT, med(d) * 100, len(d),
                                        min(d) * 100, max(d) * 100))
        # the target is the per-syscall hooks'; raw_syscalls' are shown beside
        a("%s %s |" % (what, yes(med(d) * 100 <= T_SYSCALL_PCT) if v == "per" else "shown beside"))
    us = res.get("userspace", [])
    for mode in dict.fromkeys(u.get("output", "json") for u in us):
        uu = [u for u in us if u.get("output", "json") == mode and
              u.get("threads_target", 1000) == 1000]
        if not uu:
            continue
        cpu, peak = med([u["cpu_pct"] for u in uu]), max(u["rss_peak_kb"] for u in uu) / 1024
        rss = max(u["rss_kb"] for u in uu) / 1024
        a("| userspace, %s output: ≤ 0.1 %% of a CPU with 1000 targets at 1 s | %.2f %% "
          "(median of %d) | %s |" % (mode, cpu, len(uu), yes(cpu <= T_USER_CPU_PCT)))
        # VmRSS while it runs; VmHWM also holds the start-up, when libbpf parses the
        # kernel's BTF (5.5 MB here) once and frees it
        a("| userspace, %s output: RSS ≤ 16 MiB | %.1f MiB while running (worst of %d; "
          "peak %.1f MiB%s) | %s |"
          % (mode, rss, len(uu), peak, " at start-up, while libbpf parses the kernel's BTF"
             if peak > rss + 0.5 else "", yes(rss <= T_USER_RSS_MIB)))
    a("")
    if NOTES.exists():
        a(NOTES.read_text().strip())
        a("")

    # ------------------------------------------------------------ throughput
    a("## Throughput on this machine")
    a("")
    if made and "bench-throughput.png" in made:
        a("![throughput relative to baseline](bench-throughput.png)")
        a("")
    a("Throughput relative to the baseline = baseline CPU time / variant CPU time for the same "
      "work (1.000 = no cost). `wall` is the same from elapsed time (perf bench's own "
      "`Total time`; not for the periodic loadgen). `tool CPU` is the CPU time of the tool's "
      "own processes during that workload (e.g. perf writing its file).")
    a("")
    for w, wd in r.wl.items():
        a("### %s" % wd["title"])
        a("")
        b = [r.runs[k] for k in r.runs if k[0] == "baseline" and k[1] == w]
        if b:
            a("Baseline: %s s CPU, %s s wall per run; %d %ss per run."
              % (fmt(med([x["cpu_s"] for x in b]), "%.3f"), fmt(med([x["wall_s"] for x in b]),
                                                                 "%.3f"), wd["ops"], wd["unit"]))
            a("")
        a("| variant | throughput (CPU) | slowdown | wall | extra CPU per %s | tool CPU |"
          % wd["unit"])
        a("|---|---|---:|---|---:|---:|")
        for v in [x["name"] for x in res["variants"]]:
            if v == "baseline" or r.var[v].get("per_event_only") or not r.ran(v):
                continue
            p = r.paired(v, w, "cpu_s")
            pw = r.paired(v, w, "wall_s") if not wd.get("cpu_only") else []
            ex = med(r.extra_ns_per_op(v, w))
            sl = r.slowdown(v, w)
            a("| %s | %s | %s | %s | %s | %s |" % (
                r.var[v]["label"], spread(p), fmt(sl * 100 if sl is not None else None, "%.1f %%"),
                spread(pw) if pw else "-", fmt(ex, "%.0f ns"),
                fmt(r.tool_cpu_ms(v, w), "%.1f ms")))
        a("")
    a("Per context switch (sched pipe: two switches and two wakeups per round trip, plus "
      "four syscalls), the CPU time each variant adds:")
    a("")
    a("| variant | extra CPU per context switch |")
    a("|---|---:|")
    for v in [x["name"] for x in res["variants"]]:
        if v == "baseline" or r.var[v].get("per_event_only") or not r.ran(v):
            continue
        a("| %s | %s |" % (r.var[v]["label"],
                           spread(r.extra_ns_per_op(v, "sched_pipe", 2), "%.0f ns")))
    a("")

    # ------------------------------------------------------------ per event
    a("## Per event, per program (bpf_stats)")
    a("")
    if made and "bench-per-event.png" in made:
        a("![ns per event](bench-per-event.png)")
        a("")
    vr, vf = per_event_pair(r)
    a("`run_time_ns / run_cnt` of each program while a workload ran, summed over the rounds, "
      "from the variants `%s` and `%s`: rtsup-trace and the floor with the kernel's BPF "
      "statistics on for the whole run (as shipped, rtsup-trace has them on for 100 ms at "
      "the start of one interval in 30 only, so the workloads, started 0.3 s after it attached, "
      "run between windows). So `floor` is what the statistics' own two clock reads and an empty program "
      "cost on this machine, and `net` = rtsup-trace − floor is what our program bodies cost. "
      "In sched pipe, syscall, messaging and page fault no thread is a target: those rows are "
      "the filter. In loadgen most events are targets' (the full hot path)." % (vr, vf))
    a("")
    a("| workload | program | runs | rtsup-trace ns | floor ns | net ns |")
    a("|---|---|---:|---:|---:|---:|")
    for w in r.wl:
        for p, (c, t) in sorted(r.progs(vr, w).items(), key=lambda x: -x[1][0]):
            if c < 1000:
                continue
            f = r.ns(vf, w, prog_of(r, vf, w, hook(p)) or "")
            a("| %s | %s | %d | %.1f | %s | %s |" % (w, p, c, t / c, fmt(f, "%.1f"),
                                                       fmt(t / c - f if f else None, "%.1f")))
    a("")
    if r.ran("rtsup_rt_stats") and r.ran("floor_rt_stats"):
        a("`--rt` (the service's default) the same way: `rtsup_rt_stats` against "
          "`floor_rt_stats`, each with `--rt` and nothing else to follow, so every RT thread "
          "of the machine is a target; where the policy hook cannot attach (this host: "
          "fexit refused) every switch-in reads the next thread's policy. `net --rt` minus "
          "`net` above is what `--rt` adds per event.")
        a("")
        a("| workload | program | runs | --rt ns | floor --rt ns | net --rt ns | net ns |")
        a("|---|---|---:|---:|---:|---:|---:|")
        for w in r.wl:
            for p, (c, t) in sorted(r.progs("rtsup_rt_stats", w).items(),
                                    key=lambda x: -x[1][0]):
                if c < 1000:
                    continue
                f = r.ns("floor_rt_stats", w, prog_of(r, "floor_rt_stats", w, hook(p)) or "")
                fr = r.ns(vf, w, prog_of(r, vf, w, hook(p)) or "")
                o = r.ns(vr, w, prog_of(r, vr, w, hook(p)) or "")
                a("| %s | %s | %d | %.1f | %s | %s | %s |" % (
                    w, p, c, t / c, fmt(f, "%.1f"), fmt(t / c - f if f else None, "%.1f"),
                    fmt(o - fr if o and fr else None, "%.1f")))
        a("")
    bts = [(w, p, c, t) for w in r.wl for p, (c, t) in r.progs("bpftrace_stats", w).items()
           if c >= 1000]
    if bts:
        a("bpftrace's runqlat.bt, run again with `kernel.bpf_stats_enabled=1` (the variant "
          "`bpftrace_stats`, only for these numbers):")
        a("")
        a("| workload | program | runs | ns/event |")
        a("|---|---|---:|---:|")
        for w, p, c, t in bts:
            a("| %s | %s | %d | %.1f |" % (w, p, c, t / c))
        a("")
    for h in ("sched_switch", "sched_wakeup"):
        net, share = target_only(r, "loadgen", h)
        if net is not None:
            a("- %s of a target, derived from loadgen (about %.0f %% of its events involved a "
              "target; the rest is taken to cost what it costs in sched pipe): **%.1f ns** net."
              % (h, share * 100, net))
    per_cycle = target_cycle_ns(r, vr, vf)
    if per_cycle is not None:
        a("- Every program of ours together, per cycle of a target in loadgen (sum over the "
          "programs of runs × net ns, over the cycles; the machine's other events while it ran "
          "are in it): **%.0f ns** per cycle. Work can move between hooks (a switch-in held "
          "until the thread's next event): this is the number that cannot hide it." % per_cycle)
    a("")

    stacks_section(r, res, a)

    # ------------------------------------------------------------ userspace
    if us:
        a("## rtsup-trace's own CPU time and memory")
        a("")
        a("`rtsup-loadgen -n 1000 -P 100000 -w 0 -r 1` (1000 SCHED_FIFO threads at 10 Hz) "
          "under `rtsup-trace --pid PID -i 1s` (the table), with `-j`, and as prom: the table and `--prom-textfile` (the service's output); "
          "\"900 idle\": 100 such threads and 900 SCHED_OTHER ones that run one cycle and stay parked "
          "(`-c 1 --hold`, a second `--pid`), as on a robot where most threads wait; %sCPU time of every rtsup-trace thread from "
          "`/proc/PID/task/*/schedstat` over %.0f s after a %.0f s start, RSS from `/proc/PID/status`."
          % ("\"5\": 5 such threads alone, and with the 900 parked ones (for the cost of a "
             "thread, below); " if any(u.get("threads_target", 1000) != 1000 for u in us) else "",
             med([u["seconds"] for u in us]), max(u.get("settle_s", 2) for u in us)))
        a("")
        a("| round | output | threads reported | output per s | CPU | share of one CPU | RSS peak |")
        a("|---:|---|---:|---:|---:|---:|---:|")
        for u in us:
            a("| %d | %s | %d | %s | %.1f ms | %.2f %% | %.1f MiB |" % (
                u["rep"], u.get("output", "json"), u["threads_seen"],
                "%.0f KiB" % (u["output_bytes"] / 1024 / (u["seconds"] + u.get("settle_s", 2)))
                if u.get("output_bytes") else "-",
                u["cpu_s"] * 1000, u["cpu_pct"], u["rss_peak_kb"] / 1024))
        a("")
        per_thread(us, a)

    rp = res.get("replayed", [])
    if rp:
        a("### The same work replayed, without BPF")
        a("")
        a("`rtsup-synth-trace` writes a made-up recorded trace of 1000 threads (30 one-second "
          "intervals; a tenth of the 10 Hz ones miss a deadline, a thirteenth make an mmap, "
          "every 10 s; one exits) and `rtsup-trace replay` reads it: the model, the checks "
          "and the output of a live run, without the map read and the kernel's side. CPU "
          "time (user + system), the least of 3 runs, per thread per interval; reading the "
          "trace and replaying its cycles is included.")
        a("")
        a("| trace | table | `-j` | `-j --json-threads active` |")
        a("|---|---:|---:|---:|")
        for name in dict.fromkeys(x["trace"] for x in rp):
            row = {x["output"]: x["us_per_thread"] for x in rp if x["trace"] == name}
            a("| %s | %s | %s | %s |" % (name, *("%.2f µs" % row[o] if o in row else "-"
                                                 for o in ("table", "json", "json active"))))
        a("")

    # ------------------------------------------------------------ guest
    if g:
        a("## In the PREEMPT_RT guest: CAN flood and cyclictest")
        a("")
        if g.get("error"):
            a("Not measured: %s." % g["error"])
            a("")
        else:
            if made and "bench-guest.png" in made:
                a("![guest](bench-guest.png)")
                a("")
            a("One boot of `scripts/vm-test` (%s, %.0f s in all). Emulated time is slow and noisy: "
              "only the relative numbers mean something. `cangen vcan0 -g 0 -n %d` without "
              "rtsup-trace, with `rtsup-trace --can vcan0` and with `--no-overhead` added, a "
              "different one first each round; frames accounted = rtsup-trace's count of "
              "identifier 0x321 sent, against what cangen sent."
              % (g.get("kernel_name"), g.get("seconds", 0), res["args"]["frames"]))
            a("")
            a("kframes/s per flood; in brackets the ratio to the same round's flood without "
              "rtsup-trace, and what rtsup-trace counted:")
            a("")
            a("| round | without | %s | %s | %s |" % (GUEST_LABEL["rtsup"], GUEST_LABEL["nostats"],
                                                   GUEST_LABEL["floor"]))
            a("|---:|---:|---:|---:|---:|")
            for rnd in sorted({c["rep"] for c in g.get("can", [])}):
                b = [c for c in g["can"] if c["rep"] == rnd and c["variant"] == "base"]
                fb = b[0]["frames"] / b[0]["ns"] * 1e6 if b else None
                row = [fmt(fb, "%.1f")]
                for v in ("rtsup", "nostats", "floor"):
                    x = [c for c in g["can"] if c["rep"] == rnd and c["variant"] == v]
                    fx = x[0]["frames"] / x[0]["ns"] * 1e6 if x else None
                    if x and v == "floor":  # empty programs count nothing
                        row.append("%s (%s)" % (fmt(fx, "%.1f"),
                                                fmt(fx / fb if fb and fx else None, "%.3f")))
                        continue
                    row.append("%s (%s; %s of %d)" % (
                        fmt(fx, "%.1f"), fmt(fx / fb if fb and fx else None, "%.3f"),
                        x[0].get("accounted"), x[0]["frames"]) if x else "-")
                a("| %d | %s |" % (rnd, " | ".join(row)))
            a("")
            cy = g.get("cyclictest", [])
            if cy:
                a("`cyclictest -m -p 80 -t 2 -d 0 -i 1000 -l %d` without and with "
                  "`rtsup-trace --comm cyclictest` (as shipped and `--no-overhead`) (its two threads are the targets: the full "
                  "hot path on every cycle). Average and maximum over the two threads, us:"
                  % res["args"]["loops"])
                a("")
                a("| round | without: avg | max | as shipped: avg | max | --no-overhead: avg | max "
                  "| floor: avg | max |")
                a("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
                for rnd in sorted({c["rep"] for c in cy}):
                    row = []
                    for v in ("base", "rtsup", "nostats", "floor"):
                        x = [c for c in cy if c["rep"] == rnd and c["variant"] == v and c["threads"]]
                        row += [fmt(statistics.mean(t["avg_us"] for t in x[0]["threads"]) if x
                                    else None, "%.0f"),
                                fmt(max(t["max_us"] for t in x[0]["threads"]) if x else None, "%d")]
                    a("| %d | %s |" % (rnd, " | ".join(row)))
                a("")
                for v in ("rtsup", "nostats", "floor"):
                    rel = cyc_ratio(cy, v)
                    if rel:
                        a("- average latency, %s / without, paired by round: median %.2f "
                          "(range %.2f to %.2f)" % (GUEST_LABEL[v], med(rel), min(rel), max(rel)))
                a("")

            sy = g.get("syscall", [])
            if sy:
                a("`perf bench syscall basic -l %d` (getppid: no per-syscall hook is on it) by a "
                  "thread that is no target, while `rtsup-trace -p 1 --no-overhead` runs with "
                  "its syscall hooks on `raw_syscalls` or per syscall (`--syscall-hooks`), "
                  "and the floor of each (empty programs on the same hooks), a different one "
                  "first each round. Seconds per run; in brackets the ratio to the same "
                  "round's run without rtsup-trace:" % res["args"].get("calls", 1000000))
                a("")
                vs = ("raw", "per", "rawfloor", "perfloor")
                a("| round | without | %s |" % " | ".join(GUEST_SYS_LABEL[v] for v in vs))
                a("|---:|---:|" + "---:|" * len(vs))
                for rnd in sorted({x["rep"] for x in sy}):
                    b = [x for x in sy if x["rep"] == rnd and x["variant"] == "base"]
                    row = [fmt(b[0]["ns"] / 1e9 if b else None, "%.2f")]
                    for v in vs:
                        x = [y for y in sy if y["rep"] == rnd and y["variant"] == v]
                        if not x:
                            row.append("-")
                            continue
                        row.append("%s (%s)%s" % (
                            fmt(x[0]["ns"] / 1e9, "%.2f"),
                            fmt(x[0]["ns"] / b[0]["ns"] if b else None, "%.3f"),
                            "" if x[0].get("hooks") == GUEST_SYS_HOOKS[v] else
                            " ran with %s" % x[0].get("hooks")))
                    a("| %d | %s |" % (rnd, " | ".join(row)))
                a("")

    # ------------------------------------------------------------ not run
    un = res.get("unavailable", {})
    if un:
        a("## Peers that do not run here")
        a("")
        for v, err in un.items():
            a("- **%s** (`%s`): %s" % (r.var.get(v, {}).get("label", v), v, "`%s`" % err))
        a("")
    a("## Reproduce")
    a("")
    a("```sh")
    a("make deps bench    # as root; make bench installs the peers (scripts/install-bench-deps)")
    a("scripts/bench --quick          # 2 short rounds, no guest: a try-out in about 2 minutes")
    a("scripts/bench --report-only    # this page again from docs/bench-results.json")
    a("```")
    a("")
    return "\n".join(L)


def can_ratio(g, v):
    out = []
    for rnd in sorted({c["rep"] for c in g.get("can", [])}):
        b = [c for c in g["can"] if c["rep"] == rnd and c["variant"] == "base"]
        x = [c for c in g["can"] if c["rep"] == rnd and c["variant"] == v]
        if b and x and x[0]["ns"]:
            out.append(b[0]["ns"] / x[0]["ns"])
    return out


def cyc_ratio(cy, v):
    out = []
    for rnd in sorted({c["rep"] for c in cy}):
        b = [c for c in cy if c["rep"] == rnd and c["variant"] == "base" and c["threads"]]
        x = [c for c in cy if c["rep"] == rnd and c["variant"] == v and c["threads"]]
        if b and x:
            ab = statistics.mean(t["avg_us"] for t in b[0]["threads"])
            ax = statistics.mean(t["avg_us"] for t in x[0]["threads"])
            if ab:
                out.append(ax / ab)
    return out


if __name__ == "__main__":
    sys.exit(main())
