

def ns_of(text):
    """'786us' -> 786000, '1.05ms' -> 1050000: the drawn bounds."""
    for unit, mul in (("ns", 1), ("us", 1000), ("ms", 1000000), ("s", 1000000000)):
        if text.endswith(unit) and text[:-len(unit)].replace(".", "").isdigit():
            return float(text[:-len(unit)]) * mul
    raise ValueError(text)


def test_hist_text_marks_the_exec_warn_threshold(tmp_path):
    """exec WARNs above 0.8 of the period (the default exec_warn_ratio):
    the WARN mark sits on the row whose range holds 800 us."""
    prefix = unique_prefix()
    r = subprocess.run(
        [str(TRACE), "--hist=exec", "--color=never", "--", str(LOADGEN), "--name", prefix,
         "-n", "1", "-P", "1000", "-w", "100", "-c", "500", "-s", str(tmp_path / "lg.json")],
        capture_output=True, text=True, timeout=120, env=dict(os.environ, COLUMNS="80"))
    assert r.returncode == 0, r.stderr
    warn = [line for line in r.stdout.splitlines() if "|" in line and
            line.rstrip().endswith("WARN")]
    assert len(warn) == 1, r.stdout
    lo, hi = warn[0].split("|")[0].split()[:3:2]
    assert ns_of(lo) <= 800000 < ns_of(hi) * 1.001  # bounds are printed to 3 digits


def test_can_replay_hist_gaps(tmp_path):
    """A candump log with known gaps: every gap in the histogram, in its bucket."""
    log = tmp_path / "bus.log"
    t, lines = 1700000000.0, []
    for i in range(300):
        t += 0.010 if i % 100 else 0.050  # 10 ms, and a 50 ms hole every 100 frames
        lines.append("(%.6f) vcan0 123#11" % t)
    log.write_text("\n".join(lines) + "\n")
    r = subprocess.run([str(TRACE), "can-replay", str(log), "-j", "--hist"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "\r" not in r.stderr  # no progress bar off a terminal
    can = json.loads(r.stdout.splitlines()[-1])["can"]
    (ident,) = can["ids"]
    h = ident["gap_hist"]
    assert h["count"] == 299 == sum(c for _, _, c in h["buckets"])
    # the timestamps have 1 us resolution: 10 ms within 1 us, the holes at 50 ms
    assert count_from(h["buckets"], 40_000_000) == 2
    assert sum(c for lo, hi, c in h["buckets"] if lo <= 10_000_000 <= hi + 1000) == 297
    r = subprocess.run([str(TRACE), "can-replay", str(log), "--hist", "--color=never"],
                       capture_output=True, text=True, timeout=60, env=dict(os.environ,
                                                                            COLUMNS="80"))
    assert "vcan0 0x123 rx gap (299)" in r.stdout
