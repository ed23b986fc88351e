"""Reference cases for any equation: `max2code cases EQ.mxm [-n N] [--seed S] -o FILE.jsonl`.

Parameters are drawn per the equation's declarations (a range per role, or
per the unit its description names), and each draw becomes a conformance
case of op "toc": the contact time through the generated `NAME_toc`, and,
when the polynomial is the exact gap (docs/exact-motion.md, "Which equations
get which entries"), a second case through `NAME_toc_exact` ("motion":
"exact").

References are independent of the generated code: Maxima's polynomial (the
exact rational coefficients max2code proved) is evaluated in mpmath at
DPS digits on the drawn doubles, its real roots found at that precision.
Where the double evaluation of the coefficients cannot decide the sign of
the polynomial (|P(t)| <= delta(t) = BAND eps sum_k S_k t^k, S_k the
magnitude sum of coefficient k's terms) the case accepts any answer inside
that zone; a zone across which P keeps its sign (a graze, within rounding)
may be answered or not (`none_ok` when no later zone must be).  The
acceptance intervals `accept` hold every zone up to the first one the
polynomial surely crosses.  For the exact motion the rules at t = 0 come
first: overlapped (the gap surely below minus the runtimes' band), a
contact at 0 (touching and surely approaching), or the search after a
separating touch; ambiguous draws are drawn again.

Families, in turn: random, contact (a root surely inside the horizon),
grazing (a double root: a parameter solved so that the gap and its slope
vanish together), touching at t = 0 (approaching, separating), overlapping
at t = 0, multiple roots (two or more in the horizon), large and small
scales (every length-like parameter times 1e6 and 1e-6: the contact times
stay, the coefficients span many magnitudes).
"""
from __future__ import annotations

import json
import math
import os
import random
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import mpmath

from max2code.errors import ArgumentParser, Max2CodeError, SourceError
from max2code.generate.expr import Add, Call, Mul, Num, Pow, Sym

EPS = 2.0 ** -52
DPS = 80                  # mpmath digits of the references
BAND = 512                # the zone where double arithmetic cannot decide the polynomial's sign: BAND eps S(t)
RT_FLOOR = 64             # the runtimes' zero band at t = 0: 64 eps S_gap(0) (docs/exact-motion.md)
RT_ERROR = 16             # what a double evaluation of the gap may be off by, in eps S_gap: decided beyond it
REL = 1e-12               # every accepted interval is widened by this much relative (the solvers' last bits)
HORIZONS = (0.5, 2.0, 5.0)
FAMILIES = ("random", "contact", "grazing", "touching", "overlapping", "multiple", "large", "small")
SCALES = {"large": 1e6, "small": 1e-6}
TRIES = 150               # draws per case before a family is given up for this case
KNOBS = 3                 # parameters tried when a family solves for one
SOLVE_DPS, SOLVE_STEPS = 40, 30

# (low, high) of a uniform draw per parameter role
ROLE_RANGES = {"position": (-5.0, 5.0), "velocity": (-3.0, 3.0), "acceleration": (-2.0, 2.0),
               "orbit_radius": (0.0, 1.0), "angular_velocity": (-3.0, 3.0), "phase": (-3.1, 3.1),
               "radius": (0.1, 1.5)}
LENGTH_ROLES = ("position", "velocity", "acceleration", "orbit_radius", "radius")


# ------------------------------------------------------------------ the equation
@dataclass
class Equation:
    """What the references need of a .mxm file."""
    path: str
    name: str                 # the file's stem: the cases' "equation"
    params: tuple[str, ...]
    ranges: dict[str, tuple[float, float]]
    lengths: tuple[str, ...]  # parameters scaled by the large and small families
    coefficients: tuple       # Maxima's polynomial: Poly per power of t
    exact: object | None      # exact.ExactSection when the polynomial is the exact gap, else None
    why_not_exact: str        # why there are no exact-motion cases
    windowed: bool = False    # the file declares `exact` approximations: NAME_toc_exact by windows (no cases here)


def _range_of(name: str, doc: str, role: str | None) -> tuple[tuple[float, float], bool]:
    """(range, length-like) of a parameter: from its role, else from the unit its description names."""
    if role in ROLE_RANGES:
        return ROLE_RANGES[role], role in LENGTH_ROLES
    unit = re.search(r"\(([^()]*)\)", doc or "")
    unit = unit.group(1) if unit else ""
    length = re.search(r"(?<![A-Za-z])m(?![A-Za-z])", unit) is not None
    if length and "radius" in doc.lower():
        return (0.5, 10.0), True
    if re.search(r"(?<![A-Za-z])rad(?![A-Za-z])", unit):
        return (-3.0, 3.0), False
    if length and re.search(r"m\s*/\s*s\s*\^?\s*[2-9]|s\^[2-9]", unit):
        return (-2.0, 2.0), True
    if length and "/" in unit:
        return (-3.0, 3.0), True
    if length:
        return (-5.0, 5.0), True
    return (-3.0, 3.0), False


def load_equation(path: str, ranges: dict[str, tuple[float, float]] | None = None, *, use_cache: bool = True,
                  progress: bool = False) -> Equation:
    """Maxima's polynomial of `path` and, when it is the exact gap, the exact section."""
    # imported here: the conformance runner starts without the generator
    from max2code.generate.derive import derive, parameters_of
    from max2code.generate.exact import derive_exact
    from max2code.generate.mxm import read_mxm
    from max2code.generate.names import check_names

    mod = read_mxm(path)
    check_names(mod)
    d = derive(mod, {}, use_cache=use_cache, progress=progress)
    params, docs = parameters_of(d)
    roles = {p.name: p.effect for p in mod.parameters}
    out_ranges, lengths = {}, []
    for name, doc in zip(params, docs):
        rng, length = _range_of(name, doc, roles.get(name))
        out_ranges[name] = rng
        if length:
            lengths.append(name)
    for name, rng in (ranges or {}).items():
        if name not in out_ranges:
            raise Max2CodeError(f"max2code cases: error: --range {name}: {path} has no parameter '{name}' "
                                f"(its parameters: {', '.join(params)})")
        out_ranges[name] = rng
    exact, why = None, ""
    if mod.approximations:
        why = "its polynomial approximates (an 'exact' declaration): only NAME_toc cases"
    else:
        try:
            exact = derive_exact(d, progress=progress, use_cache=use_cache)
        except SourceError as exc:
            why = f"its polynomial is not the exact gap ({exc.message}): only NAME_toc cases"
    stem = os.path.splitext(os.path.basename(path))[0]
    return Equation(path, stem, params, out_ranges, tuple(lengths), d.polynomial.coefficients, exact, why,
                    bool(mod.approximations))


# ------------------------------------------------------------- exact evaluation
def _atom(e, values) -> mpmath.mpf:
    if isinstance(e, Sym):
        return +mpmath.pi if e.name == "%pi" else values[e.name]
    if isinstance(e, Call):
        f = {"sin": mpmath.sin, "cos": mpmath.cos, "sqrt": mpmath.sqrt, "abs": abs}[e.func]
        return f(_atom(e.args[0], values))
    raise TypeError(e)


def coefficients(eq: Equation, values: dict) -> tuple[list, list]:
    """(c_k, S_k): the polynomial's coefficients at the parameters and the magnitude sums of their terms."""
    cs, ss = [], []
    for poly in eq.coefficients:
        atoms = {k: _atom(e, values) for k, e in poly.atoms}
        c = s = mpmath.mpf(0)
        for mono, q in poly.terms:
            v = mpmath.mpf(q.numerator) / q.denominator
            for k, n in mono:
                v *= atoms[k] ** n
            c += v
            s += abs(v)
        cs.append(c)
        ss.append(s)
    while len(cs) > 1 and cs[-1] == 0 and ss[-1] == 0:
        cs.pop()
        ss.pop()
    return cs, ss


def expr_value(e, values, magnitude: bool = False) -> mpmath.mpf:
    """An Expr at `values` (the parameters and the variable); with `magnitude`, the rounding scale
    of max2code.generate.exact.rounding_scale (sums of magnitudes, a call
    counts 1 + the scale of its argument)."""
    if isinstance(e, Num):
        v = mpmath.mpf(e.value.numerator) / e.value.denominator
        return abs(v) if magnitude else v
    if isinstance(e, Sym):
        v = +mpmath.pi if e.name == "%pi" else values[e.name]
        return abs(v) if magnitude else v
    if isinstance(e, Call):
        if magnitude:
            return 1 + expr_value(e.args[0], values, True)
        return _atom(Call(e.func, (Sym("__arg__"),)), {"__arg__": expr_value(e.args[0], values)})
    if isinstance(e, Add):
        return mpmath.fsum(expr_value(x, values, magnitude) for x in e.terms)
    if isinstance(e, Mul):
        v = mpmath.mpf(1)
        for x in e.factors:
            v *= expr_value(x, values, magnitude)
        return v
    if isinstance(e, Pow):
        n = int(e.exp.value)
        if n < 0 and magnitude:
            return 1 / abs(expr_value(e.base, values) ** -n)
        return expr_value(e.base, values, magnitude) ** n
    raise TypeError(e)


def _polyval(c, t):
    v = mpmath.mpf(0)
    for x in reversed(c):
        v = v * t + x
    return v


def _deriv(c):
    return [k * x for k, x in enumerate(c)][1:] or [mpmath.mpf(0)]


def _real_roots(c, lo, hi) -> list:
    """Real roots of the polynomial c (ascending) in [lo, hi], at DPS digits."""
    c = list(c)
    while len(c) > 1 and c[-1] == 0:
        c.pop()
    if len(c) < 2:
        return []
    roots = mpmath.polyroots(list(reversed(c)), maxsteps=2000, extraprec=4 * DPS)
    scale = max(1, abs(lo), abs(hi))
    out = sorted(mpmath.re(r) for r in roots if abs(mpmath.im(r)) <= mpmath.mpf(10) ** (-DPS // 3) * scale)
    return [r for r in out if lo <= r <= hi]


# ------------------------------------------------------------------- zones
@dataclass
class Zone:
    lo: mpmath.mpf
    hi: mpmath.mpf
    crossing: bool            # P surely changes sign across it
    edge: bool                # it touches t = 0 or the horizon: its root may lie outside the window


def zones(c, s, T) -> list[Zone]:
    """The stretches of [0, T] where |P| <= delta (the double coefficients cannot decide P's sign)."""
    T = mpmath.mpf(T)
    n = max(len(c), len(s))
    delta = [BAND * EPS * (s[k] if k < len(s) else 0) for k in range(n)]
    cp = [(c[k] if k < len(c) else 0) - delta[k] for k in range(n)]
    cm = [(c[k] if k < len(c) else 0) + delta[k] for k in range(n)]
    cuts = sorted(set([mpmath.mpf(0), T] + _real_roots(cp, 0, T) + _real_roots(cm, 0, T)))

    def inside(t):
        return abs(_polyval(c, t)) <= _polyval(delta, t)

    spans = []
    for a, b in zip(cuts, cuts[1:]):
        if inside((a + b) / 2):
            if spans and spans[-1][1] == a:
                spans[-1][1] = b
            else:
                spans.append([a, b])
    for x in cuts:        # a zone of one point (P = +-delta touching)
        if inside(x) and not any(a <= x <= b for a, b in spans):
            spans.append([x, x])
    spans.sort()
    out = []
    for a, b in spans:
        edge = a == 0 or b == T
        left, right = _polyval(c, a), _polyval(c, b)
        out.append(Zone(a, b, (not edge) and (left > 0) != (right > 0), edge))
    return out


def first_root(c, z: Zone):
    """The exact polynomial's first root in zone z, or None."""
    f = lambda t: _polyval(c, t)    # noqa: E731
    pts = [z.lo + (z.hi - z.lo) * k / 64 for k in range(65)]
    for a, b in zip(pts, pts[1:]):
        fa, fb = f(a), f(b)
        if fa == 0:
            return a
        if (fa > 0) != (fb > 0):
            for _ in range(4 * DPS):
                m = (a + b) / 2
                if (f(m) > 0) == (fa > 0):
                    a = m
                else:
                    b = m
            return (a + b) / 2
    return pts[-1] if f(pts[-1]) == 0 else None


def judgement(c, s, T) -> dict:
    """accept, none_ok, expect and regular for the smallest root in (0, T]."""
    zs = zones(c, s, T)
    accept, expect, must = [], None, False
    for z in zs:
        accept.append([float(z.lo * (1 - REL)), float(z.hi * (1 + REL))])
        if expect is None:
            r = first_root(c, z)
            if r is not None and r > 0:
                expect = r
        if z.crossing:
            must = True
            break
    regular = bool(must and len(accept) == 1 and expect is not None and zs[0].hi - zs[0].lo <= 2e-12 * expect)
    return {"expect": None if expect is None else float(expect), "accept": accept, "none_ok": not must,
            "regular": regular}


# ------------------------------------------------------------ exact-motion rules at t = 0
def exact_judgement(eq: Equation, values, c, s, T) -> dict | None:
    """The exact-motion case's answer, or None when the draw is ambiguous at t = 0."""
    sec = eq.exact
    z = mpmath.mpf(0)
    g0 = _polyval(c, z)
    at0 = dict(values, **{sec.variable: z})
    s0 = expr_value(sec.gap_expr, at0, magnitude=True)
    if g0 < -(RT_FLOOR + RT_ERROR) * EPS * s0:
        return {"expect": "overlapped", "accept": [], "none_ok": False, "regular": False}
    if g0 > (RT_FLOOR + RT_ERROR) * EPS * s0:
        return judgement(c, s, T)
    if abs(g0) > (RT_FLOOR - RT_ERROR) * EPS * s0:
        return None                                         # the runtimes' band may or may not hold it
    d0 = _polyval(_deriv(c), z)
    sd = expr_value(sec.gap_dt_expr, at0, magnitude=True)
    if abs(d0) <= 256 * EPS * sd:
        return None                                         # resting: the direction is not decided
    if d0 < 0:
        return {"expect": 0.0, "accept": [[0.0, 0.0]], "none_ok": False, "regular": False}
    # separating: the search starts where the gap has left the band; the first zone's answers stand
    return judgement(c, s, T)


# ------------------------------------------------------------------- draws
def _draw(eq: Equation, rng: random.Random) -> dict:
    return {p: rng.uniform(*eq.ranges[p]) for p in eq.params}


def _mp(values: dict) -> dict:
    return {k: mpmath.mpf(v) for k, v in values.items()}


def _knobs(eq: Equation) -> list[str]:
    """Parameters to solve for in the constructed families: radii, then positions, then the rest."""
    first = [p for p in eq.params if eq.ranges[p] == ROLE_RANGES["radius"]]
    return first + [p for p in eq.params if p not in first]


def _solve(eq: Equation, values: dict, equations, unknowns0) -> dict | None:
    """Solve for one parameter (and t when two equations) with mpmath.findroot; doubles of the result."""
    for q in _knobs(eq)[:KNOBS]:
        if eq.ranges[q][0] >= 0 and values[q] == 0:
            continue
        try:
            def fs(*x):
                v = _mp(values)
                v[q] = x[0]
                return equations(v, *x[1:])
            with mpmath.workdps(SOLVE_DPS):
                x0 = [mpmath.mpf(values[q])] + list(unknowns0)
                sol = mpmath.findroot(fs, x0 if len(x0) > 1 else x0[0], tol=mpmath.mpf(10) ** (-SOLVE_DPS + 6),
                                      maxsteps=SOLVE_STEPS)
        except (ValueError, ZeroDivisionError, mpmath.libmp.NoConvergence):
            continue
        sol = list(sol) if hasattr(sol, "__len__") else [sol]
        x = float(mpmath.re(sol[0]))
        if not math.isfinite(x) or (eq.ranges[q][0] >= 0 and x <= 0):
            continue
        if len(sol) > 1 and not (0 < float(mpmath.re(sol[1]))):
            continue
        out = dict(values)
        out[q] = x
        return out
    return None


def _local_min(c, T):
    """A local minimum of |P| inside (0, T) where P keeps its sign (a near miss or a near graze)."""
    for r in _real_roots(_deriv(c), 0, T):
        if 0 < r < T:
            return r
    return None


def _family(eq: Equation, family: str, rng: random.Random, T: float) -> dict | None:
    """One draw of `family`, or None."""
    v = _draw(eq, rng)
    c, s = coefficients(eq, _mp(v))
    if family == "random":
        return v
    if family in ("contact", "large", "small"):
        if c[0] > 0 and not judgement(c, s, T)["none_ok"]:
            if family in SCALES:
                if not eq.lengths:
                    return None
                k = SCALES[family]
                return {p: (x * k if p in eq.lengths else x) for p, x in v.items()}
            return v
        return None
    if family == "multiple":
        return v if len([r for r in _real_roots(c, 0, T) if r > 0]) >= 2 else None
    if family == "grazing":
        t0 = _local_min(c, T) if c[0] > 0 else None
        if t0 is None or _polyval(c, t0) <= 0:
            return None       # wanted: apart at t = 0 and a near miss inside the horizon, made a graze

        def graze(vals, t):
            cc, _ = coefficients(eq, vals)
            return [_polyval(cc, t), _polyval(_deriv(cc), t)]
        w = _solve(eq, v, graze, [t0])
        return w if w is not None and coefficients(eq, _mp(w))[0][0] > 0 else None   # apart at t = 0
    if family == "touching":
        return _solve(eq, v, lambda vals: coefficients(eq, vals)[0][0], [])
    if family == "overlapping":
        target = -mpmath.mpf("0.05") * (s[0] if s[0] else 1)
        return _solve(eq, v, lambda vals: coefficients(eq, vals)[0][0] - target, [])
    raise ValueError(family)


def make_cases(eq: Equation, n: int, seed: int, progress=None) -> tuple[list[dict], list[str]]:
    """n draws (families in turn), each a NAME_toc case and, for an exact gap, a NAME_toc_exact case."""
    rng = random.Random(seed)
    cases, notes = [], []
    given_up: dict[str, int] = {}
    with mpmath.workdps(DPS):
        for k in range(n):
            family = FAMILIES[k % len(FAMILIES)]
            made = None
            for _ in range(TRIES):
                T = rng.choice(HORIZONS)
                v = _family(eq, family, rng, T)
                if v is None:
                    continue
                vals = _mp(v)
                c, s = coefficients(eq, vals)
                try:
                    taylor = judgement(c, s, T)
                    exact = exact_judgement(eq, vals, c, s, T) if eq.exact is not None else None
                except mpmath.libmp.NoConvergence:
                    continue
                if eq.exact is not None and exact is None:
                    continue
                made = (v, T, taylor, exact)
                break
            if made is None:
                given_up[family] = given_up.get(family, 0) + 1
                continue
            v, T, taylor, exact = made
            base = {"op": "toc", "equation": eq.name, "family": family, "params": v, "horizon": T}
            cases.append({"id": f"{eq.name}-{family}-{k:03d}", **base, **taylor})
            if exact is not None:
                cases.append({"id": f"{eq.name}-exact-{family}-{k:03d}", **base, "motion": "exact", **exact})
            if progress:
                progress(k + 1, n)
    for family, count in sorted(given_up.items()):
        notes.append(f"{family}: {count} case(s) not made (no draw of this family in {TRIES} tries)")
    if eq.exact is None:
        notes.append(f"no exact-motion cases: {eq.why_not_exact}")
    return cases, notes


def write_cases(cases: list[dict], out) -> None:
    for case in cases:
        out.write(json.dumps(case) + "\n")


def _range_arg(text: str) -> tuple[str, tuple[float, float]]:
    name, sep, rest = text.partition("=")
    lo, sep2, hi = rest.partition("..")
    try:
        a, b = float(lo), float(hi)
    except ValueError:
        a = b = math.nan
    if not (sep and sep2 and name.strip() and math.isfinite(a) and math.isfinite(b) and a <= b):
        raise Max2CodeError(f"max2code cases: error: --range expects NAME=LOW..HIGH (numbers, LOW <= HIGH), got {text!r}")
    return name.strip(), (a, b)


def main(argv: list[str]) -> int:
    from max2code.progress import bar
    from max2code.textio import check_output, write_output

    ap = ArgumentParser(prog="max2code cases",
                        description="Write reference conformance cases (JSON lines, op toc) for an equation: random "
                                    "draws of its declared parameters, grazing, touching, overlapping, multiple roots "
                                    "and large and small scales, with mpmath references (docs/conformance.md).")
    ap.add_argument("file", help="the .mxm file")
    ap.add_argument("-n", type=int, default=40, metavar="N", help="parameter draws (default 40; each gives a NAME_toc "
                                                                   "case and, for an exact gap, a NAME_toc_exact case)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the draws (default 1): the same seed writes the same bytes")
    ap.add_argument("--range", action="append", default=[], metavar="NAME=LOW..HIGH",
                    help="draw parameter NAME uniformly in [LOW, HIGH] (repeatable; default: by its role or unit)")
    ap.add_argument("-o", "--output", default="-", help="the .jsonl file ('-' for standard output, the default)")
    ap.add_argument("--quiet", "-q", action="store_true", help="no progress line")
    args = ap.parse_args(argv)
    if args.n < 1:
        raise Max2CodeError("max2code cases: error: -n must be at least 1")
    check_output(args.output)
    eq = load_equation(args.file, dict(_range_arg(r) for r in args.range), progress=False)
    show = None if args.quiet else (lambda k, n: bar(k, n, f"{eq.name}: draws", prefix="cases"))
    cases, notes = make_cases(eq, args.n, args.seed, show)
    if not cases:
        raise Max2CodeError(f"{args.file}: error: no case could be made (every family failed {TRIES} draws); "
                            "give the parameters ranges with --range NAME=LOW..HIGH")
    import io
    buf = io.StringIO()
    write_cases(cases, buf)
    write_output(args.output, buf.getvalue())
    if not args.quiet:
        kinds = sum(1 for c in cases if c.get("motion") == "exact")
        print(f"max2code cases: {len(cases)} cases ({len(cases) - kinds} NAME_toc, {kinds} NAME_toc_exact) for "
              f"{eq.name}" + (f" in {args.output}" if args.output != "-" else ""), file=sys.stderr)
        for line in notes:
            print(f"max2code cases: note: {line}", file=sys.stderr)
    return 0


def cases_for(path: str, n: int = 24, seed: int = 1) -> list[dict]:
    """The cases `max2code cases PATH -n N --seed S` writes (for `conformance --equation` without --cases)."""
    return make_cases(load_equation(path), n, seed)[0]


__all__ = ["Equation", "load_equation", "make_cases", "cases_for", "main", "Path"]
