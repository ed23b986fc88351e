"""Reference contact times of the exact motion (real sin and cos), from the
paper's letters alone: independent of Maxima, of the .mxm files and of the
generated code.  mpmath at 40 digits.

The gap G(t) (zero at contact), G'(t) and a bound B2 >= |G''| on [0, T] are
written out by hand from the motion

    circle-circle: x1 = a + b t + c t^2/2 + d sin(e t + f), y1 = m + n t + o t^2/2 + d sin(p t + q),
                   circle 2 with g h i j k l and r s u j v w, radii x and z;
                   G = (x1 - x2)^2 + (y1 - y2)^2 - (x + z)^2
    point-line:    G = (a + b t + c t^2/2 + d sin(e t + f)) - (g + h t + i t^2/2 + j sin(k t + l))

Root isolation is certified by a Taylor bound: on [m - r, m + r],
|G(t) - G(m)| <= r |G'(m)| + B2 r^2 / 2, so |G(m)| above that plus the band
excludes the interval, and |G'(m)| > B2 r makes G monotone there.

The band: a double evaluation of G has an error of about eps * S(t), S the
sum of the magnitudes of G's terms (|sin| counted as 1 + |its argument|, as
the runtimes' rounding scale does).  Where |G| <= BAND_K eps S the sign of G
is not decided by double arithmetic, so any answer inside such a stretch (a
"zone") is accepted, and a contact whose zone does not change sign (a touch
within the band) may be reported or not.  BAND_K = 256 is four times the
runtimes' floor (docs/exact-motion.md).
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath

mp = mpmath.mp
EPS = 2.0 ** -52
BAND_K = 256
REL = 1e-12            # relative tolerance on every accepted interval
DPS = 40


def _f(params: dict, keys: str):
    return [mpmath.mpf(params[k]) for k in keys]


@dataclass
class Motion1:
    """One coordinate: p0 + v t + acc t^2/2 + rad sin(w t + ph)."""
    p0: object
    v: object
    acc: object
    rad: object
    w: object
    ph: object

    def at(self, t):
        return self.p0 + self.v * t + self.acc * t * t / 2 + self.rad * mpmath.sin(self.w * t + self.ph)

    def d1(self, t):
        return self.v + self.acc * t + self.rad * self.w * mpmath.cos(self.w * t + self.ph)

    def d2(self, t):
        return self.acc - self.rad * self.w ** 2 * mpmath.sin(self.w * t + self.ph)

    def scale(self, t):
        t = abs(t)
        return (abs(self.p0) + abs(self.v) * t + abs(self.acc) * t * t / 2
                + abs(self.rad) * (1 + abs(self.w) * t + abs(self.ph)))


def _tight(a: Motion1, b: Motion1, t):
    """The error scale of a - b evaluated with differences formed first."""
    t = abs(t)
    return (abs(a.p0 - b.p0) + abs(a.v - b.v) * t + abs(a.acc - b.acc) * t * t / 2
            + abs(a.rad) * (1 + abs(a.w) * t + abs(a.ph)) + abs(b.rad) * (1 + abs(b.w) * t + abs(b.ph)))


def _diff_bounds(a: Motion1, b: Motion1, T):
    """Bounds on |a - b|, |(a - b)'|, |(a - b)''| over [0, T]."""
    dv, dc = abs(a.v - b.v), abs(a.acc - b.acc)
    m0 = abs(a.p0 - b.p0) + dv * T + dc * T * T / 2 + abs(a.rad) + abs(b.rad)
    m1 = dv + dc * T + abs(a.rad * a.w) + abs(b.rad * b.w)
    m2 = dc + abs(a.rad) * a.w ** 2 + abs(b.rad) * b.w ** 2
    return m0, m1, m2


class Gap:
    """G, G', a bound on |G''| over [0, T] and the rounding scale S."""

    def __init__(self, equation: str, params: dict, T: float):
        with mpmath.workdps(DPS):
            self.equation = equation
            self.T = mpmath.mpf(T)
            if equation == "circle-circle":
                a, b, c, d, e, f, m, n, o, p, q = _f(params, "abcdefmnopq")
                g, h, i, j, k, l, r, s, u, v, w, x, z = _f(params, "ghijklrsuvwxz")
                self.x1, self.y1 = Motion1(a, b, c, d, e, f), Motion1(m, n, o, d, p, q)
                self.x2, self.y2 = Motion1(g, h, i, j, k, l), Motion1(r, s, u, j, v, w)
                self.R = x + z
                self.Rs = abs(x) + abs(z)
                X0, X1, X2 = _diff_bounds(self.x1, self.x2, self.T)
                Y0, Y1, Y2 = _diff_bounds(self.y1, self.y2, self.T)
                self.B2 = 2 * (X1 * X1 + X0 * X2 + Y1 * Y1 + Y0 * Y2)
            elif equation == "point-line":
                a, b, c, d, e, f, g, h, i, j, k, l = _f(params, "abcdefghijkl")
                self.x1, self.x2 = Motion1(a, b, c, d, e, f), Motion1(g, h, i, j, k, l)
                self.B2 = _diff_bounds(self.x1, self.x2, self.T)[2]
            else:
                raise ValueError(f"unknown equation {equation!r}")

    def G(self, t):
        if self.equation == "point-line":
            return self.x1.at(t) - self.x2.at(t)
        dx = self.x1.at(t) - self.x2.at(t)
        dy = self.y1.at(t) - self.y2.at(t)
        return dx * dx + dy * dy - self.R * self.R

    def G1(self, t):
        if self.equation == "point-line":
            return self.x1.d1(t) - self.x2.d1(t)
        dx = self.x1.at(t) - self.x2.at(t)
        dy = self.y1.at(t) - self.y2.at(t)
        return 2 * (dx * (self.x1.d1(t) - self.x2.d1(t)) + dy * (self.y1.d1(t) - self.y2.d1(t)))

    def G2(self, t):
        if self.equation == "point-line":
            return self.x1.d2(t) - self.x2.d2(t)
        dx = self.x1.at(t) - self.x2.at(t)
        dy = self.y1.at(t) - self.y2.at(t)
        ex = self.x1.d1(t) - self.x2.d1(t)
        ey = self.y1.d1(t) - self.y2.d1(t)
        return 2 * (ex * ex + dx * (self.x1.d2(t) - self.x2.d2(t)) + ey * ey + dy * (self.y1.d2(t) - self.y2.d2(t)))

    def S(self, t):
        if self.equation == "point-line":
            return self.x1.scale(t) + self.x2.scale(t)
        sx = self.x1.scale(t) + self.x2.scale(t)
        sy = self.y1.scale(t) + self.y2.scale(t)
        return sx * sx + sy * sy + self.Rs * self.Rs

    def S_tight(self, t):
        """S for an evaluation that forms position differences first (as the
        generated gap does): decides which contacts are regular."""
        if self.equation == "point-line":
            return _tight(self.x1, self.x2, t)
        # first order: d(dx^2) = 2 |dx| d(dx), and the final sum
        sx, sy = _tight(self.x1, self.x2, t), _tight(self.y1, self.y2, t)
        dx, dy = self.x1.at(t) - self.x2.at(t), self.y1.at(t) - self.y2.at(t)
        return 2 * abs(dx) * sx + 2 * abs(dy) * sy + dx * dx + dy * dy + self.Rs * self.Rs

    def band(self, t):
        return BAND_K * EPS * self.S(t)


@dataclass
class Zone:
    """A stretch [lo, hi] where |G| <= band; `cross`: G has opposite signs
    just outside it (a contact); `root`: a root inside it, when found."""
    lo: float
    hi: float
    cross: bool
    root: object = None


def _solve_level(gp: Gap, level, lo, hi):
    """A t in [lo, hi] where G(t) = level, G - level changing sign (bisection)."""
    flo = gp.G(lo) - level
    for _ in range(200):
        mid = (lo + hi) / 2
        if mid == lo or mid == hi:
            break
        fm = gp.G(mid) - level
        if (fm < 0) == (flo < 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return (lo + hi) / 2


def _monotone_zone(gp: Gap, u, v, gu, gv, inc: bool, bd):
    """On [u, v] where G is monotone: the stretch where |G| <= bd, or None."""
    if inc:
        if gv < -bd or gu > bd:
            return None
        zl = u if gu >= -bd else _solve_level(gp, -bd, u, v)
        zh = v if gv <= bd else _solve_level(gp, bd, u, v)
    else:
        if gv > bd or gu < -bd:
            return None
        zl = u if gu <= bd else _solve_level(gp, bd, u, v)
        zh = v if gv >= -bd else _solve_level(gp, -bd, u, v)
    return zl, zh


def zones(gp: Gap, t0, T, max_zones: int = 64) -> list[Zone]:
    """The zones of |G| <= band in [t0, T], in order, up to and including
    the first crossing one."""
    with mpmath.workdps(DPS):
        t0, T = mpmath.mpf(t0), mpmath.mpf(T)
        pieces = []   # (lo, hi, root or None), left to right
        stack = [(t0, T)]
        tiny = max(T, mpmath.mpf(1)) * mpmath.mpf(10) ** -30
        limit = None  # once a root is found: the end of its zone so far
        steps = 0
        while stack:
            steps += 1
            if steps > 2_000_000:
                raise RuntimeError("reference: too many intervals")
            u, v = stack.pop()
            if limit is not None and u > limit + tiny:
                break
            m, r = (u + v) / 2, (v - u) / 2
            g, g1 = gp.G(m), gp.G1(m)
            bd = gp.band(v)
            reach = r * (abs(g1) + gp.B2 * r / 2)
            if abs(g) - reach > bd:
                continue
            if abs(g) + reach <= gp.band(u):     # all of [u, v] is within the band
                pieces.append((u, v, None))
                if limit is not None and u <= limit + tiny:
                    limit = max(limit, v)
                continue
            if abs(g1) > gp.B2 * r:
                gu, gv = gp.G(u), gp.G(v)
                z = _monotone_zone(gp, u, v, gu, gv, g1 > 0, bd)
                if z is not None:
                    root = _solve_level(gp, 0, u, v) if (gu < 0) != (gv < 0) else None
                    pieces.append((z[0], z[1], root))
                    if root is not None and limit is None:
                        limit = z[1]
                    elif limit is not None and z[0] <= limit + tiny:
                        limit = max(limit, z[1])
                continue
            if r < tiny:
                pieces.append((u, v, None))
                if limit is not None and u <= limit + tiny:
                    limit = max(limit, v)
                continue
            stack.append((m, v))
            stack.append((u, m))
        merged: list[list] = []
        for lo, hi, root in pieces:
            if merged and lo <= merged[-1][1] + tiny:
                merged[-1][1] = max(merged[-1][1], hi)
                merged[-1][2] = merged[-1][2] if merged[-1][2] is not None else root
            else:
                merged.append([lo, hi, root])
        out: list[Zone] = []
        for lo, hi, root in merged:
            sl = gp.G(lo) if lo > t0 else None
            sh = gp.G(hi) if hi < T else None
            if sl is not None and sh is not None:
                cross = (sl < 0) != (sh < 0)
                if cross and root is None:
                    root = _solve_level(gp, 0, lo, hi)
                if not cross:
                    root = None   # an even number of sign changes inside the band: a touch
            else:
                cross = root is not None
            out.append(Zone(lo, hi, cross, root))
            if cross or len(out) >= max_zones:
                break
        return out


@dataclass
class Reference:
    expect: float | str | None    # the first contact (None: none; "overlapped": inside each other at t = 0)
    accept: list                  # [lo, hi] intervals of acceptable answers
    none_ok: bool                 # "none" is acceptable
    regular: bool                 # the first contact is decided to REL / 4 by a double evaluation
                                  # that forms differences first: the answer must be within REL of it
    note: str
    overlapped_ok: bool = False   # the gap is negative at t = 0 but within the band: "overlapped" stands too


def reference(equation: str, params: dict, horizon: float) -> Reference:
    """The first contact of the exact motion in (0, horizon], with the rules
    at t = 0: a gap below minus the band (the bodies inside each other) is
    "overlapped", never a contact; a gap within the band at t = 0 that
    decreases is a contact at 0; one that does not is skipped (with its
    zone).  Later roots are approaching by construction (the gap comes down
    to zero from above)."""
    gp = Gap(equation, params, horizon)
    with mpmath.workdps(DPS):
        T = mpmath.mpf(horizon)
        g0 = gp.G(0)
        if g0 < -gp.band(0):
            return Reference("overlapped", [], False, False, "overlapping at t = 0")
        ref = _reference(gp, g0, T)
        ref.overlapped_ok = bool(g0 < 0)
        return ref


def _reference(gp: Gap, g0, T) -> Reference:
    with mpmath.workdps(DPS):
        zs = zones(gp, 0, T)
        note = ""
        if zs and zs[0].lo == 0 and abs(g0) <= gp.band(0):
            if gp.G1(0) < 0:
                z = zs[0]
                return Reference(0.0, [[0.0, float(z.hi * (1 + REL))]], False, False, "touching at t = 0, approaching")
            # search again beyond the zone at t = 0 (twice its length: outside the band)
            zs = zones(gp, 2 * zs[0].hi, T)
            note = "touching at t = 0, separating"
        accept = []
        for z in zs:
            lo = float(z.lo * (1 - REL))
            hi = float(min(z.hi * (1 + REL), T))
            accept.append([lo, hi])
            if z.cross:
                at_end = z.hi >= T * (1 - REL)
                # regular: the runtimes' rounding floor (64 eps S) moves the root by at most REL/4
                slope = abs(gp.G1(z.root))
                regular = bool(len(accept) == 1 and not at_end and z.root > 0 and slope > 0
                               and 64 * EPS * gp.S_tight(z.root) / slope <= REL / 4 * z.root)
                if regular:
                    accept = [[float(z.root * (1 - REL)), float(z.root * (1 + REL))]]
                return Reference(float(z.root), accept, bool(at_end), regular,
                                 note or ("touch zones before the contact" if len(accept) > 1 else ""))
        return Reference(None, accept, True, True, note or ("touches within the band only" if accept else ""))
