"""Time of impact of two bodies (a circle or a convex polygon each), with
no world: the first contact within a horizon of two bodies moving as the
simulator moves them (docs/toi.md).  The computation is the simulator's own
(PredictMixin.pair_search, which its predictions call): bounding circles
that do not turn first, clear stretches, then Taylor windows of the
generated circle_circle and point_edge polynomials.  The same bits as the
C, Rust and Modula-2 libraries.

Units: s, m, m/s, m/s^2, rad, rad/s.  Angles count counter-clockwise.

    from max2code_rt.toi import Toi, circle, polygon, Motion
    lib = Toi(circle_circle_module, point_edge_module)   # generated with every effect
    r = lib.toi(circle(0.5), Motion(x=-3.0, vx=2.0), polygon([(-1, -1), (1, -1), (1, 1), (-1, 1)]),
                Motion(omega=1.0), 5.0)
    if r.status == HIT: r.t, r.px, r.py, r.nx, r.ny
"""
from __future__ import annotations

import math
from sys import float_info

from max2code_rt.sim.contact import ContactMixin
from max2code_rt.sim.motion import MotionMixin
from max2code_rt.sim.out import SimError
from max2code_rt.sim.overlap import OverlapMixin
from max2code_rt.sim.predict import CC, PE, TWO_M30, PredictMixin
from max2code_rt.sim.scene import Body, Vertex

DBL_MAX = float_info.max     # the largest finite double

# status of an answer (the C library's numbers)
ERROR, NONE, HIT, OVERLAPPED = -1, 0, 1, 2
# features of a contact: circle (or its centre) against a circle or a vertex; a point against an edge
FEATURE_CC, FEATURE_PE = CC, PE
# most vertices of a polygon shape
MAX_VERTICES = 64
# most steps (bounds, clear stretches, windows) of one query
MAX_STEPS = 10_000_000


class Shape:
    """A circle (verts empty, radius > 0) or a convex polygon (its vertices
    about the centre of rotation, radius 0); bound: m, the radius of the
    bounding circle about the centre of rotation."""
    __slots__ = ("radius", "bound", "verts")

    def __init__(self, radius: float, bound: float, verts: list[Vertex]):
        self.radius, self.bound, self.verts = radius, bound, verts


def circle(radius: float) -> Shape:
    """A circle of `radius` m (> 0); ValueError otherwise."""
    radius = float(radius)
    if not (0.0 < radius <= 1.7976931348623157e308):
        raise ValueError(f"radius {radius!r} is not positive and finite")
    return Shape(radius, radius, [])


def polygon(points) -> Shape:
    """A strictly convex polygon of 3..MAX_VERTICES vertices [(x, y), ...]
    (m, about the centre of rotation, counter-clockwise); ValueError otherwise."""
    pts = [(float(x), float(y)) for x, y in points]
    n = len(pts)
    if not (3 <= n <= MAX_VERTICES):
        raise ValueError(f"{n} vertices: a polygon has 3 to {MAX_VERTICES}")
    if not all(math.isfinite(x) and math.isfinite(y) for x, y in pts):
        raise ValueError("a vertex is not finite")
    verts = []
    bound = 0.0
    for k in range(n):
        (x0, y0), (x1, y1), (x2, y2) = pts[k], pts[(k + 1) % n], pts[(k + 2) % n]
        ex, ey = x1 - x0, y1 - y0
        if not (ex * (y2 - y1) - ey * (x2 - x1) > 0.0):
            raise ValueError("not strictly convex and counter-clockwise")
        ln = math.sqrt(ex * ex + ey * ey)
        nx, ny = ey / ln, -ex / ln          # outward: the polygon is counter-clockwise
        tx, ty = ex / ln, ey / ln
        rho = math.sqrt(x0 * x0 + y0 * y0)
        verts.append(Vertex((x0, y0, rho, math.atan2(y0, x0), math.atan2(ny, nx), nx * x0 + ny * y0,
                             tx * x0 + ty * y0, tx * x1 + ty * y1, nx, ny), -1))
        if rho > bound:
            bound = rho
    # the edges wind once around: the turns of the normal sum to 2 pi
    turn = 0.0
    for k in range(n):
        d = verts[(k + 1) % n].psi - verts[k].psi
        while d <= 0.0:
            d += 2.0 * math.pi
        turn += d
    if not (turn < 3.0 * math.pi):
        raise ValueError("the edges wind more than once")
    return Shape(0.0, bound, verts)


class Motion:
    """A body's motion at time 0 of the query: its centre of rotation moves
    as p + v t + a t^2/2, its angle as angle + omega t; a circle's own
    centre may orbit it at `orbit` m, at angle + orbit_phase."""
    __slots__ = ("x", "y", "vx", "vy", "ax", "ay", "angle", "omega", "orbit", "orbit_phase")

    def __init__(self, x=0.0, y=0.0, vx=0.0, vy=0.0, ax=0.0, ay=0.0, angle=0.0, omega=0.0, orbit=0.0,
                 orbit_phase=0.0):
        self.x, self.y, self.vx, self.vy, self.ax, self.ay = map(float, (x, y, vx, vy, ax, ay))
        self.angle, self.omega, self.orbit, self.orbit_phase = map(float, (angle, omega, orbit, orbit_phase))

    def values(self) -> tuple:
        return (self.x, self.y, self.vx, self.vy, self.ax, self.ay, self.angle, self.omega, self.orbit,
                self.orbit_phase)


class Result:
    """status (HIT, NONE, OVERLAPPED, ERROR); t (s); feature (FEATURE_CC or
    FEATURE_PE); first: False when i is A's feature and j B's, True when i
    is B's and j A's; i: vertex (-1: the circle) against j: edge or vertex
    (-1: the circle); (px, py) the contact point (m) and (nx, ny) the unit
    normal from the body holding i to the other, at t."""
    __slots__ = ("status", "t", "feature", "first", "i", "j", "px", "py", "nx", "ny")

    def __init__(self, status: int):
        self.status, self.t, self.feature, self.first, self.i, self.j = status, 0.0, 0, False, -1, -1
        self.px = self.py = self.nx = self.ny = 0.0

    def __repr__(self):
        return (f"Result(status={self.status}, t={self.t!r}, feature={self.feature}, first={self.first}, "
                f"i={self.i}, j={self.j}, p=({self.px!r}, {self.py!r}), n=({self.nx!r}, {self.ny!r}))")


class _Uncounted:
    """The variant counters of a world, counting nothing."""

    def __getitem__(self, k):
        return 0

    def __setitem__(self, k, v):
        pass


class _Stats:
    __slots__ = ("features", "pairs")

    def __init__(self):
        self.features = self.pairs = 0


class _Scene:
    __slots__ = ("tol", "alpha", "end", "bodies")


class _Pair(PredictMixin, MotionMixin, OverlapMixin, ContactMixin):
    """The simulator's pair computation without a world: two bodies, no
    counters, no covered edges."""

    STRAIGHT = 4.0      # a clear stretch of two turning polygons shorter than 4 windows: its window next

    def __init__(self, cc, pe):
        self.cc_coef, self.cc_var = cc.circle_circle_coefficients, cc.circle_circle_variant
        self.pe_coef, self.pe_var = pe.point_edge_coefficients, pe.point_edge_variant
        self.cc_counts = self.pe_counts = _Uncounted()
        self.stats = _Stats()
        self.s = _Scene()

    def bounds_meet(self, A: Body, B: Body, now: float, w: float) -> float | None:
        """PredictMixin.bounds_meet, but bounds that overlap now need no
        polynomial (the simulator keeps the polynomial's own value, whose
        bits its traces pin; a test that says overlap only goes on to the
        next step)."""
        x1, y1, _, _, _ = self.state_at(A, now)
        x2, y2, _, _, _ = self.state_at(B, now)
        tol = self.s.tol
        dx, dy, r = x1 - x2, y1 - y2, A.bound + B.bound
        if dx * dx + dy * dy - r * r <= tol * (2.0 * r + tol):
            return 0.0
        return PredictMixin.bounds_meet(self, A, B, now, w)

    def clear_time(self, A: Body, B: Body, now: float) -> float:
        """PredictMixin.clear_time, but for two polygons (when neither is a
        polygon that does not turn against one that does) the library's own
        (the simulator keeps its own, whose bits its traces pin): every
        vertex from one cosine and sine of its body's angle, and the gap
        along each edge normal of either polygon, held fixed and turning
        with its polygon (_edges_clear), as well as along the line of the
        centres.  Along a fixed axis the gap closes at most as fast as the
        centres' relative motion along it plus each bound times its turn
        rate, along a turning edge normal each vertex's gap stays above its
        Taylor polynomial of order 2 less the bound of its third derivative,
        and the gap of the best separating axis now is the separation, so
        this is never shorter than the bound through the norms |x| + |y|
        and never longer than the bodies stay apart."""
        if (not (A.polygon and B.polygon) or (B.om == 0.0 and self.turn_rate(A) > 0.0)
                or (A.om == 0.0 and self.turn_rate(B) > 0.0)):
            return PredictMixin.clear_time(self, A, B, now)
        x1, y1, u1, v1, g1 = self.state_at(A, now)
        x2, y2, u2, v2, g2 = self.state_at(B, now)
        dx, dy = x2 - x1, y2 - y1
        d = math.sqrt(dx * dx + dy * dy)
        if not (d > 0.0):
            return 0.0
        nx, ny = dx / d, dy / d
        ca, sa, cb, sb = math.cos(g1), math.sin(g1), math.cos(g2), math.sin(g2)
        pa = _rotated_points(A, x1, y1, ca, sa)
        pb = _rotated_points(B, x2, y2, cb, sb)
        wa = _spin_velocities(A, ca, sa)
        wb = _spin_velocities(B, cb, sb)
        hi = self.reach_points(nx, ny, pa)
        lo = -self.reach_points(-nx, -ny, pb)
        spin = A.bound * self.turn_rate(A) + B.bound * self.turn_rate(B)
        span = 1.0 / (math.fabs(A.om) + math.fabs(B.om))
        tol = self.s.tol
        du, dv, dax, day = u2 - u1, v2 - v1, B.ax - A.ax, B.ay - A.ay
        best = self.clear_root(lo - hi - tol, spin - (nx * du + ny * dv), math.fabs(nx * dax + ny * day))
        best = self._edges_clear(A, x1, y1, ca, sa, B, x2, y2, pb, wb, best, spin, span, du, dv, dax, day, tol)
        return self._edges_clear(B, x2, y2, cb, sb, A, x1, y1, pa, wa, best, spin, span, u1 - u2, v1 - v2,
                                 A.ax - B.ax, A.ay - B.ay, tol)

    def library_separation(self, A: Body, B: Body) -> float:
        """separation of A and B at 0; of two polygons with every vertex from
        one cosine and sine of its body's angle (_rotated_points), the
        library's own values (the simulator keeps separation's)."""
        if not (A.polygon and B.polygon):
            return self.separation(A, B, 0.0)
        x1, y1, _, _, g1 = self.state_at(A, 0.0)
        x2, y2, _, _, g2 = self.state_at(B, 0.0)
        pa = _rotated_points(A, x1, y1, math.cos(g1), math.sin(g1))
        pb = _rotated_points(B, x2, y2, math.cos(g2), math.sin(g2))
        return self.polygons_separation(A, B, 0.0, pa, pb)

    def _edges_clear(self, P: Body, px: float, py: float, c: float, s: float, Q: Body, qx: float, qy: float, pts,
                     wq, best: float, spin: float, span: float, du: float, dv: float, dax: float, day: float,
                     tol: float) -> float:
        """The larger of best and the time the other polygon Q (its centre
        (qx, qy)) stays beyond some edge line of P (its centre (px, py),
        cos c and sin s of its angle) by more than tol (s).  Q's vertices
        pts and their velocities from the turn wq (_spin_velocities);
        (du, dv) and (dax, day): Q's velocity and acceleration less P's;
        spin: the bounds times the turn rates; span: the time of one radian
        of the two turns together (s), the reach of the turning bound.

        Along the edge's outward normal o held fixed, every vertex of Q
        stays beyond P's support until the root of the rate bound
        e - (spin - o . (du, dv)) s - |o . (dax, day)| s^2/2 of the nearest
        vertex's gap e (each point of a body moves along o at most its
        bound times its turn rate faster than the centre).  Along the
        normal n(s) turning with P, P's support is the edge's own line, and
        vertex k's gap g(s) = n(s) . (d(s) + r_k(s)) - h (d: Q's centre less
        P's, r_k: the vertex about Q's centre) has, with the turn rates wp
        and wq, the derivatives g1 = wp n_ . u + n . (dv + w_k) and g2 =
        -wp^2 n . u + 2 wp n_ . (dv + w_k) + n . da - wq^2 n . r_k at 0 (u =
        d + r_k, n_ the normal turned a quarter, w_k the vertex's velocity
        from the turn); over [0, span] the third derivative is at most J =
        |wp|^3 D + 3 wp^2 V + 3 |wp| |da| + bound_Q |wq - wp|^3 and the
        first at most |wp| D + V + bound_Q |wq - wp| (D, V: bounds of |d|
        and |d'| over the span), so g stays above g(0) + g1 s + (g2 - J
        span/3) s^2/2 until that bound's root (at most span).  The axis
        holds until the later of the two; the turning normal is taken only
        where it can raise the axis and best, nearest vertex first, and a
        vertex whose first-derivative bound already lasts past the time so
        far is not solved."""
        wp, wr = P.om, Q.om
        vel = math.sqrt(du * du + dv * dv)
        acc = math.sqrt(dax * dax + day * day)
        cx, cy = qx - px, qy - py
        dist = math.sqrt(cx * cx + cy * cy) + (vel + 0.5 * acc * span) * span
        vmax = vel + acc * span
        aw, dw = math.fabs(wp), math.fabs(wr - wp)
        jerk = (aw * aw * aw * dist + 3.0 * aw * aw * vmax + 3.0 * aw * acc + Q.bound * dw * dw * dw) * span / 3.0
        rate = aw * dist + vmax + Q.bound * dw
        turning = span > 0.0 and span <= DBL_MAX and jerk <= DBL_MAX and rate <= DBL_MAX
        n = len(pts)
        for ed in P.verts:
            ox = c * ed.nx - s * ed.ny
            oy = s * ed.nx + c * ed.ny
            off = ox * px + oy * py + ed.h
            g = math.inf
            near = 0
            gaps = []
            for k, (x, y) in enumerate(pts):
                e = ox * x + oy * y - off
                if e - tol <= 0.0:
                    break               # then g - tol <= 0 too: x - tol rises with x
                gaps.append(e)
                if e < g:
                    g = e
                    near = k
            if len(gaps) < n or not (g - tol > 0.0):
                continue                # not apart along this axis: 0, never above best
            m = self.clear_root(g - tol, spin - (ox * du + oy * dv), math.fabs(ox * dax + oy * day))
            if turning and span > m and span > best:
                mt = span
                for i in range(n):
                    k = near if i == 0 else (i - 1 if i <= near else i)
                    e = gaps[k] - tol
                    if e - mt * rate >= 0.0:
                        continue        # its first-derivative bound alone lasts past mt
                    x, y = pts[k]
                    ux, uy = x - px, y - py
                    vx, vy = du + wq[k][0], dv + wq[k][1]
                    g1 = wp * (ox * uy - oy * ux) + (ox * vx + oy * vy)
                    g2 = (-(wp * wp) * (ox * ux + oy * uy) + 2.0 * wp * (ox * vy - oy * vx) + (ox * dax + oy * day)
                          - wr * wr * (ox * (x - qx) + oy * (y - qy)))
                    q = jerk - g2
                    if not (q > 0.0):
                        q = 0.0
                    t = self.clear_root(e, -g1, q)
                    if not (t >= 0.0):
                        t = 0.0
                    if t < mt:
                        mt = t
                        if not (mt > m and mt > best):
                            break
                if mt > m:
                    m = mt
            if m > best:
                best = m
        return best


def _rotated_points(b: Body, x: float, y: float, c: float, s: float) -> list[tuple[float, float]]:
    """The vertices of polygon b whose centre is at (x, y), from the cosine c
    and sine s of its angle: the rotation of each vertex's place (lx, ly)
    in the body's frame (m)."""
    return [(x + (c * v.lx - s * v.ly), y + (s * v.lx + c * v.ly)) for v in b.verts]


def _spin_velocities(b: Body, c: float, s: float) -> list[tuple[float, float]]:
    """The velocity of each vertex of polygon b about its centre from its
    turn (m/s): its offset from the centre (the rotation of its place
    (lx, ly) by the cosine c and sine s of the body's angle) turned a
    quarter and times the turn rate."""
    return [(-(b.om * (s * v.lx + c * v.ly)), b.om * (c * v.lx - s * v.ly)) for v in b.verts]


def _bounds_apart(A: Body, B: Body, tol: float) -> bool:
    """A and B at 0 are farther apart than their bounds and tol, so that
    their separation exceeds tol (each body lies within its bound about its
    centre of rotation) and the overlap test can be spared: the centres'
    distance less the bounds, with a margin of 2^-30 of the sizes for every
    rounding."""
    dx, dy, r = B.px - A.px, B.py - A.py, A.bound + B.bound
    d = math.sqrt(dx * dx + dy * dy)
    return d - r > tol + TWO_M30 * (d + r + math.fabs(A.px) + math.fabs(A.py) + math.fabs(B.px) + math.fabs(B.py))


def _angle_for(lever: float, n: int, tol: float) -> float:
    """The largest angle (at most 0.5 rad) whose order-n Taylor remainder of
    sin and cos, a^(n+1)/(n+1)!, times the lever (m) stays below tol."""
    f = 1.0
    for k in range(2, n + 2):
        f = f * float(k)
    return min(0.5, (f * tol / lever) ** (1.0 / float(n + 1)))


def _body(s: Shape, q: Motion, idx: int) -> Body:
    b = Body.__new__(Body)
    b.idx, b.polygon, b.fixed = idx, bool(s.verts), False
    b.px, b.py, b.vx, b.vy, b.ax, b.ay = q.x, q.y, q.vx, q.vy, q.ax, q.ay
    b.tb, b.om, b.ang = 0.0, q.omega, q.angle
    if b.polygon:
        b.r, b.orbit, b.ophase, b.bound = 0.0, 0.0, 0.0, s.bound
    else:
        b.r, b.orbit, b.ophase = s.radius, q.orbit, q.orbit_phase
        b.bound = b.orbit + b.r
    b.window = 0.0
    b.verts = s.verts
    b.sup, b.asleep, b.gone, b.island = -1, False, False, -1
    return b


class Toi:
    """The TOI library over the generated circle_circle and point_edge
    modules (generated with every effect, acceleration and orbit, at
    `taylor_order`); tol: m, the distance tolerance of contacts."""

    def __init__(self, cc, pe, tol: float = 1e-9, taylor_order: int = 4):
        self.pair = _Pair(cc, pe)
        self.tol, self.order = float(tol), int(taylor_order)

    def toi(self, a: Shape, ma: Motion, b: Shape, mb: Motion, horizon: float) -> Result:
        """The first contact of A and B within [0, horizon] s (docs/toi.md)."""
        tol, order = self.tol, self.order
        horizon = float(horizon)
        if not (0.0 < tol <= 1.7976931348623157e308) or not (1 <= order <= 7):
            return Result(ERROR)
        if not (0.0 <= horizon <= 1.7976931348623157e308):
            return Result(ERROR)
        for q in (ma, mb):
            if not all(math.fabs(v) <= 1.7976931348623157e308 for v in q.values()) or not (q.orbit >= 0.0):
                return Result(ERROR)
        if (a.verts and ma.orbit != 0.0) or (b.verts and mb.orbit != 0.0):
            return Result(ERROR)
        A, B = _body(a, ma, 0), _body(b, mb, 1)
        p = self.pair
        s = p.s
        s.tol, s.bodies, s.end = tol, [A, B], horizon
        if not _bounds_apart(A, B, tol) and p.library_separation(A, B) < -tol:
            return Result(OVERLAPPED)
        # the windows (docs/simulator.md, "Taylor windows"): both turn, a
        # lever of twice the larger bound plus the larger bound; one turns,
        # its bound plus a circle partner's radius
        ta, tb = p.turn_rate(A), p.turn_rate(B)
        big = A.bound if A.bound > B.bound else B.bound
        s.alpha = 0.5
        if ta > 0.0 and tb > 0.0:
            s.alpha = _angle_for(2.0 * big + big, order, tol)
        elif ta > 0.0:
            A.window = _angle_for(A.bound + B.r, order, tol)
        elif tb > 0.0:
            B.window = _angle_for(B.bound + A.r, order, tol)
        try:
            found, at, best = p.pair_search(A, B, 0.0, horizon, MAX_STEPS, MAX_STEPS)
        except SimError:
            return Result(ERROR)
        if found == 2:
            return Result(ERROR)
        if found == 0:
            return Result(NONE)
        s_, feat, ia, ib, i, j = best
        t = at + s_
        r = Result(HIT)
        r.t, r.feature, r.first, r.i, r.j = t, feat, ia == 1, i, j
        X, Y = s.bodies[ia], s.bodies[ib]
        bang = p.state_at(Y, t)[4]
        r.px, r.py, r.nx, r.ny = p.contact_frame(t, feat, X, Y, i, j, bang)
        return r
