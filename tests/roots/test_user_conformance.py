"""A user's own equation in the conformance suite: `max2code cases` (reference
cases for any .mxm, byte-stable), `max2code conformance --equation` (its
generated code in each language) and `--testee` (any program that speaks the
wire format, judged by the runner's rules: a wrong one fails)."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import mpmath

from conftest import ROOT

import pytest

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

USER = os.path.join(ROOT, "tests", "data", "user-equations")
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "runtimes", "python")]))


def _m2c(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "max2code", *args], capture_output=True, text=True, cwd=cwd, env=ENV)


def test_cases_are_byte_stable_and_their_references_hold(tmp_path):
    eq = os.path.join(USER, "sphere-sphere.mxm")
    outs = []
    for k in range(2):
        out = tmp_path / f"c{k}.jsonl"
        r = _m2c("cases", eq, "-n", "10", "--seed", "3", "-o", str(out), "-q")
        assert r.returncode == 0, r.stderr
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    other = tmp_path / "other.jsonl"
    assert _m2c("cases", eq, "-n", "10", "--seed", "4", "-o", str(other), "-q").returncode == 0
    assert other.read_bytes() != outs[0]
    cases = [json.loads(line) for line in outs[0].decode().splitlines()]
    assert {c["family"] for c in cases} == {"random", "contact", "grazing", "touching", "overlapping", "multiple",
                                            "large", "small"}
    assert sum(c.get("motion") == "exact" for c in cases) == 10 and len(cases) == 20
    assert any(c["expect"] == "overlapped" for c in cases)
    # the references against the gap written out here in mpmath: a root of it, and none before it
    mpmath.mp.dps = 50
    checked = 0
    for c in cases:
        if not isinstance(c["expect"], float) or c["none_ok"]:
            continue
        p = {k: mpmath.mpf(v) for k, v in c["params"].items()}

        def gap(t):
            pos = [p[a] + p[u] * t + p[q] * t * t / 2 for a, u, q in
                   (("a", "u1", "p1"), ("b", "v1", "q1"), ("c", "w1", "s1"))]
            pos2 = [p[a] + p[u] * t + p[q] * t * t / 2 for a, u, q in
                    (("d", "u2", "p2"), ("e", "v2", "q2"), ("f", "w2", "s2"))]
            return sum((x - y) ** 2 for x, y in zip(pos, pos2)) - (p["r1"] + p["r2"]) ** 2

        t = mpmath.mpf(c["expect"])
        scale = abs(gap(t)) / max(abs(mpmath.diff(gap, t)), mpmath.mpf(10) ** -30)
        assert scale <= 1e-12 * max(1.0, float(t)), (c["id"], scale)
        if gap(0) > 0:
            assert all(gap(t * k / 200) > 0 for k in range(199)), c["id"]
        assert any(lo <= c["expect"] <= hi for lo, hi in c["accept"])
        checked += 1
    assert checked >= 5


def test_a_case_of_a_users_equation_resolves_with_equation(tmp_path):
    """Without --equation the name is unknown; with it, the file answers."""
    eq = os.path.join(USER, "ball-arena.mxm")
    case = {"id": "arena-1", "op": "toc", "equation": "ball-arena", "motion": "exact",
            "params": {"x": 0.0, "y": 0.0, "vx": 2.0, "vy": 0.0, "ax": 0.0, "ay": 0.0, "r": 1.0, "R": 6.0},
            "horizon": 10.0, "expect": 2.5, "accept": [[2.5, 2.5]], "none_ok": False}
    taylor = dict(case, id="arena-2", motion="taylor")
    f = tmp_path / "arena.jsonl"
    f.write_text(json.dumps(case) + "\n" + json.dumps(taylor) + "\n")
    r = _m2c("conformance", "--lang", "python", "--cases", str(f))
    assert r.returncode == 1 and "unknown equation 'ball-arena'" in r.stdout and "--equation" in r.stdout, r.stdout
    r = _m2c("conformance", "--lang", "python", "--equation", eq, "--cases", str(f))
    assert r.returncode == 0 and "2 passed" in r.stdout, r.stdout + r.stderr
    # by its `equation` name too, and a wrong expectation fails
    f.write_text(json.dumps(dict(case, equation="ball_arena", accept=[[2.4, 2.45]], expect=2.4)) + "\n")
    r = _m2c("conformance", "--lang", "python", "--equation", eq, "--cases", str(f))
    assert r.returncode == 1 and "outside the accepted times" in r.stdout, r.stdout


def test_all_four_languages_agree_on_a_users_equation(tmp_path):
    eq = os.path.join(USER, "point-floor-quintic.mxm")
    f = tmp_path / "quintic.jsonl"
    assert _m2c("cases", eq, "-n", "8", "--seed", "2", "-o", str(f), "-q").returncode == 0
    r = _m2c("conformance", "--equation", eq, "--lang", "all", "--cases", str(f), "-q")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "bit-for-bit agreement: yes, python, c, rust, m2 agree on all 16 cases" in r.stdout, r.stdout


def _howto_testee(tmp_path) -> str:
    """The testee of docs/howto-conformance.md, with the tutorial's ball-floor.mxm beside it."""
    text = open(os.path.join(ROOT, "docs", "howto-conformance.md"), encoding="utf-8").read()
    (tmp_path / "my_testee.py").write_text(re.findall(r"```python\n(.*?)```", text, re.S)[0])
    readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    mxm = re.search(r"(equation ball_floor .*?\nend\n)", readme, re.S).group(1)
    (tmp_path / "ball-floor.mxm").write_text(mxm)
    r = _m2c("--lang=python", "--exact", "-q", "ball-floor.mxm", "-o", "ball_floor.py", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert _m2c("cases", "ball-floor.mxm", "-n", "8", "-o", "ball_cases.jsonl", "-q", cwd=tmp_path).returncode == 0
    return "my_testee.py"


def test_a_testee_of_ones_own_is_judged_and_a_wrong_one_fails(tmp_path):
    # the howto's engine testee answers the toc lines of the ball's cases
    script = _howto_testee(tmp_path)
    r = _m2c("conformance", "--testee", f"{sys.executable} {script}", "--cases", "ball_cases.jsonl", "-q", cwd=tmp_path)
    assert r.returncode == 0 and "[testee] 16 cases: 16 passed" in r.stdout, r.stdout + r.stderr
    # the same engine one part in a million late fails, naming the case and why
    wrong = (tmp_path / script).read_text().replace("hexed(t))", "hexed(t * 1.000001))")
    (tmp_path / "wrong.py").write_text(wrong)
    r = _m2c("conformance", "--testee", f"{sys.executable} wrong.py", "--cases", "ball_cases.jsonl", "-q", cwd=tmp_path)
    assert r.returncode == 1 and "FAIL" in r.stdout and "outside the accepted times" in r.stdout, r.stdout
    # a root solver: the bundled Python testee passes the README's case, one answering a wrong root fails
    roots = tmp_path / "drop.jsonl"
    roots.write_text('{"id": "drop", "op": "roots", "coeffs": [0.9, 0.0, -4.905], "lo": 0, "hi": 10, '
                     '"expect": 0.4283529368781193, "roots": [[0.4283529368781193, 1, 1e-12]]}\n')
    r = _m2c("conformance", "--testee", f"{sys.executable} -m max2code_rt.testee", "--cases", str(roots))
    assert r.returncode == 0 and "[testee] pass  drop" in r.stdout, r.stdout + r.stderr
    (tmp_path / "liar.py").write_text(
        "import struct, sys\n"
        "for line in sys.stdin:\n"
        "    seq = line.split()[1]\n"
        "    print(seq, struct.pack('>d', 0.5).hex())      # always 0.5\n")
    r = _m2c("conformance", "--testee", f"{sys.executable} {tmp_path / 'liar.py'}", "--cases", str(roots))
    assert r.returncode == 1 and "FAIL  drop" in r.stdout and "not a root" in r.stdout, r.stdout
    # a testee that is not there is an error of the run, not a pass
    r = _m2c("conformance", "--testee", "no-such-testee-program", "--cases", str(roots))
    assert r.returncode == 1 and "ERROR" in r.stdout


def test_conformance_needs_lang_or_testee():
    r = _m2c("conformance", "--cases", "x.jsonl")
    assert r.returncode == 1 and "--lang LANG or --testee" in r.stderr
