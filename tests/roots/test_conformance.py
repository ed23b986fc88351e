"""The conformance suite of the four root-solver runtimes, run through the
runner (which builds each testee into build/ when needed), plus tests of the
runner's own rules (unknown ops, expected failures, acceptance)."""
from __future__ import annotations

import json

import pytest

from max2code.conformance import runner as R

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

LANGS = list(R.ALL_LANGS)
_reports: dict[str, R.Report] = {}


def report(lang: str) -> R.Report:
    if lang not in _reports:
        _reports[lang] = R.run_lang(lang, R.load_cases(R.default_case_files()))
    return _reports[lang]


@pytest.mark.parametrize("lang", LANGS)
def test_conformance(lang, capsys):
    rep = report(lang)
    with capsys.disabled():
        print()
        R.print_report(rep, quiet=True)
        print(R.accuracy_table([rep]))
    assert not rep.error, rep.error
    assert len(rep.results) >= 2000
    bad = [f"{r.case_id}: {r.status} {r.verdict.why}" for r in rep.results if r.status in ("FAIL", "XPASS")]
    assert not bad, "\n".join(bad[:20])


def test_runtimes_agree_bit_for_bit(capsys):
    reps = [report(lang) for lang in LANGS]
    with capsys.disabled():
        print()
        print(R.accuracy_table(reps))
    assert R.agreement(reps) == []


def test_main_cli_quiet(capsys):
    assert R.main(["--lang", "python", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "conformance: OK" in out and "max relative error" in out


def write_cases(tmp_path, cases):
    p = tmp_path / "cases.jsonl"
    p.write_text("".join(json.dumps(c) + "\n" for c in cases))
    return p


GOOD = {"id": "lin", "op": "roots", "coeffs": [-0.5, 1.0], "lo": 0.0, "hi": 1.0,
        "expect": 0.5, "roots": [[0.5, 1, 5e-13]]}


def test_unknown_op_is_a_failure_not_a_crash(tmp_path, capsys):
    p = write_cases(tmp_path, [GOOD, {"id": "later", "op": "spin", "args": [1, 2]},
                               {"id": "bad-toc", "op": "toc", "equation": "no-such-equation", "params": {}, "horizon": 1}])
    assert R.main(["--lang", "python", "--cases", str(p)]) == 1
    out = capsys.readouterr().out
    assert "FAIL  later" in out and "unknown op 'spin'" in out
    assert "FAIL  bad-toc" in out and "malformed toc case" in out
    assert "pass  lin" in out


def test_listed_failure_that_passes_fails_the_run(tmp_path, monkeypatch, capsys):
    p = write_cases(tmp_path, [GOOD])
    (tmp_path / "python.txt").write_text("lin supposedly broken\n")
    monkeypatch.setattr(R, "XFAIL_DIR", tmp_path)
    assert R.main(["--lang", "python", "--cases", str(p)]) == 1
    assert "XPASS" in capsys.readouterr().out


def test_listed_failure_that_fails_is_tolerated(tmp_path, monkeypatch):
    wrong = dict(GOOD, id="wrong", roots=[[0.25, 1, 1e-13]], expect=0.25)
    p = write_cases(tmp_path, [GOOD, wrong])
    assert R.main(["--lang", "c", "--cases", str(p)]) == 1
    (tmp_path / "c.txt").write_text("wrong  reference deliberately off\n")
    monkeypatch.setattr(R, "XFAIL_DIR", tmp_path)
    assert R.main(["--lang", "c", "--cases", str(p)]) == 0


@pytest.mark.parametrize("answer,ok", [
    ("none", False),                      # misses a sure root
    (R.hex_of(0.5), True),
    (R.hex_of(0.5 + 1e-13), True),        # within tolerance
    (R.hex_of(0.5 + 1e-9), False),
    (R.hex_of(1.5), False),               # outside (lo, hi]
    ("error unknown-op", False),
    ("zz", False),
])
def test_judge(answer, ok):
    assert R.RootsOp().judge(GOOD, answer).ok is ok


def test_judge_boundary_rules():
    op = R.RootsOp()
    near_lo = {"coeffs": [0, 1], "lo": 0.25, "hi": 1.0, "roots": [[0.25 + 1e-14, 1, 1e-12], [0.75, 1, 1e-12]]}
    assert op.judge(near_lo, R.hex_of(0.25 + 1e-14)).ok        # the root just above lo
    assert op.judge(near_lo, R.hex_of(0.75)).ok                 # or skip it (within tol of lo)
    near_hi = {"coeffs": [0, 1], "lo": 0.0, "hi": 1.0, "roots": [[1.0 + 1e-14, 1, 1e-12]]}
    assert op.judge(near_hi, "none").ok
    assert op.judge(near_hi, R.hex_of(1.0)).ok
    sure = {"coeffs": [0, 1], "lo": 0.0, "hi": 1.0, "roots": [[0.3, 1, 1e-12], [0.6, 1, 1e-12]]}
    assert not op.judge(sure, R.hex_of(0.6)).ok                 # skipped a smaller root


def test_case_files_are_well_formed():
    cases = R.load_cases(R.default_case_files())
    ids = [c["id"] for c in cases]
    assert len(ids) == len(set(ids))
    for c in cases:
        assert c["op"] in R.OPS
        if c["op"] == "toc":
            assert c["equation"] in ("circle-circle", "point-line") and c["horizon"] > 0 and "expect" in c
            # exact motion: a contact at t = 0 (touching, approaching) is 0
            low_ok = (lambda e: 0 <= e) if c.get("motion") == "exact" else (lambda e: 0 < e)
            if c["expect"] == "overlapped":      # exact motion: the bodies overlap at t = 0 (docs/exact-motion.md)
                assert c.get("motion") == "exact"
                continue
            assert c["expect"] is None or (low_ok(c["expect"]) and c["expect"] <= c["horizon"])
            continue
        assert "expect" in c and "roots" in c
        lo, hi = R.num(c["lo"]), R.num(c["hi"])
        e = c["expect"]
        if e is not None:
            assert lo < e <= hi
    degrees = {len(c["coeffs"]) - 1 for c in cases if c["id"].startswith("random-")}
    assert degrees == set(range(1, 17))


def raw_answers(lang: str, polys: list[tuple[list[float], float, float]]) -> list[str]:
    import subprocess
    cmd = R.build_testee(lang)
    text = "\n".join(R.RootsOp().wire({"coeffs": c, "lo": lo, "hi": hi}, i)
                     for i, (c, lo, hi) in enumerate(polys)) + "\n"
    out = subprocess.run(cmd, input=text, stdout=subprocess.PIPE, text=True, check=True).stdout
    return [line.split(" ", 1)[1] for line in out.splitlines()]


def test_differential_random_bits():
    """Fresh random inputs (not in the case files), including nasty ones:
    the four runtimes must return identical bits."""
    import random
    rng = random.Random(99)
    polys = []
    for k in range(3000):
        deg = rng.randint(0, 16)
        kind = k % 4
        if kind == 0:
            c = [rng.gauss(0, 1) for _ in range(deg + 1)]
        elif kind == 1:
            c = [rng.choice([0.0, 1.0, -1.0, 0.5, 0.25]) for _ in range(deg + 1)]
        elif kind == 2:
            c = [rng.uniform(-1, 1) * 10.0 ** rng.randint(-300, 300) for _ in range(deg + 1)]
        else:
            r = [rng.choice([0.25, 0.5, 0.75, rng.random()]) for _ in range(deg)]
            c = [1.0]
            for x in r:
                c = [0.0] + c
                for i in range(len(c) - 1):
                    c[i] -= x * c[i + 1]
        lo = rng.choice([0.0, -1.0, rng.uniform(-2, 1), 0.25])
        hi = lo + rng.choice([1.0, 1e-9, 1e6, rng.uniform(0, 3), 1e300])
        polys.append((c, lo, hi))
    answers = {lang: raw_answers(lang, polys) for lang in LANGS}
    base = answers["python"]
    for lang in LANGS[1:]:
        diff = [i for i, (a, b) in enumerate(zip(base, answers[lang])) if a != b]
        assert len(answers[lang]) == len(base) and not diff, (lang, [polys[i] for i in diff[:3]])
    found = [a for a in base if a != "none"]
    assert len(found) > 300


def test_differential_any_magnitude_bits():
    """Coefficients and intervals over the whole double range (subnormals,
    near-overflow values, one magnitude or spread): the band path (docs/roots.md
    step 8) returns identical bits in the four runtimes."""
    import math
    import random
    rng = random.Random(5)
    big = 1.7976931348623157e308
    polys = []
    for k in range(2000):
        deg = rng.randint(1, 16)
        kind = k % 4
        if kind == 0:
            c = [rng.choice([0.0, 1.0]) * math.ldexp(rng.uniform(-1, 1), rng.randint(-1074, 1023))
                 for _ in range(deg + 1)]
        elif kind == 1:
            e = rng.randint(-1000, 950)
            c = [math.ldexp(rng.uniform(-1, 1), e + rng.randint(-60, 60)) for _ in range(deg + 1)]
        elif kind == 2:
            c = [rng.uniform(-1, 1) * 10.0 ** rng.uniform(-320, 307) for _ in range(deg + 1)]
        else:
            c = [rng.choice([5e-324, -5e-324, 1e-310, 1.7e308, -1.7e308, 0.0, 1.0]) for _ in range(deg + 1)]
        lo = rng.choice([0.0, -big, -rng.uniform(0, 1) * 10.0 ** rng.uniform(-300, 300), 1e-300])
        hi = rng.choice([big, 1.0, 10.0 ** rng.uniform(-300, 308)])
        if not lo < hi:
            lo, hi = 0.0, big
        polys.append((c, lo, hi))
    answers = {lang: raw_answers(lang, polys) for lang in LANGS}
    base = answers["python"]
    for lang in LANGS[1:]:
        diff = [i for i, (a, b) in enumerate(zip(base, answers[lang])) if a != b]
        assert len(answers[lang]) == len(base) and not diff, (lang, [polys[i] for i in diff[:3]])
    assert sum(1 for a in base if a != "none") > 1000
    assert not any(a.startswith("error") for a in base)
