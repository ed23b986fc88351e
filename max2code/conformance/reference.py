"""Reference answers for the "roots" op, from the exact double coefficients.

The polynomial is taken exactly (each double is a rational number); Yun's
square-free factorisation over the rationals gives every root's multiplicity
exactly, and mpmath (at 120 digits) finds the roots of each square-free factor.
The tolerance of each real root follows docs/roots.md:

    tol = max(1e-12 |r|, 4 * (m! * eps * ptilde(|r|) / |p^(m)(r)|)^(1/m), floor)

with floor = 1e-300 (2^-1074 for the scaled cases, whose roots go down to 1e-300).
"""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath

EPS = 2.0 ** -52
DPS = 120


def _trim(p: list[Fraction]) -> list[Fraction]:
    p = list(p)
    while p and p[-1] == 0:
        p.pop()
    return p


def _deriv(p: list[Fraction]) -> list[Fraction]:
    return [p[i] * i for i in range(1, len(p))]


def _divmod(a: list[Fraction], b: list[Fraction]) -> tuple[list[Fraction], list[Fraction]]:
    a = list(a)
    q = [Fraction(0)] * max(len(a) - len(b) + 1, 1)
    while len(a) >= len(b) and a:
        f = a[-1] / b[-1]
        k = len(a) - len(b)
        q[k] = f
        for i in range(len(b)):
            a[k + i] -= f * b[i]
        a.pop()
        a = _trim(a)
    return _trim(q), a


def _gcd(a: list[Fraction], b: list[Fraction]) -> list[Fraction]:
    a, b = _trim(a), _trim(b)
    while b:
        _, r = _divmod(a, b)
        a, b = b, r
    lc = a[-1]
    return [x / lc for x in a]


def squarefree(p: list[Fraction]) -> list[tuple[list[Fraction], int]]:
    """Yun's algorithm: [(factor, multiplicity)] with p = lc * prod factor^m."""
    p = _trim(p)
    out = []
    dp = _deriv(p)
    a = _gcd(p, dp)
    b, _ = _divmod(p, a)
    c, _ = _divmod(dp, a)
    d = [x - y for x, y in _zip_pad(c, _deriv(b))]
    d = _trim(d)
    m = 1
    while len(b) > 1:
        a = _gcd(b, d)
        if len(a) > 1:
            out.append((a, m))
        b, _ = _divmod(b, a)
        c, _ = _divmod(d, a)
        d = _trim([x - y for x, y in _zip_pad(c, _deriv(b))])
        m += 1
    return out


def _zip_pad(x, y):
    n = max(len(x), len(y))
    x = list(x) + [Fraction(0)] * (n - len(x))
    y = list(y) + [Fraction(0)] * (n - len(y))
    return zip(x, y)


def _mpf(x: Fraction):
    return mpmath.mpf(x.numerator) / mpmath.mpf(x.denominator)


def _refined(desc, approx):
    """Each approximation refined by Newton's method at three times the
    working precision; None when two of them end on one root."""
    out = []
    with mpmath.workdps(3 * DPS):
        tiny = mpmath.mpf(10) ** (-DPS)
        for z in approx:
            z = mpmath.mpc(z)
            for _ in range(400):
                v, d = mpmath.polyval(desc, z, derivative=True)
                if d == 0:
                    break
                step = v / d
                z -= step
                if abs(step) <= tiny * abs(z):
                    break
            out.append(z)
    sep = mpmath.mpf(10) ** (-(DPS // 2))
    for i in range(len(out)):
        for j in range(i + 1, len(out)):
            if abs(out[i] - out[j]) <= sep * max(abs(out[i]), abs(out[j])):
                return None
    return out


def _certain_roots(desc):
    """All roots of a square-free polynomial (descending mpf coefficients)
    whose roots may span 600 decades: polyroots' approximations, refined by
    Newton's method, must end on as many distinct roots as the degree (a
    spurious approximation ends on another root and is caught); otherwise
    polyroots again with more working precision."""
    for extra, steps in ((12 * DPS, 2000), (40 * DPS, 20000), (120 * DPS, 50000)):
        try:
            approx = mpmath.polyroots(desc, maxsteps=steps, extraprec=extra)
        except mpmath.libmp.libhyper.NoConvergence:
            continue
        out = _refined(desc, approx)
        if out is not None:
            return out
    raise RuntimeError("reference roots: no certain set of roots")


def real_roots(coeffs: list[float], scale: Fraction | None = None) -> list[tuple[mpmath.mpf, int]]:
    """All distinct real roots (as mpf at DPS digits) with multiplicities, ascending.

    With `scale` (the magnitude of the roots, for the any-magnitude cases) each
    square-free factor is solved in u = t / scale, exactly transformed, and a
    root counts as real when its imaginary part is below 1e-60 of its modulus
    (rather than of 1 + |re|, which would call a complex pair of size 1e-300
    real)."""
    p = _trim([Fraction(c) for c in coeffs])
    if len(p) <= 1:
        return []
    out = []
    with mpmath.workdps(DPS):
        for f, m in squarefree(p):
            if len(f) == 2:
                out.append((_mpf(-f[0]) / _mpf(f[1]), m))
                continue
            if scale is not None:
                f = [v * scale ** i for i, v in enumerate(f)]
            desc = [_mpf(x) for x in reversed(f)]
            if scale is not None:
                roots = _certain_roots(desc)
            else:
                try:
                    roots = mpmath.polyroots(desc, maxsteps=2000, extraprec=12 * DPS)
                except mpmath.libmp.libhyper.NoConvergence:
                    # widely spread roots (e.g. 1 and 1e600) need more working precision
                    roots = mpmath.polyroots(desc, maxsteps=50000, extraprec=40 * DPS)
            for z in roots:
                z = mpmath.mpc(z)
                size = abs(z) if scale is not None else 1 + abs(z.real)
                if abs(z.imag) <= mpmath.mpf(10) ** (-(DPS // 2)) * size:
                    r = mpmath.mpf(z.real)
                    out.append((r * _mpf(scale) if scale is not None else r, m))
    out.sort(key=lambda rm: rm[0])
    return out


def tolerance(coeffs: list[float], r, m: int, floor: float = 1e-300) -> float:
    """Accepted distance from the reference root r of multiplicity m."""
    with mpmath.workdps(DPS):
        p = [mpmath.mpf(c) for c in coeffs]
        ar = abs(r)
        pt = sum(abs(c) * ar ** i for i, c in enumerate(p))
        dm = mpmath.mpf(0)
        for i in range(m, len(p)):
            dm += p[i] * mpmath.ff(i, m) * r ** (i - m)
        rel = mpmath.mpf(1e-12) * ar
        if dm == 0:
            cond = mpmath.inf
        else:
            cond = 4 * (math.factorial(m) * mpmath.mpf(EPS) * pt / abs(dm)) ** (mpmath.mpf(1) / m)
        tol = max(rel, cond, mpmath.mpf(floor))
        return float(tol)


def reference(coeffs: list[float], lo: float, hi: float, floor: float = 1e-300, limit: float = 1e300,
              scale: Fraction | None = None) -> dict:
    """Reference fields of a roots case: expect (float or None), and the real
    roots near (lo, hi] that decide acceptance, each [r, m, tol].  `floor` is
    the absolute floor of the tolerance and roots beyond `limit` are left out
    (the scaled cases use the smallest subnormal and the largest double);
    `scale` as in real_roots."""
    bad = any(not math.isfinite(c) for c in coeffs) or not (math.isfinite(lo) and math.isfinite(hi)) or not (lo < hi)
    if bad:
        return {"expect": None, "roots": []}
    roots = real_roots(coeffs, scale)
    near = []
    expect = None
    with mpmath.workdps(DPS):
        for r, m in roots:
            if abs(r) > limit:      # beyond any finite interval of doubles
                continue
            tol = min(tolerance(coeffs, r, m, floor), 1e300)
            if r <= lo - tol or r > hi + tol:
                continue
            rf = float(r)
            near.append([rf, m, tol])
            if expect is None and lo < r <= hi:
                expect = rf
    return {"expect": expect, "roots": near}
