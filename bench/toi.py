"""Time of impact side by side: max2code's exact contact time against
parry2d's nonlinear shape cast (f64 and f32) and, when its source is given,
Box2D v3's `b2TimeOfImpact`, on families of two circles on rigid motions
(every peer can take them), scored against mpmath references.

    python3 bench/toi.py [--motions 40] [--rounds 7] [--box2d-src DIR] [--families a,b]

Ours: the generated `circle_circle_toc_exact` (C and Rust, default options)
and, for scale, the single Taylor polynomial `circle_circle_coefficients`
plus the runtime's root solver over the whole horizon (exact only where no
body orbits).  parry2d: a small crate, bench/peers/parry-toi, built with cargo into
build/toi/parry.  Box2D: its source built with cmake into build/toi/box2d and
a small C driver (bench/peers/box2d/toi.c); `b2TimeOfImpact` over the horizon with
the sweeps of the same rigid motions.

Each family is a row of the table FAMILIES: name -> (draw, note, shapes).
`draw(rng)` gives one case: for shapes "circles" {"params": circle-circle
letters, "horizon": T} (every peer takes them and exact_ref scores them).
Families of other shapes plug in as rows with their own shapes word and a
module bench/toi_ours.py giving `measure(lang, cases) -> (answers, ns)` and
`reference(case)` for them: main() then measures those families with it
(ours only) and scores them the same way.

Printed per family and peer: ns per query (median over interleaved rounds
of the median pass), right / wrong / missed / invented (a contact within
1e-9 s or inside the reference's accepted intervals is right; a contact
where the reference has none is invented; none where it has one is missed;
"overlapped" is right only where the reference says so) and the largest
|answer - reference| over the cases where both have a contact.
"""
from __future__ import annotations

import argparse
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path[:0] = [str(ROOT), str(ROOT / "runtimes" / "python")]

import mpmath  # noqa: E402

from max2code.conformance.exact_cases import _aim, _first_extremum  # noqa: E402
from max2code.conformance.exact_ref import DPS, Gap, reference  # noqa: E402

BUILD = ROOT / "build" / "toi"
EQUATION = ROOT / "equations" / "circle-circle.mxm"
LETTERS = "abcdefmnopqghijklrsuvwxz"
TOL = 1e-9          # seconds: a contact this close to the reference's is right
PASSES = 5          # timed passes per round in every driver (their median is the round's figure)


# ---- families: rigid motions written in the equation's letters --------------

def _body(rng, orbit: bool, moving: bool, w: float = 3.0) -> dict:
    """One circle: its rotation centre at (a, m) moving with (b, n), the ball
    turning about it at radius d with angular velocity e = p; y's phase q and
    x's phase f = q + pi/2 make the orbit a circle (a rigid rotation)."""
    q = rng.uniform(-3.1, 3.1)
    om = rng.uniform(-w, w) if orbit else 0.0
    return {"a": rng.uniform(-3, 3), "b": rng.uniform(-2, 2) if moving else 0.0, "c": 0.0,
            "d": rng.uniform(0.1, 1.0) if orbit else 0.0, "e": om, "f": q + math.pi / 2,
            "m": rng.uniform(-3, 3), "n": rng.uniform(-2, 2) if moving else 0.0, "o": 0.0, "p": om, "q": q}


def _pair(rng, orbit1: bool, orbit2: bool, moving2: bool = True) -> dict:
    b1 = _body(rng, orbit1, True)
    b2 = _body(rng, orbit2, moving2)
    p = dict(b1)
    for mine, theirs in zip("abcdefmnopq", "ghijklrsuvw"):
        p[theirs] = b2[mine]
    p["x"], p["z"] = rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.8)
    return p


def _aimed(rng, p: dict, T: float) -> dict:
    """Half the draws: body 2's centre moved so that the paths meet near a
    random time (or pass within 1.5 radius sums); the others as drawn (most
    of them miss)."""
    return _aim(rng, p, "circle-circle", T, 1.5) if rng.random() < 0.5 else p


def _apart(p: dict) -> bool:
    """The circles do not touch at t = 0 (by 1e-6 m at least)."""
    dx = p["a"] + p["d"] * math.sin(p["f"]) - p["g"] - p["j"] * math.sin(p["l"])
    dy = p["m"] + p["d"] * math.sin(p["q"]) - p["r"] - p["j"] * math.sin(p["w"])
    return math.hypot(dx, dy) > p["x"] + p["z"] + 1e-6


def _draw_plain(orbit1, orbit2, moving2=True):
    def draw(rng):
        while True:
            T = rng.choice([1.0, 2.0, 5.0])
            p = _aimed(rng, _pair(rng, orbit1, orbit2, moving2), T)
            if _apart(p):
                return {"params": p, "horizon": T}
    return draw


def _draw_graze(rng):
    """Both orbiting; radii such that the circles overlap or miss by 1e-9 m
    at their first closest approach."""
    for _ in range(200):
        T = rng.choice([2.0, 5.0])
        p = _pair(rng, True, True)
        gp = Gap("circle-circle", dict(p, x=0.0, z=0.0), T)
        t = _first_extremum(gp, T, gp.G, gp.G1)
        if t is None or gp.G2(t) <= 0:
            continue
        with mpmath.workdps(DPS):
            dist = mpmath.sqrt(gp.G(t))
        if dist < 0.3:
            continue
        total = float(dist + rng.choice([-1e-9, 1e-9]))
        p["x"] = rng.uniform(0.3, 0.7) * total
        p["z"] = total - p["x"]
        return {"params": p, "horizon": T}
    raise RuntimeError("no grazing configuration found")


def _draw_far(rng):
    case = _draw_plain(True, True)(rng)
    off = rng.choice([1e5, -2.5e5])
    for k in "agmr":
        case["params"][k] += off
    return case


FAMILIES = {
    "no spin": (_draw_plain(False, False), "translation only: the polynomial is the exact motion", "circles"),
    "spin vs fixed": (_draw_plain(True, False, moving2=False), "circle 1 orbits, circle 2 rests", "circles"),
    "both orbiting": (_draw_plain(True, True), "both circles orbit and translate", "circles"),
    "grazing": (_draw_graze, "both orbiting, overlap or miss by 1e-9 m at the closest approach", "circles"),
    "far": (_draw_far, "both orbiting, 1e5-2.5e5 m from the origin", "circles"),
}


def _other_shapes():
    """bench/toi_ours.py (the polygon TOI API's driver), when present: its
    FAMILIES join the table, measured with its measure(lang, cases)."""
    try:
        import toi_ours
    except ImportError:
        return None
    FAMILIES.update(getattr(toi_ours, "FAMILIES", {}))
    return toi_ours


def references(cases: list[dict], progress: bool) -> None:
    """Each case's mpmath reference (max2code.conformance.exact_ref)."""
    for i, c in enumerate(cases):
        if progress:
            print(f"\rtoi: references {i + 1}/{len(cases)}", end="", file=sys.stderr, flush=True)
        c["ref"] = reference("circle-circle", c["params"], c["horizon"])
    if progress:
        print(file=sys.stderr)


# ---- scoring --------------------------------------------------------------

def score(answer, ref) -> str:
    """right / wrong / missed / invented for one answer (float, None or "overlapped")."""
    if ref.expect == "overlapped":
        return "right" if answer == "overlapped" else "wrong"
    if answer == "overlapped":
        return "right" if ref.overlapped_ok else "wrong"
    if answer is None:
        return "right" if ref.none_ok else "missed"
    if ref.expect is None and not any(lo <= answer <= hi for lo, hi in ref.accept):
        return "invented"
    if any(lo <= answer <= hi for lo, hi in ref.accept):
        return "right"
    if ref.expect is not None and abs(answer - ref.expect) <= TOL:
        return "right"
    return "wrong"


# ---- ours ---------------------------------------------------------------

class Ours:
    """The generated circle_circle_toc_exact and the single polynomial in C and Rust."""

    def __init__(self, langs: list[str], workdir: str, progress: bool):
        import dataclasses

        from max2code.generate.pipeline import GenerateRequest, generate_file
        from max2code.toolchain import toolchain
        from max2code.toolchain.exact import build_exact_harness, build_poly_harness

        self.harness = {}
        for lang in langs:
            if progress:
                print(f"toi: {lang}: generate and build", file=sys.stderr, flush=True)
            req = GenerateRequest(path=str(EQUATION), lang=lang, out_name="generated")
            plain = generate_file(req)
            sel = plain.selection
            toolchain(lang).exact_harness_build("harness", "harness", workdir)
            self.harness[lang, "poly"] = build_poly_harness(lang, plain.text, plain.function.params, sel.name, True,
                                                            sel.max_degree, os.path.join(workdir, f"{lang}-poly"))
            g = generate_file(dataclasses.replace(req, exact=True))
            self.harness[lang, "exact"] = build_exact_harness(lang, g.text, g.exact,
                                                              os.path.join(workdir, f"{lang}-exact"))

    def run(self, lang: str, kind: str, cases: list[dict], reps: int):
        rows = []
        for c in cases:
            row = [c["params"][k] for k in LETTERS] + [c["horizon"]]
            rows.append(row + [1.0, 1.0, 0.0, 0.0] if kind == "exact" else row)
        answers, ns = self.harness[lang, kind].run(rows, reps=reps)
        out = []
        for st, t in answers:
            out.append(t if st == 1 else "overlapped" if st == 2 else None)
        return out, ns


def measure_ours(ours: Ours, lang: str, kind: str, cases: list[dict], reps: int = PASSES):
    """(answers, ns per query) of one of ours on the cases."""
    return ours.run(lang, kind, cases, reps)


# ---- parry2d ------------------------------------------------------------

def build_parry(progress: bool) -> Path:
    if progress:
        print("toi: parry2d: cargo build --release (the first build fetches and compiles the crates)",
              file=sys.stderr, flush=True)
    target = BUILD / "parry"
    manifest = ROOT / "bench" / "peers" / "parry-toi" / "Cargo.toml"
    subprocess.run(["cargo", "build", "--release", "--quiet", "--manifest-path", str(manifest)], check=True,
                   env=dict(os.environ, CARGO_TARGET_DIR=str(target)))
    return target / "release" / "toi_parry"


def rigid_rows(cases: list[dict]) -> list[list[float]]:
    """Per case: per body the rotation centre, its velocity, the angular
    velocity, the ball's offset from the centre at t = 0 and its radius;
    then the horizon (the layout of bench/peers/parry-toi and bench/peers/box2d/toi.c)."""
    rows = []
    for c in cases:
        p = c["params"]
        row = []
        for a, b, d, e, f, m, n, q, rad in (("a", "b", "d", "e", "f", "m", "n", "q", "x"),
                                           ("g", "h", "j", "k", "l", "r", "s", "w", "z")):
            row += [p[a], p[m], p[b], p[n], p[e], p[d] * math.sin(p[f]), p[d] * math.sin(p[q]), p[rad]]
        rows.append(row + [c["horizon"]])
    return rows


def run_rigid(exe: Path, cases: list[dict], reps: int, tags: tuple[str, ...]):
    text = f"{reps}\n" + "\n".join(" ".join(repr(float(v)) for v in r) for r in rigid_rows(cases)) + "\n"
    proc = subprocess.run([str(exe)], input=text, capture_output=True, text=True, check=True)
    answers = {t: [] for t in tags}
    ns = {}
    for line in proc.stdout.splitlines():
        key, _, val = line.partition(" ")
        if key in answers:
            answers[key].append(None if val == "none" else float(val))
        elif key == "ns":
            tag, _, x = val.partition(" ")
            ns[tag] = float(x)
    return answers, ns


# ---- Box2D --------------------------------------------------------------

def build_box2d(src: Path, progress: bool, driver: str = "toi.c", name: str = "toi_box2d") -> Path:
    """Box2D's library from its source (cmake, release, no samples or tests)
    and a driver of bench/peers/box2d (toi.c: two balls) linked against it."""
    out = BUILD / "box2d"
    out.mkdir(parents=True, exist_ok=True)
    if progress:
        print(f"toi: box2d: cmake build of {src}", file=sys.stderr, flush=True)
    subprocess.run(["cmake", "-S", str(src), "-B", str(out), "-DCMAKE_BUILD_TYPE=Release",
                    "-DBOX2D_SAMPLES=OFF", "-DBOX2D_UNIT_TESTS=OFF", "-DBOX2D_BENCHMARKS=OFF",
                    "-DBOX2D_VALIDATE=OFF"], check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(out), "-j2"], check=True, stdout=subprocess.DEVNULL)
    lib = next(out.rglob("libbox2d*.a"))
    exe = out / name
    subprocess.run(["gcc", "-O2", "-std=c17", f"-I{src / 'include'}", str(ROOT / "bench" / "peers" / "box2d" / driver),
                    "-o", str(exe), str(lib), "-lm"], check=True)
    return exe


# ---- the sweep ----------------------------------------------------------

def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--motions", type=int, default=40, help="cases per family (default 40)")
    ap.add_argument("--rounds", type=int, default=7, help="interleaved timing rounds (default 7)")
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--families", default=",".join(FAMILIES), help="comma-separated, from: " + ", ".join(FAMILIES))
    ap.add_argument("--langs", default="c,rust", help="ours: c, rust or both (default c,rust)")
    ap.add_argument("--box2d-src", type=Path, help="Box2D v3's source tree: also measure b2TimeOfImpact")
    ap.add_argument("--no-parry", action="store_true", help="skip parry2d")
    ap.add_argument("--quiet", action="store_true")
    other = _other_shapes()
    a = ap.parse_args(argv)
    progress = not a.quiet
    families = [f.strip() for f in a.families.split(",") if f.strip()]
    for f in families:
        if f not in FAMILIES:
            ap.error(f"unknown family {f!r}")
    rng = random.Random(a.seed)
    cases = {}
    for f in families:
        if progress:
            print(f"toi: drawing {a.motions} cases: {f}", file=sys.stderr, flush=True)
        cases[f] = [FAMILIES[f][0](rng) for _ in range(a.motions)]
        if FAMILIES[f][2] == "circles":
            references(cases[f], progress)
        elif other is None:
            ap.error(f"family {f!r} needs bench/toi_ours.py")
        else:
            for c in cases[f]:
                c["ref"] = other.reference(c)
    BUILD.mkdir(parents=True, exist_ok=True)
    peers = []         # (label, function(cases, reps) -> (answers, ns))
    with tempfile.TemporaryDirectory(prefix="toi-", dir=BUILD) as tmp:
        langs = [x.strip() for x in a.langs.split(",") if x.strip()]
        ours = Ours(langs, tmp, progress)
        for lang in langs:
            peers.append((f"ours {lang} toc_exact", lambda cs, r, lang=lang: ours.run(lang, "exact", cs, r)))
            peers.append((f"ours {lang} polynomial", lambda cs, r, lang=lang: ours.run(lang, "poly", cs, r)))
        rigid = []
        if not a.no_parry:
            rigid.append((build_parry(progress), ("f64", "f32"), "parry2d"))
        if a.box2d_src:
            rigid.append((build_box2d(a.box2d_src, progress), ("b2",), "box2d"))
        for exe, tags, name in rigid:
            for tag in tags:
                def fn(cs, r, exe=exe, tags=tags, tag=tag):
                    ans, ns = run_rigid(exe, cs, r, tags)
                    return ans[tag], ns.get(tag)
                peers.append((f"{name} {tag}" if name != "box2d" else "box2d b2TimeOfImpact", fn))
        circle_peers = list(peers)
        if other is not None:
            for lang in langs:
                peers.append((f"ours {lang} toi", lambda cs, r, lang=lang: other.measure(lang, cs)))
        serves = {(f, label): (FAMILIES[f][2] == "circles") == (label in dict(circle_peers))
                  for f in families for label, _ in peers}
        ns = {(f, p): [] for f in families for p, _ in peers if serves[f, p]}
        answers = {}
        for rnd in range(a.rounds):
            order = peers[rnd % len(peers):] + peers[:rnd % len(peers)]
            for f in families:
                for label, fn in order:
                    if not serves[f, label]:
                        continue
                    if progress:
                        print(f"\rtoi: round {rnd + 1}/{a.rounds}: {f}: {label}" + " " * 20, end="",
                              file=sys.stderr, flush=True)
                    ans, t = fn(cases[f], PASSES)
                    ns[f, label].append(t)
                    answers[f, label] = ans
        if progress:
            print(file=sys.stderr)
    print("| family | peer | ns per query | right | wrong | missed | invented | largest error s |")
    print("|---|---|---|---|---|---|---|---|")
    for f in families:
        for label, _ in peers:
            if not serves[f, label]:
                continue
            counts = {"right": 0, "wrong": 0, "missed": 0, "invented": 0}
            worst = 0.0
            for ans, c in zip(answers[f, label], cases[f]):
                counts[score(ans, c["ref"])] += 1
                if isinstance(ans, float) and isinstance(c["ref"].expect, float):
                    worst = max(worst, abs(ans - c["ref"].expect))
            print(f"| {f} | {label} | {statistics.median(ns[f, label]):,.0f} | {counts['right']} | {counts['wrong']} | "
                  f"{counts['missed']} | {counts['invented']} | {worst:.1e} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
