"""The benchmarks' own bookkeeping (bench/roots.py, bench/sim.py): with their
runs and builds stubbed, what they print is what they measured; no speed is
asserted (speed is a figure, not a test)."""
from __future__ import annotations

import importlib.util

import pytest

from max2code.paths import ROOT


def test_bench_rounds_take_the_smallest_median(monkeypatch, capsys):
    """`bench/roots.py --rounds N` measures every column N times, the columns
    taking turns, and prints the smallest of each figure's N medians (builds
    and timings stubbed: this checks the bookkeeping, not the speed)."""
    from max2code.conformance import bench
    for name in ("make_c", "make_m2", "cargo"):
        monkeypatch.setattr(bench, name, lambda *a, **k: None)
    monkeypatch.setattr(bench.R, "build_testee", lambda *a, **k: None)
    order = []
    # native columns: round r gives 10 + degree, except round 1, which is 1 less
    # (later rounds are slower again: the minimum is not simply the last)
    def native(cmd, text):
        order.append("native")
        r = order.count("native") // 5 + (order.count("native") % 5 != 0)
        return {d: 10.0 + d - (1.0 if r == 2 else 0.0) for d in bench.DEGREES}
    calls = {"n": 0}
    def time_python(fn, polys, reps):
        order.append("python")
        calls["n"] += 1
        return 1000.0 + 10 * calls["n"]
    monkeypatch.setattr(bench, "native", native)
    monkeypatch.setattr(bench, "time_python", time_python)
    assert bench.main(["--rounds", "3", "--per-degree", "2", "--markdown"]) == 0
    out = capsys.readouterr().out
    rows = [ln for ln in out.splitlines() if ln.startswith("| ") and not ln.startswith("| degree")]
    assert len(rows) == len(bench.DEGREES)
    for deg, row in zip(bench.DEGREES, rows):
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[0] == str(deg)
        assert cells[1:6] == [f"{10.0 + deg - 1.0:.1f}"] * 5, row  # round 2's, the smallest
        # Python then numpy per round, degree by degree: round 1's are the smallest
        i = bench.DEGREES.index(deg)
        assert cells[6] == f"{1000 + 10 * (i + 1):,.0f}" and cells[7] == f"{1000 + 10 * (i + 6):,.0f}", row
    assert "smallest of 3 interleaved rounds" in out
    # the columns take turns: 5 native runs and 10 Python timings per round, 3 rounds
    assert order == (["native"] * 5 + ["python"] * 10) * 3
    with pytest.raises(SystemExit) as e:
        bench.main(["--rounds", "0"])
    assert e.value.code == 2


def test_sim_rounds_take_the_smallest_times(monkeypatch, capsys):
    """`bench/sim.py --rounds N` runs each scene (and its start) N times per
    runtime, the runtimes taking turns, and reports the smallest CPU and wall
    times (the simulators stubbed: this checks the bookkeeping, not the speed)."""
    sim = _bench_sim()
    monkeypatch.setattr(sim, "build_simulator", lambda lang, *a: lang)
    order = []
    counts = {"collisions": 400, "cells": 500, "stale": 900, "pairs": 3000}

    def run(build, flat):
        order.append(build)
        k = len(order)
        if k <= 1:  # the pilot run of the first runtime
            return 1.0, 1.0, counts
        start = (k - 2) % 2 == 0  # each turn runs the start, then the scene
        turn = (k - 2) // 4  # c then rust per round: 4 runs a round
        # round 2 is the fastest (times 2, 1, 3 in rounds 1, 2, 3); rust 10 % slower than c
        cpu = {0: 2.0, 1: 1.0, 2: 3.0}[turn] * (1.1 if build == "rust" else 1.0)
        return (cpu * 0.01, cpu * 0.01, {"collisions": 0}) if start else (cpu * 1.5, cpu, counts)
    monkeypatch.setattr(sim, "run", run)
    assert sim.main(["--langs", "c,rust", "--sizes", "20", "--events", "1000", "--rounds", "3"]) == 0
    out = capsys.readouterr().out
    row = out.splitlines()[1].split()
    assert int(row[0]) == 20 and int(row[2]) == 900 and int(row[3]) == 400  # events: all but stale, pairs
    # c: cpu s, ev/s, coll/s, wall s, start s; then rust's
    assert [float(x) for x in row[6:11]] == [1.0, 900.0, 400.0, 1.5, 0.01]
    assert [float(x) for x in row[12:17]] == [1.1, pytest.approx(900 / 1.1, rel=1e-3),
                                              pytest.approx(400 / 1.1, rel=1e-3), 1.65, 0.011]
    assert "smallest of 3 interleaved rounds" in out
    assert order == ["c"] + ["c", "c", "rust", "rust"] * 3
    with pytest.raises(SystemExit) as e:
        sim.main(["--rounds", "0"])
    assert e.value.code == 2


def _bench_sim():
    """bench/sim.py as a module."""
    spec = importlib.util.spec_from_file_location("bench_sim", ROOT / "bench" / "sim.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _toi_shapes():
    spec = importlib.util.spec_from_file_location("toi_shapes", ROOT / "bench" / "toi_shapes.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_toi_shapes_gives_the_peers_every_rigid_case_and_scores_their_answers():
    """bench/toi_shapes.py: only cases without acceleration or orbit go to the
    peers, each as one line of the drivers' layout (horizon, then per body
    kind, n, 7 numbers and n vertices), and a peer's time is scored by the
    conformance rule: inside [t_in, t_deep] right, a contact where the
    bodies never come within 2 tol invented, none where they touch missed."""
    ts = _toi_shapes()
    cases = ts.load(ts.CASES, None)
    everything = [ln for ln in ts.CASES.read_text().splitlines() if ln.strip()]
    assert 0 < len(cases) < len(everything)
    for c in cases:
        fields = ts.peer_line(c).split()
        n_a = int(fields[2])
        n_b = int(fields[1 + 9 + 2 * n_a + 1])
        assert len(fields) == 1 + (9 + 2 * n_a) + (9 + 2 * n_b)
        assert float(fields[0]) == c["horizon"]
    hit = next(c for c in cases if c.get("t_deep") is not None and c["d0"] > 0)
    assert ts.verdict(hit, repr(hit["t_star"])) == "right"
    assert ts.verdict(hit, "none") == "missed"
    assert ts.verdict(hit, repr(hit["t_in"] - 1e-3)) == "wrong"
    assert ts.verdict(hit, "refused") == "wrong"
    apart = next(c for c in cases if c.get("t_in") is None and c["d0"] > 0)
    assert ts.verdict(apart, "none") == "right"
    assert ts.verdict(apart, "0.5") == "invented"
