"""Smallest real root of a polynomial in (lo, hi]: the Python runtime.

Pure Python on purpose: it performs the same IEEE operations in the same order
as the C, Rust and Modula-2 runtimes, so the four agree bit for bit.  The
algorithm and its contract are specified in docs/roots.md.
"""
from __future__ import annotations

import math

__all__ = ["smallest_root", "MAX_DEGREE"]

MAX_DEGREE = 16
EPS = 2.0 ** -52          # unit roundoff times two (spacing of doubles at 1)
SPLITTER = 134217729.0    # 2^27 + 1, Veltkamp splitting constant
TINY = 2.0 ** -1000       # absolute floor of the touching bound
SIXTEENTH = 2.0 ** -16    # bisection step from an end at zero
NEWTON_TOL = 2.0 ** -30   # an accepted Newton step this small (relative) has converged
HALLEY_TOL = 2.0 ** -8    # an accepted Halley step this small: the polish finishes it (Bernstein's single root)
HALLEY_MIN = 2.0 ** -968  # Halley's products below this lose precision to underflow
HANDOFF_TOL = 2.0 ** -14  # ... or an accepted Newton step (Halley refused) this small
POLISH_TOL = 2.0 ** -22   # a polishing Halley step this small ends the polish
MAXIT = 100               # bracketed Newton step limit
MODERATE_LO = 2.0 ** -200  # degree-2 fast path: every coefficient 0 or in [2^-200, 2^200)
MODERATE_HI = 2.0 ** 200
QUAD_SPREAD = 900         # degree 2: one scale when the coefficient exponents span at most this
ONE_SCALE_SPAN = 800      # degree n >= 3: one scale when all roots lie in 2^(+-800/n)
BAND_SPAN = 800           # otherwise bands of magnitude 2^(800/n)
_ldexp = math.ldexp

_isfinite = math.isfinite
_fabs = math.fabs
_sqrt = math.sqrt
_frexp = math.frexp


def _two_prod(a: float, b: float) -> tuple[float, float]:
    """Error-free product: a*b = p + e exactly (Dekker, no FMA)."""
    p = a * b
    t = SPLITTER * a
    ah = t - (t - a)
    al = a - ah
    t = SPLITTER * b
    bh = t - (t - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


def _comp_horner(a: list[float], n: int, x: float) -> float:
    """p(x) by compensated Horner: as accurate as Horner in twice the precision."""
    s = a[n]
    c = 0.0
    for i in range(n - 1, -1, -1):
        # TwoProduct(s, x), inlined
        p = s * x
        t = SPLITTER * s
        sh = t - (t - s)
        sl = s - sh
        t = SPLITTER * x
        xh = t - (t - x)
        xl = x - xh
        pe = ((sh * xh - p) + sh * xl + sl * xh) + sl * xl
        # TwoSum(p, a[i])
        ai = a[i]
        s = p + ai
        z = s - p
        se = (p - (s - z)) + (ai - z)
        c = c * x + (pe + se)
    return s + c


def _sign_top(a: list[float], n: int, x: float) -> int:
    """Sign of p(x) in {-1, 0, +1}; 0 means zero within the rounding bound."""
    fabs = _fabs
    ax = fabs(x)
    v = a[n]
    pt = fabs(v)
    for ai in a[n - 1::-1]:
        v = v * x + ai
        pt = pt * ax + fabs(ai)
    if fabs(v) > 2.0 * n * EPS * pt:
        return 1 if v > 0.0 else -1
    r = _comp_horner(a, n, x)
    bound = (2.0 * n * EPS) * (2.0 * n * EPS) * pt + TINY
    if _fabs(r) <= bound:
        return 0
    return 1 if r > 0.0 else -1


def _sign_plain(a: list[float], n: int, x: float) -> int:
    v = a[n]
    for ai in a[n - 1::-1]:
        v = v * x + ai
    if v > 0.0:
        return 1
    if v < 0.0:
        return -1
    return 0


def _midpoint(xa: float, xb: float, half: float) -> float:
    """Bisection point of [xa, xb] (half = (xb - xa)/2): geometric when the
    bracket spans more than a factor 8 on one side of zero, so that roots far
    smaller than the bracket are reached in few steps."""
    if xa < 0.0 < xb:
        return 0.0
    if xa > 0.0 and xb > 8.0 * xa:
        return _sqrt(xa) * _sqrt(xb)
    if xb < 0.0 and xa < 8.0 * xb:
        return -(_sqrt(-xa) * _sqrt(-xb))
    if xa == 0.0 and xb > 0.0:
        return xb * SIXTEENTH
    if xb == 0.0 and xa < 0.0:
        return xa * SIXTEENTH
    return xa + half


def _newton(a: list[float], n: int, lo: float, hi: float, slo: int, x0: float,
            tolnewton: float = NEWTON_TOL) -> float:
    """Root of p in (lo, hi) where p(lo) has sign slo and p(hi) the other,
    starting at x0 (lo < x0 < hi)."""
    xa = lo
    xb = hi
    x = x0
    dx = xb - xa
    dxold = dx
    neg = slo < 0
    an = a[n]
    rest = a[n - 1::-1]
    fabs = _fabs
    for _ in range(MAXIT):
        v = an
        d = 0.0
        for ai in rest:
            d = d * x + v
            v = v * x + ai
        if v == 0.0:
            return x
        if (v < 0.0) == neg:
            xa = x
        else:
            xb = x
        if d != 0.0 and fabs(4.0 * v) < fabs(dxold * d):
            step = v / d
            xn = x - step
            if xa < xn < xb:
                dxold = dx
                dx = step
                tol = tolnewton
            else:
                dxold = dx
                dx = 0.5 * (xb - xa)
                xn = _midpoint(xa, xb, dx)
                tol = EPS
        else:
            dxold = dx
            dx = 0.5 * (xb - xa)
            xn = _midpoint(xa, xb, dx)
            tol = EPS
        if not (xa < xn < xb):
            return x
        if fabs(dx) <= tol * fabs(xn):
            return xn
        x = xn
    return x


def _halley_step(v: float, d: float, h: float) -> tuple[float, bool]:
    """The step from p(x) = v, p'(x) = d (nonzero), p''(x)/2 = h: Halley's
    v d / (d^2 - v h) when d^2 - v h > d^2 / 2 (at most twice the Newton step,
    same direction; false for an overflow or NaN) and both v d and d^2 are at
    least HALLEY_MIN (no precision lost to underflow), else Newton's v / d;
    and whether it is Halley's."""
    dd = d * d
    vd = v * d
    den = dd - v * h
    if den > 0.5 * dd and _fabs(vd) >= HALLEY_MIN and dd >= HALLEY_MIN:
        return vd / den, True
    return v / d, False


_HALLEY_BODY = """
    xa = lo
    xb = hi
    x = x0
    dx = xb - xa
    dxold = dx
    neg = slo < 0
    for _ in range(MAXIT):
{eval}
        if v == 0.0:
            return x
        if (v < 0.0) == neg:
            xa = x
        else:
            xb = x
        if d != 0.0 and fabs(4.0 * v) < fabs(dxold * d):
            dd = d * d
            vd = v * d
            den = dd - v * h
            if den > 0.5 * dd and fabs(vd) >= HALLEY_MIN and dd >= HALLEY_MIN:
                step = vd / den
                tol = HALLEY_TOL
            else:
                step = v / d
                tol = HANDOFF_TOL
            xn = x - step
            if xa < xn < xb:
                dxold = dx
                dx = step
            else:
                dxold = dx
                dx = 0.5 * (xb - xa)
                xn = midpoint(xa, xb, dx)
                tol = EPS
        else:
            dxold = dx
            dx = 0.5 * (xb - xa)
            xn = midpoint(xa, xb, dx)
            tol = EPS
        if not (xa < xn < xb):
            return x
        if fabs(dx) <= tol * fabs(xn):
            return xn
        x = xn
    return x
"""


def _unrolled_halley(n: int):
    """Bernstein's single simple root in (lo, hi) for degree n as
    straight-line code: (a, lo, hi, slo, x0) -> x.  _newton with the step of
    _halley_step (h = p''/2), p, p' and p''/2 by Estrin's scheme (step 7.3:
    the coefficients of p' and p''/2 once, the powers x, x^2, x^4, ... once
    per evaluation); an accepted Halley step of at most HALLEY_TOL |x| ends
    it, a Newton step of at most HANDOFF_TOL |x|."""
    levels = n.bit_length()           # n >= 3: at least two
    pre = [f"    {', '.join(f'a{i}' for i in range(n + 1))}, = a"]
    pre += [f"    da{i} = {float(i + 1)!r} * a{i + 1}" for i in range(n)]
    pre += [f"    ha{i} = {float((i + 1) * (i + 2) // 2)!r} * a{i + 2}" for i in range(n - 1)]
    ev = ["    p0 = x"] + [f"    p{k} = p{k - 1} * p{k - 1}" for k in range(1, levels)]
    ev += _estrin_lines("a", n, "v") + _estrin_lines("da", n - 1, "d") + _estrin_lines("ha", n - 2, "h")
    src = ("def halley(a, lo, hi, slo, x0):\n" + "\n".join(pre)
           + _HALLEY_BODY.format(eval="\n".join("    " + line for line in ev)))
    env = {"fabs": _fabs, "midpoint": _midpoint, "MAXIT": MAXIT, "HALLEY_MIN": HALLEY_MIN,
           "HALLEY_TOL": HALLEY_TOL, "HANDOFF_TOL": HANDOFF_TOL, "EPS": EPS}
    exec(src, env)
    return env["halley"]




def _quadratic(a: float, b: float, c: float) -> list[float]:
    """Real roots of a x^2 + b x + c (a != 0), ascending; a double root once.

    The plain discriminant b*b - 4ac is used when it cannot cancel
    (4ac <= b*b/2) and a clearly negative one means no real root; only in
    between is it computed from error-free products."""
    p = b * b
    q = (4.0 * a) * c
    d = p - q
    if q <= 0.5 * p:
        if d == 0.0:                   # b == 0 and ac == 0
            return [-b / (2.0 * a)]
    elif d < -EPS * (p + q):
        return []
    else:
        p, pe = _two_prod(b, b)
        a4 = 4.0 * a
        q, qe = _two_prod(a4, c)
        d = (p - q) + (pe - qe)
        bound = EPS * EPS * (p + _fabs(q))
        if d < -bound:
            return []
        if d <= bound:
            return [-b / (2.0 * a)]
    s = _sqrt(d)
    if b < 0.0:
        s = -s
    q = -0.5 * (b + s)
    r1 = q / a
    r2 = c / q
    if r1 <= r2:
        return [r1, r2]
    return [r2, r1]


def _quadratic_scaled(a: float, b: float, c: float) -> list[float]:
    """_quadratic in x = 2^s u (step 7.4): s balances a 2^(2s) against c (or
    against b 2^s when c = 0), a common power of two puts the largest
    coefficient in [1, 2), and the roots u come back as ldexp(u, s).  The
    same bits as _quadratic where its products stay normal; where they
    underflow (roots far from 1 with tiny coefficients) the roots are kept."""
    ea = _frexp(a)[1]
    eb = _frexp(b)[1] if b != 0.0 else 0
    ec = _frexp(c)[1] if c != 0.0 else 0
    if c != 0.0:
        s = (ec - ea) // 2
    elif b != 0.0:
        s = eb - ea
    else:
        s = 0
    m = ea + 2 * s
    if b != 0.0:
        m = max(m, eb + s)
    if c != 0.0:
        m = max(m, ec)
    k = 1 - m
    out = []
    for u in _quadratic(_ldexp(a, 2 * s + k), _ldexp(b, s + k), _ldexp(c, k)):
        try:
            out.append(_ldexp(u, s))
        except OverflowError:         # C's ldexp: +-infinity
            out.append(math.copysign(math.inf, u))
    return out


def _roots_between(a: list[float], n: int, crit: list[float], lo: float, hi: float) -> list[float]:
    """All roots of p (degree n >= 2) in the open interval (lo, hi), ascending,
    given the ascending roots `crit` of p' in (lo, hi).  Plain signs."""
    out: list[float] = []
    xl = lo
    sl = _sign_plain(a, n, lo)
    m = len(crit)
    for i in range(m + 1):
        if i < m:
            xr = crit[i]
            sr = _sign_plain(a, n, xr)
        else:
            xr = hi
            sr = _sign_plain(a, n, hi)
        if sl == 0 and i > 0:
            out.append(xl)
        elif sl * sr < 0:
            out.append(_newton(a, n, xl, xr, sl, 0.5 * (xl + xr)))
        xl = xr
        sl = sr
    return out


def _scale(c: list[float], n: int, m: float) -> list[float]:
    """Coefficients times an exact power of two so that m = max |c_i| is in [1, 2)."""
    e = math.frexp(m)[1]
    k = 1 - e
    a = list(c[: n + 1])
    if k > 1000:
        f = math.ldexp(1.0, 600)
        a = [v * f for v in a]
        k -= 600
    f = math.ldexp(1.0, k)
    return [v * f for v in a]


# i! for 0 <= i <= 16 (exact)
_FACT = [float(math.factorial(i)) for i in range(MAX_DEGREE + 1)]
BERN_DEPTH = 12           # Bernstein subdivision depth limit


def _unrolled_bernstein(n: int):
    """Step 7.2 for degree n as straight-line code: (a, lo, w) -> n! times
    the Bernstein coefficients of p on [lo, lo + w] and their error bound e.
    The same operations in the same order as the loops of docs/roots.md
    (Taylor shift when lo != 0, powers of w times j! (n-j)!, summation
    triangle, ptilde(|lo| + w)); CPython runs the unrolled statements on
    local variables several times faster than the index loops."""
    b = [f"b{i}" for i in range(n + 1)]
    lines = [f"def bern(a, lo, w):", f"    {', '.join(b)}, = a", "    if lo != 0.0:"]
    for i in range(n):
        for j in range(n - 1, i - 1, -1):
            lines.append(f"        {b[j]} = {b[j]} + lo * {b[j + 1]}")
    lines.append("    f = 1.0")
    for j in range(n + 1):
        lines.append(f"    {b[j]} = {b[j]} * f * {_FACT[j] * _FACT[n - j]!r}")
        lines.append("    f = f * w")
    for k in range(1, n + 1):
        for j in range(n, k - 1, -1):
            lines.append(f"    {b[j]} = {b[j]} + {b[j - 1]}")
    lines.append("    y = fabs(lo) + w")
    lines.append(f"    pt = fabs(a[{n}])")
    for i in range(n - 1, -1, -1):
        lines.append(f"    pt = pt * y + fabs(a[{i}])")
    lines.append(f"    return [{', '.join(b)}], {8.0 * (n + 1)!r} * EPS * pt * {_FACT[n]!r} + TINY")
    env = {"fabs": _fabs, "EPS": EPS, "TINY": TINY}
    exec("\n".join(lines), env)
    return env["bern"]


def _unrolled_split(n: int):
    """de Casteljau at 1/2 (step 7.3) for degree n as straight-line code:
    b -> (left half, right half), the same operations as the loops."""
    c = [f"c{i}" for i in range(n + 1)]
    left = ["l0"]
    right = [""] * (n + 1)
    right[n] = c[n]
    lines = [f"def split(b):", f"    {', '.join(c)}, = b", "    l0 = c0"]
    for k in range(1, n + 1):
        for i in range(n - k + 1):
            lines.append(f"    {c[i]} = 0.5 * ({c[i]} + {c[i + 1]})")
        lines.append(f"    l{k} = c0")
        left.append(f"l{k}")
        if n - k > 0:
            lines.append(f"    r{n - k} = {c[n - k]}")
            right[n - k] = f"r{n - k}"
        else:
            right[0] = f"l{n}"
    lines.append(f"    return [{', '.join(left)}], [{', '.join(right)}]")
    env: dict = {}
    exec("\n".join(lines), env)
    return env["split"]


def _unrolled_horner(n: int):
    """Horner for p(x), p'(x) and p''(x)/2 with Higham's running bound mu for
    degree n as straight-line code: (a, x) -> (v, d, h, mu), the same
    operations as the loop of _polish_halley in the other runtimes."""
    lines = [f"def horner(a, x):", f"    {', '.join(f'a{i}' for i in range(n + 1))}, = a",
             f"    v = a{n}", "    d = 0.0", "    h = 0.0", "    ax = fabs(x)", "    mu = 0.5 * fabs(v)"]
    for i in range(n - 1, -1, -1):
        lines += ["    h = h * x + d", "    d = d * x + v", f"    v = v * x + a{i}", "    mu = mu * ax + fabs(v)"]
    lines.append("    return v, d, h, mu")
    env = {"fabs": _fabs}
    exec("\n".join(lines), env)
    return env["horner"]


def _estrin_lines(c: str, m: int, out: str) -> list[str]:
    """Straight-line Estrin's scheme for the locals c0..cm at x into `out`
    (step 7.3): pairs q_i = q_2i + q_2i+1 * p with p = x, x^2, x^4, ... (the
    locals p0, p1, p2, ...), an odd last entry carried up unchanged, until
    one value is left."""
    q = [f"{c}{i}" for i in range(m + 1)]
    lines = []
    level = 0
    while len(q) > 1:
        nq = []
        for i in range(0, len(q), 2):
            if i + 1 < len(q):
                name = f"{c}_{level}_{i // 2}"
                lines.append(f"    {name} = {q[i]} + {q[i + 1]} * p{level}")
                nq.append(name)
            else:
                nq.append(q[i])
        q = nq
        level += 1
    lines.append(f"    {out} = {q[0]}")
    return lines


_HALLEY = [None] * 3 + [_unrolled_halley(n) for n in range(3, MAX_DEGREE + 1)]
_HORNER2_MU = [None] * 3 + [_unrolled_horner(n) for n in range(3, MAX_DEGREE + 1)]
_BERN = [None] * 3 + [_unrolled_bernstein(n) for n in range(3, MAX_DEGREE + 1)]
_SPLIT = [None] * 3 + [_unrolled_split(n) for n in range(3, MAX_DEGREE + 1)]


def _by_derivatives(a: list[float], n: int, lo: float, hi: float) -> float | None:
    """The derivative method on [lo, hi] (answers in (lo, hi]): roots of the
    derivatives bottom up, then the first root of p with careful signs."""
    ders = [a]
    for k in range(1, n - 1):
        prev = ders[k - 1]
        ders.append([prev[i + 1] * (i + 1) for i in range(n - k + 1)])
    d2 = ders[n - 2]
    crit = [x for x in _quadratic_scaled(d2[2], d2[1], d2[0]) if lo < x < hi]
    for k in range(n - 3, 0, -1):
        crit = _roots_between(ders[k], n - k, crit, lo, hi)
    xl = lo
    sl = _sign_top(a, n, lo)
    m = len(crit)
    for i in range(m + 1):
        if sl == 0 and i > 0:
            return xl
        if i < m:
            xr = crit[i]
        else:
            xr = hi
        sr = _sign_top(a, n, xr)
        if sl * sr < 0:
            x = _newton(a, n, xl, xr, sl, 0.5 * (xl + xr))
            x = _polish(a, n, x, xl, xr)   # the monotone piece bounds the polish
            if not (x > xl):
                x = xr
            if x > xr:
                x = xr
            return x
        xl = xr
        sl = sr
    if sl == 0:
        return hi
    return None


def _general(a: list[float], n: int, lo: float, hi: float) -> float | None:
    fabs = _fabs
    # 1. clip to the root bound (r >= 2: nothing to clip in [-2, 2])
    if not (-2.0 <= lo and hi <= 2.0):
        mx = 0.0
        for i in range(n):
            v = fabs(a[i])
            if v > mx:
                mx = v
        mx = mx / fabs(a[n])        # = max |a_i|/|a_n| (rounding is monotone)
        r = 2.0 * (1.0 + mx)
        cap = math.ldexp(1.0, 900 // n)
        if r > cap:
            r = cap
        if lo < -r:
            lo = -r
        if hi > r:
            hi = r
        if not (lo < hi):
            return None
    # 2. n! times the Bernstein coefficients of p on [lo, hi], error bound e
    b, e = _BERN[n](a, lo, hi - lo)
    # 3. subdivision, left to right
    stack = []
    depth = 0
    xl = lo
    xr = hi
    nf = float(n)
    while True:
        # sign variations, or -1 when a coefficient is within e of zero
        b0 = b[0]
        m = fabs(b0)
        unsure = m <= e
        v = 0
        neg = b0 < 0.0
        for bi in b[1:]:
            ab = fabs(bi)
            if ab > m:
                m = ab
            if ab <= e:
                unsure = True
            if (bi < 0.0) != neg:
                v += 1
                neg = not neg
        if unsure:
            v = -1
        if v == 1:
            # one simple root in (xl, xr): start where the control polygon crosses
            i = 0
            while (b[i + 1] < 0.0) == (b[i] < 0.0):
                i += 1
            x0 = xl + ((xr - xl) / nf) * (i + b[i] / (b[i] - b[i + 1]))
            if not (xl < x0 < xr):
                x0 = 0.5 * (xl + xr)
            x = _HALLEY[n](a, xl, xr, -1 if b0 < 0.0 else 1, x0)
            x = _polish_halley(a, n, x, xl, xr)
            if not (x > xl):
                x = xr
            if x > xr:
                x = xr
            return x
        if v != 0:
            if depth == BERN_DEPTH or (v < 0 and (fabs(b0) <= e or fabs(b[n]) <= e)):
                t = _by_derivatives(a, n, xl, xr)
                if t is not None:
                    return t
            else:
                # de Casteljau at 1/2: left half in b, right half pushed
                b, rb = _SPLIT[n](b)
                xm = 0.5 * (xl + xr)
                e = e + nf * EPS * m
                depth += 1
                stack.append((rb, e, xm, xr, depth))
                xr = xm
                continue
        # no root in (xl, xr]: the next pending interval
        if not stack:
            return None
        b, e, xl, xr, depth = stack.pop()


def _polish(a: list[float], n: int, x: float, xa: float, xb: float) -> float:
    """A last Newton step: plain when the running error bound of Horner at x
    is within a few ulps of x, else up to two steps with a compensated p(x)."""
    fabs = _fabs
    for _ in range(2):
        ax = fabs(x)
        v = a[n]
        d = 0.0
        mu = 0.5 * fabs(v)
        for i in range(n - 1, -1, -1):
            d = d * x + v
            v = v * x + a[i]
            mu = mu * ax + fabs(v)
        if d == 0.0:
            return x
        # running error bound of Horner (Higham, Alg. 5.1): |v - p(x)| <= eps (mu - |v|/2)
        if mu <= 2.0 * fabs(x * d):
            xn = x - v / d
            if xa < xn <= xb:
                return xn
            return x
        vc = _comp_horner(a, n, x)
        if vc == 0.0:
            return x
        xn = x - vc / d
        if not (xa < xn <= xb) or xn == x:
            return x
        x = xn
    return x


def _polish_halley(a: list[float], n: int, x: float, xa: float, xb: float) -> float:
    """The polish after Bernstein's Halley iteration: the step of _halley_step
    from p(x) (plain Horner where its running error bound allows, else
    compensated), p'(x) and p''(x)/2, kept only inside (xa, xb]; a Halley step
    of at most POLISH_TOL |x| (a Newton step: NEWTON_TOL) ends it, else
    another round, at most three."""
    fabs = _fabs
    horner = _HORNER2_MU[n]
    for _ in range(3):
        v, d, h, mu = horner(a, x)
        if d == 0.0:
            return x
        if mu > 2.0 * fabs(x * d):   # plain Horner not accurate enough: compensated
            v = _comp_horner(a, n, x)
        step, halley = _halley_step(v, d, h)
        xn = x - step
        if not (xa < xn <= xb):
            return x
        if fabs(step) <= (POLISH_TOL if halley else NEWTON_TOL) * fabs(xn):
            return xn
        x = xn
    return x


def _moderate(v: float) -> bool:
    """v is zero or 2^-200 <= |v| < 2^200 (false for NaN and infinities)."""
    v = _fabs(v)
    return v == 0.0 or MODERATE_LO <= v < MODERATE_HI


def _quadratic_in(a: float, b: float, c: float, lo: float, hi: float) -> float | None:
    """First root of a x^2 + b x + c in (lo, hi] (a != 0)."""
    for t in _quadratic(a, b, c):
        if lo < t <= hi:
            return t
    return None


def _exponent(x: float) -> int:
    """Binary exponent e of a finite nonzero x = f 2^e, 0.5 <= |f| < 1."""
    return math.frexp(x)[1]


def _ceil_div(a: int, k: int) -> int:
    """ceil(a / k) for k > 0 (written with nonnegative operands only)."""
    if a >= 0:
        return (a + k - 1) // k
    return -((-a) // k)


def _root_exponents(c: list[float], n: int, j: int) -> tuple[int, int]:
    """(u, l): every root t of p has |t| < 2^u, every nonzero root |t| > 2^l.
    Fujiwara's bound 2 max |c_i/c_n|^(1/(n-i)) on p and on its reverse, in
    exponents (|c_i| < 2^e_i, |c_n| >= 2^(e_n - 1)); j < n is the lowest
    index with c[j] != 0."""
    en = _exponent(c[n])
    ej = _exponent(c[j])
    u = -(1 << 30)
    lx = -(1 << 30)
    for i in range(j, n):
        if c[i] != 0.0:
            v = _ceil_div(_exponent(c[i]) - en + 1, n - i)
            if v > u:
                u = v
    for i in range(j + 1, n + 1):
        if c[i] != 0.0:
            v = _ceil_div(_exponent(c[i]) - ej + 1, i - j)
            if v > lx:
                lx = v
    return u + 1, -(lx + 1)


def _band(c: list[float], n: int, s: int, xl: float, xr: float) -> float | None:
    """Smallest root in (xl, xr] with 2^(s - BAND_SPAN//n) <= |x| <= 2^s
    there: solved in u = t 2^-s, coefficients c_i 2^(s i) scaled together
    so that the largest lies in [1, 2) (those far below underflow: their
    terms are negligible in the band)."""
    m = -(1 << 30)
    for i in range(n + 1):
        if c[i] != 0.0:
            f = _exponent(c[i]) + s * i
            if f > m:
                m = f
    a = [_ldexp(c[i], s * i + 1 - m) for i in range(n + 1)]
    while n >= 0 and a[n] == 0.0:
        n -= 1
    if n <= 0:
        return None
    a = a[:n + 1]                     # the general method reads every entry
    ul = _ldexp(xl, -s)
    ur = _ldexp(xr, -s)
    if n == 1:
        u = -a[0] / a[1]
        if not (ul < u <= ur):
            return None
    elif n == 2:
        u = _quadratic_in(a[2], a[1], a[0], ul, ur)
    else:
        u = _general(a, n, ul, ur)
    if u is None:
        return None
    t = _ldexp(u, s)
    if xl < t <= xr:
        return t
    return None


def _edge(e: int) -> float:
    """2^e, or infinity beyond the largest double (a band edge)."""
    if e > 1023:
        return math.inf
    return _ldexp(1.0, e)


def _banded(c: list[float], n: int, j: int, ue: int, le: int, lo: float, hi: float) -> float | None:
    """Roots spread too widely for one scale: the magnitudes 2^le .. 2^ue
    are cut into bands of width 2^w (w = BAND_SPAN // n), each solved with
    its own power-of-two scale of t, in the order of t: negative bands from
    the most negative, the root 0 (when c_0 = 0), positive bands."""
    w = BAND_SPAN // n
    nb = _ceil_div(ue - le, w)
    for k in range(nb - 1, -1, -1):
        s = le + (k + 1) * w
        xl = -_edge(s)
        xr = -_edge(s - w)
        if lo > xl:
            xl = lo
        if hi < xr:
            xr = hi
        if xl < xr:
            t = _band(c, n, s, xl, xr)
            if t is not None:
                return t
    if j > 0 and lo < 0.0 <= hi:
        return 0.0
    for k in range(nb):
        s = le + (k + 1) * w
        xl = _edge(s - w)
        xr = _edge(s)
        if lo > xl:
            xl = lo
        if hi < xr:
            xr = hi
        if xl < xr:
            t = _band(c, n, s, xl, xr)
            if t is not None:
                return t
    return None


def _solve(c: list[float], n: int, lo: float, hi: float) -> float | None:
    """Degree n >= 2 (c[n] != 0, all finite, lo < hi finite): one power-of-two
    scale of the coefficients when the roots allow it, else bands."""
    ac = list(map(_fabs, c))
    mx = max(ac)
    if 0.0 in ac:
        nz = [v for v in ac if v != 0.0]
        mn = min(nz)
        j = 0
        while ac[j] == 0.0:
            j += 1
    else:
        mn = min(ac)
        j = 0
    spread = _frexp(mx)[1] - _frexp(mn)[1]
    if n == 2:
        one_scale = spread <= QUAD_SPREAD
        if not one_scale:
            ue, le = _root_exponents(c, n, j)
    else:
        lim = ONE_SCALE_SPAN // n
        one_scale = spread <= lim - 2
        if not one_scale:
            ue, le = _root_exponents(c, n, j)
            one_scale = ue <= lim and le >= -lim
    if one_scale:
        a = _scale(c, n, mx)
        while n >= 0 and a[n] == 0.0:     # underflowed to zero in the scaling
            n -= 1
        if n <= 0:
            return None
        a = a[:n + 1]                     # the general method reads every entry
        if n == 1:
            t = -a[0] / a[1]
            return t if lo < t <= hi else None
        if n == 2:
            return _quadratic_in(a[2], a[1], a[0], lo, hi)
        return _general(a, n, lo, hi)
    return _banded(c, n, j, ue, le, lo, hi)


def _one_scale_lines(n: int) -> list[str]:
    """Steps 2-5 for degree n (3 <= n) as straight-line code on the locals c0..cn,
    for the common case: the top coefficient nonzero, every coefficient finite,
    one scale chosen by the spread (step 4) and a factor 2^(1-e) that is
    representable (max |c_i| >= 2^-1000).  Its lines return the general
    method's answer on the scaled coefficients a0..an; any other input falls
    through to the lines that follow them.  Why it is exactly step 4's choice:
    with M = max |c_i| = 2^e f and a_i = c_i 2^(1-e) (exact: |a_i| < 2, and a
    nonzero a_i that underflows fails the test below, as it must), frexp's
    exponent of c_i is e(c_i) = e(a_i) + e - 1, so spread <= lim - 2
    (lim = 800 // n) holds iff every nonzero |a_i| >= 2^(2 - lim).  A NaN
    fails that test (or makes M NaN) and an infinity makes M infinite; zeros
    are read on c_i, since a tiny c_i can underflow to zero when scaled down."""
    tl = _ldexp(1.0, 2 - ONE_SCALE_SPAN // n)
    lines = [f"    if c{n} != 0.0:", "        mx = c0", "        mn = c0"]
    for i in range(1, n + 1):
        lines += [f"        if c{i} > mx:", f"            mx = c{i}",
                  f"        elif c{i} < mn:", f"            mn = c{i}"]
    lines += ["        if mx < -mn:", "            mx = -mn",
              "        if SCALE_MIN <= mx < INF:",
              "            f = POW2[frexp(mx)[1]]"]
    lines += [f"            a{i} = c{i} * f" for i in range(n + 1)]
    tests = " and ".join(f"(a{i} >= {tl!r} or a{i} <= {-tl!r} or c{i} == 0.0)" for i in range(n + 1))
    lines += [f"            if {tests}:",
              f"                return general([{', '.join(f'a{i}' for i in range(n + 1))}], {n}, lo, hi)"]
    return lines


def _unrolled_entry(n: int):
    """(c, lo, hi) -> steps 2-7 for a list c of n + 1 finite-or-not floats,
    lo < hi finite: the one-scale case of _one_scale_lines, else _stripped."""
    src = ("def entry(c, lo, hi):\n"
           f"    {', '.join(f'c{i}' for i in range(n + 1))}, = c\n"
           + "\n".join(_one_scale_lines(n))
           + f"\n    return stripped(c, {n}, lo, hi)\n")
    env = {"SCALE_MIN": _ldexp(1.0, -1000), "INF": math.inf, "POW2": _POW2, "frexp": _frexp,
           "general": _general, "stripped": _stripped}
    exec(src, env)
    return env["entry"]


# 2^(1-e) for the exponents e = frexp(M)[1] of step 5's single factor (e >= -999),
# indexed by e (negative e from the end: the list has 2048 entries)
_POW2 = [0.0] * 2048
for _e in range(-999, 1025):
    _POW2[_e] = _ldexp(1.0, 1 - _e)
del _e


def _stripped(c: list[float], n: int, lo: float, hi: float) -> float | None:
    """Steps 2-8 for the list c of n + 1 floats (lo < hi finite): None for a
    NaN or an infinity, the top zeros stripped, then degree 1, or _solve."""
    if not all(map(_isfinite, c)):
        return None
    while n >= 0 and c[n] == 0.0:
        n -= 1
    if n <= 0:
        return None
    if n == 1:
        return -c[0] / c[1]
    return _solve(c, n, lo, hi)


def smallest_root(coeffs, lo: float, hi: float) -> float | None:
    """Smallest real root t of sum(coeffs[i] * t**i) with lo < t <= hi, or None.

    Coefficients ascending, degree 0..16 (see docs/roots.md for the contract)."""
    lo = float(lo)
    hi = float(hi)
    c = [*map(float, coeffs)]
    n = len(c) - 1
    if n > MAX_DEGREE:
        raise ValueError(f"degree {n} exceeds {MAX_DEGREE}")
    if not (-_INF < lo < hi < _INF):      # both finite and lo < hi (false for a NaN)
        return None
    if n >= 3:
        # degrees 3, 4 with lo >= 0: most windows without a root answer none here
        # (docs/roots.md step 1, "lo >= 0" (c)); n < 5 first: degrees 6, 8 pay one test
        if n < 5 and lo >= 0.0 and hi >= _HI_MIN and (
                _no_root3(c[0], c[1], c[2], c[3], hi) if n == 3 else _no_root4(c[0], c[1], c[2], c[3], c[4], hi)):
            return None
        t = _ENTRY[n](c, lo, hi)
    elif n == 2 and c[2] != 0.0 and _moderate(c[0]) and _moderate(c[1]) and _moderate(c[2]):
        # fast path: the same bits as scaling first (no intermediate leaves the normal range)
        t = _quadratic_in(c[2], c[1], c[0], lo, hi)
        return None if t is None else t + 0.0
    else:
        t = _stripped(c, n, lo, hi)
    if t is None or not (lo < t <= hi):
        return None
    return t + 0.0


def _no_root3(t0, c1, c2, c3, hi):
    """True when the cubic's Bernstein coefficients on [0, hi] all have one
    sign beyond their rounding (docs/roots.md step 1, "lo >= 0" (c)): no root
    in [0, hi]. False says nothing; inf or NaN never answers (m = inf or a
    comparison with NaN is false)."""
    h2 = hi * hi
    t1 = c1 * hi
    t2 = c2 * h2
    t3 = c3 * (h2 * hi)
    b3 = (t0 + t1) + (t2 + t3)
    if (t0 < 0.0) != (b3 < 0.0):          # p(0), p(hi) of opposite signs: the usual root
        return False
    m = _NONE_REL * ((abs(t0) + abs(t1)) + (abs(t2) + abs(t3))) + _NONE_ABS
    b1 = t0 + t1 * _THIRD
    b2 = (t0 + t1 * _TWO_THIRDS) + t2 * _THIRD
    if t0 > m:
        return b1 > m and b2 > m and b3 > m
    return t0 < -m and b1 < -m and b2 < -m and b3 < -m


def _no_root4(t0, c1, c2, c3, c4, hi):
    """The quartic's counterpart of _no_root3 (the same reasoning)."""
    h2 = hi * hi
    t1 = c1 * hi
    t2 = c2 * h2
    t3 = c3 * (h2 * hi)
    t4 = c4 * (h2 * h2)
    b4 = ((t0 + t1) + (t2 + t3)) + t4
    if (t0 < 0.0) != (b4 < 0.0):
        return False
    m = _NONE_REL * (((abs(t0) + abs(t1)) + (abs(t2) + abs(t3))) + abs(t4)) + _NONE_ABS
    b1 = t0 + t1 * 0.25
    b2 = (t0 + t1 * 0.5) + t2 * _SIXTH
    b3 = (t0 + t1 * 0.75) + (t2 * 0.5 + t3 * 0.25)
    if t0 > m:
        return b1 > m and b2 > m and b3 > m and b4 > m
    return t0 < -m and b1 < -m and b2 < -m and b3 < -m and b4 < -m


_NONE_REL = 2.0 ** -46   # 16x the coefficients' rounding bound 2^-50 * sum |t_i|
_NONE_ABS = 2.0 ** -900  # keeps m > 0 when every t_i is zero or subnormal
_HI_MIN = 2.0 ** -250    # below it hi^2..hi^4 may underflow and lose a huge c_i * hi^i
_THIRD = 1.0 / 3.0
_TWO_THIRDS = 2.0 / 3.0
_SIXTH = 1.0 / 6.0
_INF = math.inf
_ENTRY = [None] * 3 + [_unrolled_entry(n) for n in range(3, MAX_DEGREE + 1)]
