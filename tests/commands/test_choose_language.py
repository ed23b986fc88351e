"""`max2code choose-language [EQ.mxm]`: a user's equation, interleaved rounds
within a time budget, median and spread per language, and what each
language gives besides speed."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from max2code.reports import choose_language

ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))


QUINTIC = os.path.join(ROOT, "tests", "data", "user-equations", "point-floor-quintic.mxm")
MARGIN = 0.5        # seconds past the budget the accounting may show: stopping a child, writing the table


def choose(*args):
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", *map(str, args)], capture_output=True,
                       text=True, cwd=ROOT, env=ENV, timeout=1800)
    assert r.returncode == 0, r.stderr
    return r


def accounting(out: str) -> dict:
    """The run's accounting line, read back: budget, preparing, timing, total (seconds), and the builds' text."""
    line = next(x for x in out.splitlines() if x.startswith("Accounting: "))
    m = re.fullmatch(r"Accounting: budget ([\d.]+) s; preparing ([\d.]+) s \(motions ([\d.]+) s; builds (.*?)\); "
                     r"timing ([\d.]+) s \((\d+) rounds\); total ([\d.]+) s(; over the budget by [\d.]+ s)?\.", line)
    assert m, line
    budget, prepare, motions, builds, timing, rounds, total, over = m.groups()
    return {"budget": float(budget), "prepare": float(prepare), "motions": float(motions), "builds": builds,
            "timing": float(timing), "rounds": int(rounds), "total": float(total), "over": over}


@pytest.mark.slow
def test_a_users_equation_in_rounds(tmp_path):
    doc = tmp_path / "doc.md"
    doc.write_text(f"before\n{choose_language.BEGIN}\nold\n{choose_language.END}\nafter\n")
    r = choose(QUINTIC, "--langs", "python,c", "--seconds", 1200, "--rounds", 3, "--motions", 20, "--write", doc)
    out = r.stdout
    assert "point-floor-quintic.mxm" in out
    rounds = int(re.search(r"median over (\d+) interleaved rounds", out).group(1))
    assert rounds == 3 == accounting(out)["rounds"]
    assert re.search(r"\d+ rounds in [0-9.]+ s", r.stderr)          # the progress line's last state
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in out.splitlines() if line.startswith("| python") or line.startswith("| c ")}
    assert set(rows) == {"python", "c"}
    for lang, cells in rows.items():
        # NAME_toc and NAME_toc_exact (the quintic's polynomial is its exact gap): median (smallest-largest)
        for cell in cells[:2]:
            med, lo, hi = (float(x.replace(",", "")) for x in re.fullmatch(r"([\d,]+) \(([\d,]+)-([\d,]+)\)", cell).groups())
            assert 0 < lo <= med <= hi
        assert float(cells[2].removesuffix(" (reused)")) > 0             # build seconds, when made
    assert rows["python"][3].startswith("no") and rows["c"][3] == "yes (float)"
    assert rows["python"][4].startswith("no") and rows["c"][4].startswith("yes: `#line`")
    assert rows["c"][5] == "yes"
    text = doc.read_text()
    assert text.startswith("before\n") and text.endswith("after\n") and "old" not in text and "| c |" in text

    # again, with a budget of 3 s: the harnesses are reused (no build), and the run ends within its budget by
    # its own accounting, whose parts add up
    r = choose(QUINTIC, "--langs", "python,c", "--seconds", 3, "--motions", 20)
    acc = accounting(r.stdout)
    assert acc["builds"] == "none; reused python, c", acc
    assert acc["motions"] == 0.0 and acc["over"] is None
    assert acc["total"] <= acc["budget"] + MARGIN, acc
    assert abs(acc["prepare"] + acc["timing"] - acc["total"]) <= 0.11, acc
    assert "| python | " in r.stdout and "(reused)" in r.stdout


def test_a_build_that_does_not_fit_is_said_and_not_begun(tmp_path, monkeypatch):
    """With the last Modula-2 build known to take 500 s, a 120 s budget
    does not begin it, says why, and spends nothing on it."""
    from max2code.toolchain import cache

    eq = tmp_path / "q.mxm"
    eq.write_text(open(QUINTIC).read() + "// a copy: no build of it is reused\n")
    monkeypatch.setattr(cache, "seconds_taken", lambda: {"m2": {"seconds": 500.0, "finished": True}})
    monkeypatch.setattr(choose_language, "_within", lambda deadline, fn, *a: (True, fn(*a), 0.0)
                        if fn is choose_language._motions else pytest.fail("began a build"))
    out, info = choose_language.measure(str(eq), ["m2"], seconds=120.0, motions=5, progress=False)
    m2 = out[0]
    assert m2.poly is None and m2.spent_s == 0.0 and m2.build_s is None
    assert m2.note.startswith("not built: generating and building it takes about 500 s (as when last made here)")
    assert info["rounds"] == 0 and info["build_s"] == 0.0
    assert "| m2 | - | - | - |" in choose_language.table(out, info, "q.mxm", "max2code choose-language q.mxm")


@pytest.mark.parametrize("seconds", [12.0, 60.0, 240.0])
def test_builds_leave_a_share_of_the_budget_to_timing(tmp_path, monkeypatch, seconds):
    """Builds are planned and stopped against the budget less its timing
    share: one planned to take the whole budget is not begun, one that fits
    the builds' share is begun with the builds' deadline, and the cheapest
    is made first."""
    from max2code.toolchain import cache

    eq = tmp_path / "q.mxm"
    eq.write_text(open(QUINTIC).read() + "// a copy: no build of it is reused\n")
    share = choose_language.timing_reserve(seconds)
    assert choose_language.TIMING_MIN_S <= share or share == 0.5 * seconds
    assert 0 < share <= 0.5 * seconds
    fits = seconds - share - 2.0                   # fits the builds' share (the motions take a moment)
    taken = {"python": {"seconds": fits, "finished": True},
             "c": {"seconds": seconds - 1.0, "finished": True},         # fits the budget, not the builds' share
             "rust": {"seconds": fits / 2, "finished": False}}         # stopped then: planned as never made
    monkeypatch.setattr(cache, "seconds_taken", lambda: taken)
    remembered = []
    monkeypatch.setattr(cache, "remember_seconds", lambda *a: remembered.append(a))
    begun = []
    start = time.perf_counter()

    def within(deadline, fn, *a):
        if fn is choose_language._motions:
            return True, fn(*a), 0.0
        begun.append((a[1], deadline - start))
        return False, None, 0.0                     # as if stopped: nothing is timed
    monkeypatch.setattr(choose_language, "_within", within)
    out, info = choose_language.measure(str(eq), ["c", "rust", "python"], seconds=seconds, motions=5,
                                        progress=False, start=start)
    notes = {lg.name: lg.note for lg in out}
    # rust is planned at FIRST_SECONDS (60 s), which fits the builds' share of 240 s only
    assert [lang for lang, _ in begun] == {12.0: ["python"], 60.0: ["python"], 240.0: ["rust", "python"]}[seconds]
    assert remembered == [(lang, 0.0, False) for lang, _ in begun]
    for _, deadline in begun:
        assert deadline == pytest.approx(seconds - share, abs=1e-6)
    assert notes["c"].startswith(f"not built: generating and building it takes about {seconds - 1:.0f} s")
    assert "the budget leaves for builds" in notes["c"]
    enough = float(re.search(r"--seconds (\d+)", notes["c"]).group(1))
    assert enough - choose_language.timing_reserve(enough) >= seconds - 1.0
    assert choose_language.planned_seconds("rust", taken["rust"]) == choose_language.FIRST_SECONDS["rust"]


def test_a_child_still_working_at_the_deadline_is_stopped_with_its_children(tmp_path):
    """_within stops the child and what it started (a compiler, Maxima) at the deadline."""
    pid_file = tmp_path / "pid"

    def work():
        p = subprocess.Popen(["sleep", "600"])
        pid_file.write_text(str(p.pid))
        p.wait()
        return "finished"

    ok, value, seconds = choose_language._within(time.perf_counter() + 1.0, work)
    assert (ok, value) == (False, None)
    pid = int(pid_file.read_text())
    for _ in range(100):                 # the sleep's parent is gone; it is reaped by init, or a zombie a moment
        try:
            with open(f"/proc/{pid}/stat") as fh:
                state = fh.read().rsplit(")", 1)[1].split()[0]
        except FileNotFoundError:
            break
        if state == "Z":
            break
        time.sleep(0.05)
    else:
        pytest.fail(f"the child's child {pid} still runs")
    assert choose_language._within(time.perf_counter() + 60.0, lambda: 42)[:2] == (True, 42)
    assert choose_language._within(time.perf_counter() + 60.0, lambda: 1 / 0)[:2] == (False, "division by zero")


def test_a_new_compiler_is_a_new_key(monkeypatch):
    """Harnesses kept for reuse are keyed by the compilers' versions too:
    another gcc (or Python) gives another key, so nothing built by the old
    one is reused."""
    from max2code.toolchain import base, cache, toolchain

    tools = toolchain("c").tool_versions()
    assert set(tools) == {"python", "gcc", "pkg-config"} and tools["gcc"].startswith("gcc")
    key = cache.equation_key(QUINTIC, lang="c", tools=tools)
    assert key == cache.equation_key(QUINTIC, lang="c", tools=toolchain("c").tool_versions())
    monkeypatch.setattr(base, "_version", lambda tool: "gcc (a newer one) 99.1" if tool == "gcc" else "same")
    assert cache.equation_key(QUINTIC, lang="c", tools=toolchain("c").tool_versions()) != key
    assert toolchain("python").tool_versions() == {"python": sys.version}


def test_facts_and_spread():
    assert choose_language.facts("m2")["reentrant"].startswith("NAME_toc yes; NAME_toc_exact no")
    assert choose_language.facts("rust")["single"] == "yes (f32)"
    assert choose_language._ns([300.0, 310.0, 500.0]) == "310 (300-500)"
    assert choose_language._ns([]) == "-"


def test_unknown_language_and_missing_file():
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", "--langs", "cobol"], capture_output=True,
                       text=True, cwd=ROOT, env=ENV)
    assert r.returncode == 1 and "unknown cobol" in r.stderr
    r = subprocess.run([sys.executable, "-m", "max2code", "choose-language", "nowhere.mxm"], capture_output=True,
                       text=True, cwd=ROOT, env=ENV)
    assert r.returncode == 1 and "nowhere.mxm: error: no such file" in r.stderr
