"""Reference answers of the TOI library (op "toi", docs/toi.md) on the
exact motion: real sin and cos, mpmath at 24 digits, independent of the
generated code and of the runtimes.

Each body's centre of rotation moves as p + v t + a t^2/2 and its angle as
angle + omega t; a polygon's vertex (x, y) about the centre is at
centre + R(angle) (x, y), a circle's centre at centre + orbit (cos(angle +
phase), sin(angle + phase)).  The distance D(t) of the two bodies is, for
each point P (a vertex of one polygon against the other polygon; a circle's
centre, less its radius) the signed distance of P to the other body (the
Euclidean distance outside, minus the depth inside), the smallest over the
points; two circles: the distance of their centres less the radii.  For
convex bodies that are apart D is their Euclidean distance.

`first_within(case, c)` is the first time D(t) <= c in [0, T], found
feature by feature: a point crossing an edge's line at offset c while it
lies along the edge's segment, or coming within c of a vertex (c > 0), or
lying behind every edge line by -c (c <= 0).  Each feature's gap is smooth
with a bound B2 >= |g''| over [0, T], so its crossings are isolated with
certainty: on [m - r, m + r], |g(t) - g(m)| <= r |g'(m)| + B2 r^2 / 2
excludes an interval or, with |g'(m)| > B2 r, proves it monotone.  A
crossing is then bisected to 1e-21 s.
"""
from __future__ import annotations

import mpmath

DPS = 24
MAX_DEPTH = 90


def _mp(x):
    return mpmath.mpf(x)


class Body:
    """One body of a case, in mpmath numbers."""

    def __init__(self, d: dict):
        m = d["motion"]
        self.p = (_mp(m["x"]), _mp(m["y"]))
        self.v = (_mp(m["vx"]), _mp(m["vy"]))
        self.a = (_mp(m["ax"]), _mp(m["ay"]))
        self.th, self.om = _mp(m["angle"]), _mp(m["omega"])
        self.polygon = d["shape"] == "polygon"
        if self.polygon:
            self.r = _mp(0)
            self.orbit = self.ophase = _mp(0)
            pts = [(_mp(x), _mp(y)) for x, y in d["vertices"]]
            self.pts = pts
            n = len(pts)
            self.edges = []          # (psi, h, s1, s2) per edge, exact
            for k in range(n):
                (x0, y0), (x1, y1) = pts[k], pts[(k + 1) % n]
                ex, ey = x1 - x0, y1 - y0
                ln = mpmath.sqrt(ex * ex + ey * ey)
                nx, ny = ey / ln, -ex / ln
                tx, ty = ex / ln, ey / ln
                self.edges.append((mpmath.atan2(ny, nx), nx * x0 + ny * y0, tx * x0 + ty * y0, tx * x1 + ty * y1))
            self.local = [(mpmath.sqrt(x * x + y * y), mpmath.atan2(y, x)) for x, y in pts]
            self.bound = max(rho for rho, _ in self.local)
        else:
            self.r = _mp(d["radius"])
            self.orbit, self.ophase = _mp(m.get("orbit", 0.0)), _mp(m.get("orbit_phase", 0.0))
            self.pts, self.edges, self.local = [], [], []
            self.bound = self.orbit + self.r

    def centre(self, t):
        return (self.p[0] + self.v[0] * t + self.a[0] * t * t / 2, self.p[1] + self.v[1] * t + self.a[1] * t * t / 2)

    def centre_d(self, t):
        return (self.v[0] + self.a[0] * t, self.v[1] + self.a[1] * t)

    def angle(self, t):
        return self.th + self.om * t

    def point(self, rho, beta, t):
        """A point at rho, beta about the centre: its position and velocity."""
        (cx, cy), (ux, uy) = self.centre(t), self.centre_d(t)
        ph = self.angle(t) + beta
        c, s = mpmath.cos(ph), mpmath.sin(ph)
        return (cx + rho * c, cy + rho * s), (ux - rho * self.om * s, uy + rho * self.om * c)

    def points(self):
        """(rho, beta, radius) of the points that touch: vertices, or the circle's centre."""
        if self.polygon:
            return [(rho, beta, _mp(0)) for rho, beta in self.local]
        return [(self.orbit, self.ophase, self.r)]


def _rel_bounds(P: Body, Q: Body, T):
    """Bounds over [0, T] on |dc|, |dc'|, |dc''| of the centres' difference."""
    dp = mpmath.sqrt((P.p[0] - Q.p[0]) ** 2 + (P.p[1] - Q.p[1]) ** 2)
    dv = mpmath.sqrt((P.v[0] - Q.v[0]) ** 2 + (P.v[1] - Q.v[1]) ** 2)
    da = mpmath.sqrt((P.a[0] - Q.a[0]) ** 2 + (P.a[1] - Q.a[1]) ** 2)
    return dp + dv * T + da * T * T / 2, dv + da * T, da


class _Line:
    """Point (rho, beta) of P against edge j's line of Q, offset c: g = n . (X - cQ) - h - c."""

    def __init__(self, P, rho, beta, Q, j, c, T):
        self.P, self.rho, self.beta, self.Q, self.j, self.c = P, rho, beta, Q, j, c
        psi, self.h, self.s1, self.s2 = Q.edges[j]
        self.psi = psi
        m0, m1, m2 = _rel_bounds(P, Q, T)
        self.B2 = Q.om ** 2 * m0 + 2 * abs(Q.om) * m1 + m2 + rho * (P.om - Q.om) ** 2

    def parts(self, t):
        (x, y), (u, w) = self.P.point(self.rho, self.beta, t)
        (qx, qy), (qu, qw) = self.Q.centre(t), self.Q.centre_d(t)
        ph = self.Q.angle(t) + self.psi
        nx, ny = mpmath.cos(ph), mpmath.sin(ph)
        dx, dy = x - qx, y - qy
        g = nx * dx + ny * dy - self.h - self.c
        gd = self.Q.om * (-ny * dx + nx * dy) + nx * (u - qu) + ny * (w - qw)
        along = -ny * dx + nx * dy
        return g, gd, along

    def f(self, t):
        g, gd, _ = self.parts(t)
        return g, gd

    def valid(self, t):
        _, _, along = self.parts(t)
        return self.s1 <= along <= self.s2


class _Dist:
    """Point (rho, beta) of P against point (rho2, beta2) of Q, radius R: g = |X - Y|^2 - R^2."""

    def __init__(self, P, rho, beta, Q, rho2, beta2, R, T):
        self.P, self.rho, self.beta, self.Q, self.rho2, self.beta2, self.R = P, rho, beta, Q, rho2, beta2, R
        m0, m1, m2 = _rel_bounds(P, Q, T)
        w0 = m0 + rho + rho2
        w1 = m1 + rho * abs(P.om) + rho2 * abs(Q.om)
        w2 = m2 + rho * P.om ** 2 + rho2 * Q.om ** 2
        self.B2 = 2 * w1 * w1 + 2 * w0 * w2

    def f(self, t):
        (x, y), (u, w) = self.P.point(self.rho, self.beta, t)
        (x2, y2), (u2, w2) = self.Q.point(self.rho2, self.beta2, t)
        dx, dy = x - x2, y - y2
        return dx * dx + dy * dy - self.R * self.R, 2 * (dx * (u - u2) + dy * (w - w2))

    def valid(self, t):
        return True


def _crossings(feat, T, t0=None):
    """The downward crossings of feat's g through 0 in (t0, T] (t0: 0 by
    default), in time order (a touch that reaches g <= 0 inside the depth
    limit counts as one)."""
    B2 = feat.B2

    def rec(lo, hi, glo, ghi, depth):
        m = (lo + hi) / 2
        r = (hi - lo) / 2
        gm, dm = feat.f(m)
        if abs(gm) > r * abs(dm) + B2 * r * r / 2:
            return
        if abs(dm) > B2 * r:
            if glo > 0 and ghi <= 0:
                a, b = lo, hi
                for _ in range(200):
                    if b - a <= mpmath.mpf("1e-21") * (1 + abs(b)):
                        break
                    mid = (a + b) / 2
                    if feat.f(mid)[0] > 0:
                        a = mid
                    else:
                        b = mid
                yield b
            return
        if depth >= MAX_DEPTH:
            if gm <= 0:
                yield m
            return
        yield from rec(lo, m, glo, gm, depth + 1)
        yield from rec(m, hi, gm, ghi, depth + 1)

    lo = _mp(0) if t0 is None else t0
    if not lo < T:
        return
    g0 = feat.f(lo)[0]
    gT = feat.f(T)[0]
    yield from rec(lo, T, g0, gT, 0)


def _first_valid(feat, T, t0=None):
    for t in _crossings(feat, T, t0):
        if feat.valid(t):
            return t
    return None


def _features(A: Body, B: Body, c, T):
    """The features whose crossings enter D <= c."""
    if not A.polygon and not B.polygon:
        R = A.r + B.r + c
        if R <= 0:
            return [], []
        return [_Dist(A, A.orbit, A.ophase, B, B.orbit, B.ophase, R, T)], []
    lines, deep = [], []
    for P, Q in ((A, B), (B, A)):
        if not Q.polygon:
            continue
        for rho, beta, rad in P.points():
            cc = c + rad
            group = [_Line(P, rho, beta, Q, j, cc, T) for j in range(len(Q.edges))]
            if cc > 0:
                lines += group
                lines += [_Dist(P, rho, beta, Q, r2, b2, cc, T) for r2, b2 in Q.local]
            elif cc == 0:
                lines += group
            else:
                deep.append(group)
    return lines, deep


def distance(A: Body, B: Body, t) -> object:
    """D(t): the bodies' signed distance (module docstring)."""
    if not A.polygon and not B.polygon:
        (x, y), _ = A.point(A.orbit, A.ophase, t)
        (x2, y2), _ = B.point(B.orbit, B.ophase, t)
        return mpmath.sqrt((x - x2) ** 2 + (y - y2) ** 2) - A.r - B.r
    best = None
    for P, Q in ((A, B), (B, A)):
        if not Q.polygon:
            continue
        for rho, beta, rad in P.points():
            (x, y), _ = P.point(rho, beta, t)
            (qx, qy) = Q.centre(t)
            gs, segs = [], []
            for j, (psi, h, s1, s2) in enumerate(Q.edges):
                ph = Q.angle(t) + psi
                nx, ny = mpmath.cos(ph), mpmath.sin(ph)
                dx, dy = x - qx, y - qy
                g = nx * dx + ny * dy - h
                along = -ny * dx + nx * dy
                gs.append(g)
                u = min(max(along, s1), s2)
                segs.append(mpmath.sqrt(g * g + (along - u) ** 2))
            sd = max(gs) if max(gs) <= 0 else min(segs)
            d = sd - rad
            best = d if best is None or d < best else best
    return best


def first_within(A: Body, B: Body, c, T, t_from=0.0):
    """The first time in [t_from, T] with D(t) <= c, or None, when D > c
    all through [0, t_from)."""
    with mpmath.workdps(DPS):
        c, T, t_from = _mp(c), _mp(T), _mp(t_from)
        if distance(A, B, t_from) <= c:
            return t_from
        # nothing comes within c before the bounding circles do
        R = A.bound + B.bound + abs(c)
        t0 = None
        for t in _crossings(_Dist(A, 0, 0, B, 0, 0, R, T), T, t_from):
            t0 = t
            break
        if t0 is None and not _Dist(A, 0, 0, B, 0, 0, R, T).f(t_from)[0] <= 0:
            return None
        t0 = t_from if t0 is None else t0
        lines, deep = _features(A, B, c, T)
        best = None
        for feat in lines:
            t = _first_valid(feat, best if best is not None else T, t0)
            if t is not None and (best is None or t < best):
                best = t
        for group in deep:
            for k, feat in enumerate(group):
                others = group[:k] + group[k + 1:]
                for t in _crossings(feat, best if best is not None else T, t0):
                    if all(o.f(t)[0] <= 0 for o in others):
                        if best is None or t < best:
                            best = t
                        break
        return best


def reference(case: dict) -> dict:
    """The reference fields of a case: d0 (D at 0), t_star (first D <= 0),
    t_in (first D <= 2 tol) and t_deep (first D <= -2 tol), as floats or None."""
    with mpmath.workdps(DPS):
        A, B = Body(case["a"]), Body(case["b"])
        T, tol = case["horizon"], case["tol"]
        d0 = distance(A, B, _mp(0))
        out = {"d0": float(d0), "t_in": None, "t_star": None, "t_deep": None}
        # D only decreases to a level after passing the higher ones: each search starts at the last
        start = 0.0
        for name, c in (("t_in", 2.0 * tol), ("t_star", 0.0), ("t_deep", -2.0 * tol)):
            t = first_within(A, B, c, T, start)
            if t is None:
                break
            out[name] = float(t)
            start = t
        return out
