# SPDX-License-Identifier: GPL-2.0 OR BSD-3-Clause
"""When a timing count differs: the tracer's recorded cycles (--record) beside
the generator's own clock reads (rtsup-loadgen --cycle-log), cycle by cycle.
A failing assertion prints the cycles the two judged otherwise, with what
the generator saw around them, so a red run says which race it met."""
import bisect
import struct

REC_CYCLE = 2
CF_MISS, CF_OVERRUN = 0x01, 0x02
# user/sinks/record.h: struct rec_cycle = u64 end + struct rtsup_cycle_rec
_CYCLE = struct.Struct("<Q IIII QQQQQQ IIIIIIII")


def recorded_cycles(path):
    """{tid: [cycle dict, ...]} from a recorded trace, in file order."""
    out = {}
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"RTSUPREC":
        raise ValueError("%s: not an rtsup trace" % path)
    _version, hlen = struct.unpack_from("<II", data, 8)
    off = 16 + hlen
    while off + 8 <= len(data):
        typ, length, _crc = struct.unpack_from("<HHI", data, off)
        off += 8
        if typ == REC_CYCLE and length >= _CYCLE.size:
            v = _CYCLE.unpack_from(data, off)
            (_end, tid, _tgid, resets, _pad, start, period, exe, cpu, latency, nominal,
             preempt, blocks, migrations, _sys, _usys, _minflt, _majflt, flags) = v
            out.setdefault(tid, []).append(dict(
                start=start, exec=exe, cpu=cpu, latency=latency, nominal=nominal,
                preempt=preempt, blocks=blocks, migrations=migrations, flags=flags,
                resets=resets, period=period))
        off += length
    return out


def generator_cycles(path):
    """{tid: [cycle dict, ...]} from rtsup-loadgen --cycle-log; each cycle
    gains 'next_before', the read before the sleep that ended it."""
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            tid, c, release, before, start, end, invol, vol, rd0, rd1 = map(int, line.split())
            out.setdefault(tid, []).append(dict(cycle=c, release=release, before=before,
                                                start=start, end=end, invol=invol, vol=vol,
                                                rd_before=rd0, rd_start=rd1))
    for cycles in out.values():
        for a, b in zip(cycles, cycles[1:]):
            # the sleep after a cycle ends it: its miss is that cycle's (the park's never is)
            a["next_before"] = b["before"]
            a["late_after"] = bool(b["release"]) and b["release"] <= b["before"]
        cycles.pop()  # the last line is the park's read only
    return out


def _nearest(gen, starts, start):
    """The generator's cycle whose start read follows the tracer's start
    closest (the tracer's start is at the switch-in, before that read);
    'starts' are gen's start reads, in order."""
    i = bisect.bisect_left(starts, start)
    return gen[i] if i < len(gen) else None


def _matched(rec, gen):
    """(recorded, generated) pairs: each recorded cycle with the generator's
    cycle nearest after its start (_nearest); a recorded cycle that starts
    after the generator's last start read has none and is left out"""
    starts = [g["start"] for g in gen]
    for r in rec:
        g = _nearest(gen, starts, r["start"])
        if g is not None:
            yield r, g


def differences(rec, gen, period_ns, flag=CF_OVERRUN):
    """Lines naming each cycle the tracer flagged ('flag') and the generator
    did not, or the other way round, with both sides' clock reads."""
    lines = []
    for r, g in _matched(rec, gen):
        t_flag = bool(r["flags"] & flag)
        if flag == CF_OVERRUN:
            g_flag = g["end"] - g["start"] > period_ns
        else:
            g_flag = g.get("late_after", False)
        if t_flag == g_flag:
            continue
        lines.append(
            "cycle %d: tracer %s, generator %s; tracer start %+d ns from the generator's, "
            "exec %d ns (nominal %d, preempt %d, migrations %d, latency %d); generator: "
            "release %+d ns, work %d ns, to the next sleep's read %s ns, "
            "switches at start invol %d vol %d" % (
                g["cycle"], t_flag, g_flag, r["start"] - g["start"], r["exec"], r["nominal"],
                r["preempt"], r["migrations"], r["latency"], g["release"] - g["start"],
                g["end"] - g["start"],
                g["next_before"] - g["start"] if "next_before" in g else "?",
                g["invol"], g["vol"]))
    return lines


def explain(record_path, log_path, tid, period_ns, flag=CF_OVERRUN):
    """One text block for an assertion message; never raises."""
    try:
        rec = recorded_cycles(record_path).get(tid, [])
        gen = generator_cycles(log_path).get(tid, [])
        lines = differences(rec, gen, period_ns, flag)
        return "\n%d recorded, %d generated cycles; judged otherwise:\n%s" % (
            len(rec), len(gen), "\n".join(lines) or "(none)")
    except (OSError, ValueError, KeyError, struct.error) as e:
        return "\n(no cycle comparison: %s)" % e


def exec_containment(record_path, log_path, tid):
    """(spans, short): the generator's span of each cycle, from its clock
    read after the sleep to its read before the next sleep, and the lines
    naming each recorded cycle shorter than the generator's cycle it holds.
    The tracer's cycle runs from the switch-in, before the first read, to
    the next sleep's entry, after the second: it holds that span, on the
    same clock (CLOCK_MONOTONIC), with no tolerance."""
    rec = recorded_cycles(record_path).get(tid, [])
    gen = generator_cycles(log_path).get(tid, [])
    short = []
    for r, g in _matched(rec, gen):
        span = g["next_before"] - g["start"]
        if r["exec"] < span:
            short.append("cycle %d: tracer exec %d ns, generator span %d ns, tracer start %+d ns"
                         % (g["cycle"], r["exec"], span, r["start"] - g["start"]))
    return sorted(g["next_before"] - g["start"] for g in gen), short
