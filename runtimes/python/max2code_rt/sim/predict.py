"""Predictions: the first contact of a pair after now (pair_search, which
the TOI library max2code_rt.toi calls too; or a horizon event where the
Taylor polynomials of its turns stop being good), the first valid
root of one feature's gap polynomial, and a body's next cell crossing.
Every prediction goes through the generated entries of
equations/circle-circle.mxm and equations/point-edge.mxm (the World's
cc_coef, cc_var, pe_coef, pe_var) and the root solver smallest_root."""
from __future__ import annotations

import math

from max2code_rt.roots import _HI_MIN, _no_root3, _no_root4, smallest_root
from max2code_rt.sim.motion import MotionMixin
from max2code_rt.sim.out import SimError
from max2code_rt.sim.queue import CellEvent
from max2code_rt.sim.scene import Body, Vertex

HALF_PI = 1.5707963267948966   # pi/2 rounded to double (cos x = sin(x + pi/2))
# contact features: circle-circle (also circle-vertex) and point-edge
CC, PE = 0, 1
# the most stages (a meeting of the bounds, a clear stretch, a Taylor window)
# one prediction of a pair goes through before it leaves the rest to a horizon
CHAIN = 8
TWO_M40 = 2.0 ** -40  # circles_apart's margins: far above the coefficients' rounding
TWO_M30 = 2.0 ** -30
MAX_FLOAT = 1.7976931348623157e308
TWO_M900 = 2.0 ** -900  # ... and its bounds on sizes: nothing underflows or overflows
TWO_M450 = 2.0 ** -450
TWO_P450 = 2.0 ** 450
FEATURE_NAMES = ("circle-circle", "point-edge")
_BEFORE_MARGIN = 2.0 ** -10  # first_contact's: a root beyond before (1 + 2^-10) is far beyond before


def _always(s: float) -> bool:
    return True


_BINOMIAL = tuple(tuple(float(math.comb(j, i)) for i in range(j + 1)) for j in range(9))  # exact
_TWO_M46 = 2.0 ** -46
_TWO_M900 = 2.0 ** -900
_TWO_M100 = 2.0 ** -100


def _no_root_high(c: list[float], n: int, hi: float) -> bool:
    """The polynomial c of degree n (5 to 8) surely has no root in [0, hi]
    (hi >= 2^-100, so that hi^8 stays normal): its Bernstein coefficients
    there, b_j = sum_{i <= j} C(j, i) u_i with t_i = c_i hi^i and u_i = t_i /
    C(n, i), are all beyond m = 2^-46 S + 2^-900 (S = sum |t_i|) with t_0's
    sign (the root solver's test for degrees 3 and 4, for higher degrees:
    docs/simulator.md, "Features that cannot come first")."""
    u = []
    p = 1.0
    S = 0.0
    for i in range(n + 1):
        t = c[i] * p
        p = p * hi
        S = S + abs(t)
        u.append(t / _BINOMIAL[n][i])
    m = _TWO_M46 * S + _TWO_M900
    neg = u[0] < 0.0
    for j in range(n + 1):
        row = _BINOMIAL[j]
        b = 0.0
        for i in range(j + 1):
            b = b + row[i] * u[i]
        if not (b < -m if neg else b > m):
            return False
    return True


def _before(best) -> float:
    """first_contact's before for the earliest contact found so far (best: _better's)."""
    return math.inf if best is None else best[0]


class PredictMixin:
    """Pairs, features, first valid roots, cell crossings."""

    # A clear stretch of two turning polygons shorter than this many Taylor
    # windows leads straight to the window at its end, without another bound
    # or clear-stretch test (the TOI library's own step; 0: never, the
    # simulator's chain)
    STRAIGHT = 0.0

    @staticmethod
    def pressing(c: list[float], deg: int, d: float, s: float) -> bool:
        """At a zero of the gap c: approaching (first derivative d < 0), or
        resting and pressed together (d == 0, second derivative < 0)."""
        if d < 0.0:
            return True
        if d != 0.0 or deg < 2:
            return False
        dd = 0.0
        for k in range(deg, 1, -1):
            dd = dd * s + k * (k - 1) * c[k]
        return dd < 0.0

    @staticmethod
    def touching_now(c: list[float], deg: int, kappa: float) -> bool:
        """At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
        pressed together (c2 < 0) so that the gap closes again before it
        ever exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.
        (A resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.)"""
        if c[1] < 0.0:
            return True
        if deg < 2 or not (c[2] < 0.0):
            return False
        return c[0] + c[1] * c[1] / (4.0 * -c[2]) <= kappa

    def first_contact(self, c: list[float], deg: int, w: float, kappa: float, check,
                      before: float = math.inf) -> float | None:
        """The smallest s in [0, w] where the gap c(s) reaches zero while
        decreasing, or touches zero with zero slope while pressed together
        (resting contact), and check(s) holds.  At s = 0 the gap counts as
        zero within kappa: approaching or pressed (touching_now) means
        contact now, separating or merely touching never.

        before: the earliest contact of the pair's other features found so
        far (inf for none); a contact at or after it is never kept (the
        earliest one, first found on a tie, wins), so the search may answer
        None instead (docs/simulator.md, "Features that cannot come first"):
        at once when before is 0, and when a Bernstein test shows no root in
        [0, before (1 + 2^-10)] (degrees 3 and 4: the root solver's entry's;
        5 to 8: _no_root_high), so that a root found in [0, w] lies beyond
        before by far more than the solver's error."""
        if not (before > 0.0):
            return None
        if deg >= 1 and math.fabs(c[0]) <= kappa and self.touching_now(c, deg, kappa) and check(0.0):
            return 0.0
        if before < w and 3 <= deg <= 8:
            h = before + before * _BEFORE_MARGIN
            if h < w and ((h >= _HI_MIN and (_no_root3(c[0], c[1], c[2], c[3], h) if deg == 3
                                             else _no_root4(c[0], c[1], c[2], c[3], c[4], h))) if deg <= 4
                          else h >= _TWO_M100 and _no_root_high(c, deg, h)):
                return None
        lo = 0.0
        for _ in range(deg + 2):
            s = smallest_root(c[:deg + 1], lo, w)
            if s is None:
                return None
            d = 0.0
            for k in range(deg, 0, -1):
                d = d * s + k * c[k]
            if self.pressing(c, deg, d, s) and check(s):
                return s
            lo = s
        return None

    def circle_params(self, b: Body, now: float, v: Vertex | None):
        """circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
        circle's centre (v None) or of a polygon's vertex, at time now."""
        x, y, vx, vy, ang = self.state_at(b, now)
        if v is None:
            d, phase = b.orbit, ang + b.ophase
        else:
            d, phase = v.rho, ang + v.beta
        om = b.om
        if om == 0.0 and d != 0.0:
            # an orbit that does not turn is a fixed offset: fold it in
            x = x + d * math.cos(phase)
            y = y + d * math.sin(phase)
            d = 0.0
        if d == 0.0:
            om = 0.0
            phase = 0.0
        return x, vx, b.ax, d, om, phase + HALF_PI, y, vy, b.ay, om, phase

    @staticmethod
    def centre_params(b: Body, now: float):
        """circle_circle parameters of b's centre of rotation at time now, no
        orbit: the centre of a bounding circle (circle_params of a polygon)."""
        x, y, vx, vy, _ = MotionMixin.state_at(b, now)
        return x, vx, b.ax, 0.0, 0.0, HALF_PI, y, vy, b.ay, 0.0, 0.0

    def predict_cc(self, A: Body, B: Body, vb: Vertex | None, rb: float, now: float, w: float,
                   before: float = math.inf):
        """Circle of A against circle of B (vb None) or vertex vb of B (radius 0); before: first_contact's."""
        return self.circles_first(self.circle_params(A, now, None), A.r, self.circle_params(B, now, vb), rb, w,
                                  before)

    def circles_first(self, pa, ra: float, pb, rb: float, w: float, before: float = math.inf):
        """The first contact within [0, w] of a circle of radius ra moving as
        pa (circle_params) and one of radius rb moving as pb."""
        args = self.cc_args(pa, ra, pb, rb)
        tol = self.s.tol
        kappa = tol * (2.0 * (ra + rb) + tol)
        if self.circles_apart(args, kappa):
            self.cc_count(args)
            return None
        coef = self.cc_coefficients(args)
        return self.first_contact(coef, len(coef) - 1, w, kappa, _always, before)

    @staticmethod
    def circles_apart(g, kappa: float) -> bool:
        """The pair of circles_gap's parameters g surely has no contact,
        decided without the polynomial (docs/simulator.md, "Pairs that stay
        apart"): neither circle orbits and their relative acceleration is
        zero, so the gap is |p + v s|^2 - R^2 (p, v: the relative position
        and velocity, R = ra + rb), and either the centres separate (p . v > 0
        by more than its rounding: the generated c1 = 2 p.v is then positive,
        c2 = |v|^2 is never negative, and first_contact finds no approach),
        or they approach on a line that passes farther than R from each
        other: (p x v)^2 > (R^2 + kappa) |v|^2 by more than the rounding
        (then the gap now exceeds kappa and its discriminant is clearly
        negative: no root).  The margins (2^-40 and 2^-30 of the terms'
        size) are far above the few units of 2^-53 by which the coefficients
        can be off, and the sizes are bounded so that nothing underflows
        (where rounding is no longer relative: a speed of 1e-162 m/s squares
        to 0) or overflows.  The caller still counts the prediction."""
        if g[2] != 0.0 or g[8] != 0.0 or g[3] != 0.0 or g[14] != 0.0:
            return False
        x, vx, y, vy = g[0], g[1], g[6], g[7]
        px, py = x * vx, y * vy
        size = math.fabs(px) + math.fabs(py)
        if size >= TWO_M900 and px + py > TWO_M40 * size:
            return True
        r = g[22] + g[23]
        v2, p2 = vx * vx + vy * vy, x * x + y * y
        if not (TWO_M450 <= v2 <= TWO_P450 and TWO_M450 <= p2 <= TWO_P450):
            return False
        cross = x * vy - y * vx
        return cross * cross - (r * r + kappa) * v2 > TWO_M30 * p2 * v2

    def circles_gap(self, pa, ra: float, pb, rb: float) -> list[float]:
        """The circle_circle polynomial (squared distance of the centres less
        (ra + rb)^2, in s from the parameters' time) of a circle of radius ra
        moving as pa (circle_params) and one of radius rb moving as pb."""
        return self.cc_coefficients(self.cc_args(pa, ra, pb, rb))

    @staticmethod
    def cc_args(pa, ra: float, pb, rb: float) -> tuple:
        """circle_circle's 24 parameters of a circle of radius ra moving as
        pa (circle_params) and one of radius rb moving as pb."""
        a, b_, c, d, e, f, m, n, o, p, q = pa
        g, h, i, j, k, l, r, s_, u, v, ww = pb
        # only differences of the centres' motions matter: circle 1 moves
        # relative to circle 2's centre of rotation, so that a common gravity
        # cancels (no_accel variants) and far from the origin nothing is lost
        return (a - g, b_ - h, c - i, d, e, f, m - r, n - s_, o - u, p, q,
                0.0, 0.0, 0.0, j, k, l, 0.0, 0.0, 0.0, v, ww, ra, rb)

    def cc_count(self, args) -> None:
        """Counts a circle_circle prediction: its variant and `features`."""
        idx = self.cc_var(*args)
        if idx < 0:
            raise SimError("circle_circle: the scene uses an effect the generated code leaves out")
        self.cc_counts[idx] += 1
        self.stats.features += 1

    def cc_coefficients(self, args) -> list[float]:
        self.cc_count(args)
        return self.cc_coef(*args)

    def predict_pe(self, X: Body, Y: Body, vx_: Vertex | None, j: int, now: float, w: float, i: int = -1,
                   before: float = math.inf):
        """Point of X (circle centre with radius, or vertex vx_, X's vertex i) against the line of edge j
        of Y (none while a fixed body covers the edge: its cover is not gone); before: first_contact's."""
        cover = Y.verts[j].cover
        if cover >= 0 and not self.s.bodies[cover].gone:
            return None
        if vx_ is None:
            rho, beta, rad = X.orbit, X.ophase, X.r
        else:
            rho, beta, rad = vx_.rho, vx_.beta, 0.0
        coef = self.pe_coefficients(X, Y, rho, beta, rad, j, now)
        return self.pe_first(coef, X, Y, rho, beta, j, now, w, i, before)

    def pe_coefficients(self, X: Body, Y: Body, rho: float, beta: float, rad: float, j: int,
                        now: float) -> list[float]:
        """The point_edge polynomial of a circle of radius rad whose centre
        orbits X's centre at rho (phase beta in X's frame) against the line
        of edge j of Y, in s = t - now (its c[0]: the gap now)."""
        ed = Y.verts[j]
        x1, y1, u1, v1, ang1 = self.state_at(X, now)
        x2, y2, u2, v2, ang2 = self.state_at(Y, now)
        phn = ang2 + ed.psi
        wr = X.om - Y.om
        phr = (ang1 + beta) - phn
        h = ed.h + rad
        if wr == 0.0 and rho != 0.0:
            # the point does not turn relative to the edge: its offset along
            # the normal is a constant, folded into the line's offset
            h = h - rho * math.cos(phr)
            rho = 0.0
        args = (x1 - x2, u1 - u2, X.ax - Y.ax, y1 - y2, v1 - v2, X.ay - Y.ay,
                rho, wr, phr, Y.om, phn, h)
        idx = self.pe_var(*args)
        if idx < 0:
            raise SimError("point_edge: the scene uses an effect the generated code leaves out")
        self.pe_counts[idx] += 1
        self.stats.features += 1
        return self.pe_coef(*args)

    def pe_first(self, coef: list[float], X: Body, Y: Body, rho: float, beta: float, j: int, now: float,
                 w: float, i: int = -1, before: float = math.inf):
        """The first contact within [0, w] of pe_coefficients' polygon whose
        point (X's centre, or rho, beta about it) lies on edge j's segment;
        when the point is X's vertex i (i >= 0), both neighbours of that
        vertex must also lie no more than the tolerance behind edge j's line
        (`behind`: else that line does not separate the bodies there, a
        corner meeting a corner: another feature pair is the contact)."""
        ed = Y.verts[j]
        tol = self.s.tol

        def inside(s: float) -> bool:
            t = now + s
            px, py, _, _, pa = self.state_at(X, t)
            if rho != 0.0:
                px, py = px + rho * math.cos(pa + beta), py + rho * math.sin(pa + beta)
            qx, qy, _, _, qa = self.state_at(Y, t)
            th = qa + ed.psi
            c = math.cos(th)
            sn = math.sin(th)
            along = (px - qx) * -sn + (py - qy) * c
            if not (ed.s1 - tol <= along <= ed.s2 + tol):
                return False
            if i < 0:
                return True
            return not self.behind(X, i, t, qx, qy, c, sn, ed.h)

        return self.first_contact(coef, len(coef) - 1, w, tol, inside, before)

    def behind(self, X: Body, i: int, t: float, qx: float, qy: float, c: float, sn: float, h: float) -> bool:
        """A neighbour of X's vertex i at t lies more than the tolerance
        behind the line (c, sn) . (p - (qx, qy)) = h (an edge's line: its
        outward unit normal (c, sn) at angle th, its body's centre (qx, qy)),
        previous neighbour first (docs/simulator.md, "Corners")."""
        n = len(X.verts)
        px, py, _, _, pa = self.state_at(X, t)
        lim = -self.s.tol
        for k in ((i + n - 1) % n, (i + 1) % n):
            v = X.verts[k]
            kx = px + v.rho * math.cos(pa + v.beta)
            ky = py + v.rho * math.sin(pa + v.beta)
            if (kx - qx) * c + (ky - qy) * sn - h < lim:
                return True
        return False

    def predict_pair(self, A: Body, B: Body, now: float) -> None:
        """Schedule the first contact of A and B after now, or a horizon
        event where the Taylor polynomials of their turns stop being good.
        Cheap steps chain: a later meeting of the bounds or a clear stretch
        moves `now` on (up to CHAIN stages, at most one Taylor window:
        pair_search, the TOI library's computation)."""
        s = self.s
        if A.sup == B.idx or B.sup == A.idx:
            return      # the support's edge line separates them (both convex): only leaving ends it
        if (A.asleep and self.grounded(B)) or (B.asleep and self.grounded(A)):
            return      # a sleeper against a sleeper or an unmoving fixed body: nothing moves
        self.stats.pairs += 1
        found, at, best = self.pair_search(A, B, now, s.end, CHAIN, 1)
        if found == 1:
            bodies = s.bodies
            self.push_collision(at + best[0], best[1], bodies[best[2]], bodies[best[3]], best[4], best[5])
        elif found == 2 and at < s.end:
            self.push_horizon(at, A, B)

    def pair_search(self, A: Body, B: Body, now: float, end: float, stages: int, windows: int):
        """The first contact of A and B after now (docs/simulator.md, "One
        prediction chains its cheap steps"): a later meeting of the bounds
        or a clear stretch moves now on, a Taylor window solves the
        features, at most `stages` steps of which at most `windows` windows.
        (1, at, best) with best = (s after at, feature, a, b, i, j); (0, at,
        None) when there is none before end; (2, at, None) when the steps
        ran out at `at` (the simulator schedules a horizon there)."""
        s = self.s
        ta, tb = self.turn_rate(A), self.turn_rate(B)
        lead = self.STRAIGHT if A.polygon and B.polygon and ta > 0.0 and tb > 0.0 else 0.0
        straight = False
        solved = 0
        for _ in range(stages):
            w = end - now
            if not (w > 0.0):
                return 0, now, None
            if (A.polygon or B.polygon) and not straight:
                # bounds that do not turn: until they touch, nothing can
                if B.polygon and ta > 0.0 and B.om == 0.0:
                    meet = self.bound_polygon(A, B, now, w)
                elif A.polygon and tb > 0.0 and A.om == 0.0:
                    meet = self.bound_polygon(B, A, now, w)
                else:
                    meet = self.bounds_meet(A, B, now, w)
                if meet is None:
                    return 0, now, None
                if meet > 0.0:
                    now = now + meet
                    continue
            if ta > 0.0 and tb > 0.0:
                w = min(w, s.alpha / (ta + tb))
            elif ta > 0.0:
                w = min(w, A.window / ta)
            elif tb > 0.0:
                w = min(w, B.window / tb)
            if (ta > 0.0 or tb > 0.0) and not straight:
                clear = self.clear_time(A, B, now)
                if clear >= w:
                    # apart all through the window, whatever the turns do: no
                    # roots to solve until they may come within the tolerance
                    now = now + clear
                    straight = clear < lead * w
                    continue
            straight = False
            if solved >= windows:
                break       # the simulator: one Taylor window per prediction, the next at a horizon
            best = self.features(A, B, now, w)
            if best is not None:
                return 1, now, best
            if ta == 0.0 and tb == 0.0:
                return 0, now, None     # nothing turns: the window was the whole run
            now = now + w
            solved += 1
        return 2, now, None

    def features(self, A: Body, B: Body, now: float, w: float):
        """The earliest contact of A's and B's features within [0, w] after now:
        (s, feature, a, b, i, j), or None."""
        best = None
        if not A.polygon and not B.polygon:
            t = self.predict_cc(A, B, None, B.r, now, w)
            if t is not None:
                best = (t, CC, A.idx, B.idx, -1, -1)
        elif not A.polygon:
            best = self.circle_polygon(A, B, now, w, None)
        elif not B.polygon:
            best = self.circle_polygon(B, A, now, w, None)
        else:
            best = self.vertices_edges(A, B, now, w, None)
            best = self.vertices_edges(B, A, now, w, best)
        return best

    def bounds_meet(self, A: Body, B: Body, now: float, w: float) -> float | None:
        """When the bounding circles first touch within (0, w]: 0.0 when they
        overlap or touch now (within the tolerance), None when they do not
        meet (exact: bounding circles do not turn)."""
        x1, y1, u1, v1, _ = self.state_at(A, now)
        x2, y2, u2, v2, _ = self.state_at(B, now)
        args = (x1 - x2, u1 - u2, A.ax - B.ax, 0.0, 0.0, HALF_PI, y1 - y2, v1 - v2, A.ay - B.ay, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0, A.bound, B.bound)
        coef = self.cc_coefficients(args)
        tol = self.s.tol
        if coef[0] <= tol * (2.0 * (A.bound + B.bound) + tol):
            return 0.0
        return smallest_root(coef, 0.0, w)

    def bound_polygon(self, T: Body, P: Body, now: float, w: float) -> float | None:
        """T turns, polygon P does not: when T's bounding circle (radius
        T.bound about T's centre of rotation, which does not turn) first
        touches P itself (its edges, then its vertices) within (0, w]; 0.0 when
        no edge line of P has the circle beyond it by more than the tolerance
        now (overlapping, or near a corner); None when they do not meet.
        Exact: neither the circle nor P turns."""
        tol = self.s.tol
        coefs = []
        apart = False
        for j in range(len(P.verts)):
            c = self.pe_coefficients(T, P, 0.0, 0.0, T.bound, j, now)
            if c[0] > tol:
                apart = True
            coefs.append(c)
        if not apart:
            return 0.0
        meet = None
        for j in range(len(P.verts)):
            t = self.pe_first(coefs[j], T, P, 0.0, 0.0, j, now, w, -1, math.inf if meet is None else meet)
            if t is not None and (meet is None or t < meet):
                meet = t
        pt = self.centre_params(T, now)
        for v in P.verts:
            t = self.circles_first(pt, T.bound, self.circle_params(P, now, v), 0.0, w,
                                   math.inf if meet is None else meet)
            if t is not None and (meet is None or t < meet):
                meet = t
        return meet

    def clear_time(self, A: Body, B: Body, now: float) -> float:
        """How long A and B surely stay more than the tolerance apart, from
        their gap g along a fixed unit axis n now (0 when not apart now).
        Along n the gap changes by (dv . n) s + (da . n) s^2/2 from the
        centres' relative motion (dv, da: the far body's velocity and
        acceleration less the near one's, so that dv . n > 0 opens the gap)
        and closes by at most spin s from the turns (spin: each turning
        body's bound times its turn rate): it stays above the tolerance for
        s below the positive root of |da . n|/2 s^2 + r s - (g - tol),
        r = spin - dv . n (clear_root).  The axis: when one of them is a
        polygon P that does not turn and the other, T, turns, each of P's
        edge normals (fixed: P does not turn; g the gap of T's vertices, or
        of its circle, beyond the edge's line), the largest of the times;
        otherwise the line of the centres (g: the smallest projection of B
        on it less the largest of A's, circles by their radius)."""
        if B.polygon and B.om == 0.0 and self.turn_rate(A) > 0.0:
            return self.clear_axes(A, B, now)
        if A.polygon and A.om == 0.0 and self.turn_rate(B) > 0.0:
            return self.clear_axes(B, A, now)
        x1, y1, u1, v1, _ = self.state_at(A, now)
        x2, y2, u2, v2, _ = self.state_at(B, now)
        dx, dy = x2 - x1, y2 - y1
        d = math.sqrt(dx * dx + dy * dy)
        if not (d > 0.0):
            return 0.0
        nx, ny = dx / d, dy / d
        if A.polygon and B.polygon:
            # two polygons: their vertices now, once for reach and the separation
            pa, pb = self.vertices(A, now), self.vertices(B, now)
            hi = self.reach_points(nx, ny, pa)
            lo = -self.reach_points(-nx, -ny, pb)
        else:
            hi = self.reach(A, nx, ny, now)
            lo = -self.reach(B, -nx, -ny, now)
        spin = A.bound * self.turn_rate(A) + B.bound * self.turn_rate(B)
        tol = self.s.tol
        along = self.clear_root(lo - hi - tol, spin - (nx * (u2 - u1) + ny * (v2 - v1)),
                                math.fabs(nx * (B.ax - A.ax) + ny * (B.ay - A.ay)))
        # and along the best separating axis, which may turn: the norms, |x| + |y|
        if A.polygon and B.polygon:
            sep = self.polygons_separation(A, B, now, pa, pb)
        else:
            sep = self.separation(A, B, now)
        anyway = self.clear_root(sep - tol,
                                 spin + math.fabs(u2 - u1) + math.fabs(v2 - v1),
                                 math.fabs(B.ax - A.ax) + math.fabs(B.ay - A.ay))
        return max(along, anyway)

    def reach(self, b: Body, nx: float, ny: float, now: float) -> float:
        """The largest projection of b on the unit axis (nx, ny) at now."""
        if not b.polygon:
            px, py = self.point_at(b, None, now)
            return nx * px + ny * py + b.r
        best = -math.inf
        for v in b.verts:
            px, py = self.point_at(b, v, now)
            best = max(best, nx * px + ny * py)
        return best

    @staticmethod
    def reach_points(nx: float, ny: float, pts) -> float:
        """reach of a polygon whose vertices now are pts."""
        best = -math.inf
        for px, py in pts:
            best = max(best, nx * px + ny * py)
        return best

    def clear_axes(self, T: Body, P: Body, now: float) -> float:
        """clear_time along each edge normal of P (P does not turn, T does)."""
        _, _, u1, v1, _ = self.state_at(T, now)
        _, _, u2, v2, _ = self.state_at(P, now)
        du, dv, dax, day = u1 - u2, v1 - v2, T.ax - P.ax, T.ay - P.ay
        spin = T.bound * self.turn_rate(T)
        best = 0.0
        for j in range(len(P.verts)):
            ox, oy, off = self.edge_line(P, j, now)
            c = self.clear_root(-self.reach(T, -ox, -oy, now) - off - self.s.tol, spin - (ox * du + oy * dv),
                                math.fabs(ox * dax + oy * day))
            best = max(best, c)
        return best

    @staticmethod
    def clear_root(g: float, r: float, q: float) -> float:
        """The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
        inf when it has none (r <= 0 and q = 0)."""
        if not (g > 0.0):
            return 0.0
        if r > 0.0:
            return 2.0 * g / (r + math.sqrt(r * r + 2.0 * q * g))
        if q > 0.0:
            return (math.sqrt(r * r + 2.0 * q * g) - r) / q
        return math.inf

    @staticmethod
    def _better(best, t, feat, a, b, i, j):
        if t is not None and (best is None or t < best[0]):
            return (t, feat, a, b, i, j)
        return best

    def circle_polygon(self, C: Body, P: Body, now: float, w: float, best):
        for j in range(len(P.verts)):
            t = self.predict_pe(C, P, None, j, now, w, -1, _before(best))
            best = self._better(best, t, PE, C.idx, P.idx, -1, j)
        for k, v in enumerate(P.verts):
            best = self._better(best, self.predict_cc(C, P, v, 0.0, now, w, _before(best)), CC, C.idx, P.idx, -1, k)
        return best

    def window_bound(self, X: Body, Y: Body, now: float, w: float):
        """What every vertex-edge pair of a window shares, X holding the
        vertices and Y the edges: None when the bound does not hold (a turn
        over 1 rad in the window), else (cos and sin of X's angle now, the
        bound's part common to every pair (m), its part per metre of a
        vertex's radius, the same two for the place along an edge, and per
        edge of Y: its outward unit normal now, the gap of X's centre beyond
        its line (m), the margin of the line's offset (m), X's centre along
        the edge's tangent (-ny, nx) now (m), the edge's extent widened by
        the margins (m)).

        The gap g(s) = n(s) . (d(s) + r(s)) - h of a vertex (r: its offset
        from X's centre, |r| = rho, turning at wx) from the line of an edge
        of Y (n: its unit normal, turning at wy; d: X's centre less Y's)
        changes over [0, w] by at most w (|wy| D + V + |wx - wy| rho), since
        |g'| <= |wy| |d| + |d'| + |wx - wy| rho (D >= |d|, V >= |d'| over the
        window); point_edge's polynomial is g with the sin and cos of both
        turns replaced by their Taylor polynomials of order n >= 1, each off
        by at most x^2/2 for a turn x <= 1 rad, so it is within (xn^2 D +
        xr^2 rho) of g (xn = |wy| w, xr = |wx - wy| w).  When |g(0)| exceeds
        both plus the tolerance (first_contact's contact now) and a margin
        of 2^-30 of the sizes and of the angles' lever for every rounding,
        the polynomial keeps the sign of g(0) all through the window: no
        root, no contact (docs/toi.md, "Cost").  Likewise the place
        a(s) = t(s) . (d(s) + r(s)) of the vertex along the edge (t: the
        edge's unit tangent) changes by at most w (|wy| (D + rho) + V +
        |wx| rho): when a(0) lies farther than that beyond the edge's extent
        widened by the tolerance, inside (evaluated on the exact motion)
        refuses every root of the window."""
        x1, y1, u1, v1, ang1 = self.state_at(X, now)
        x2, y2, u2, v2, ang2 = self.state_at(Y, now)
        dx, dy = x1 - x2, y1 - y2
        u, v, ax, ay = u1 - u2, v1 - v2, X.ax - Y.ax, X.ay - Y.ay
        speed = math.sqrt(u * u + v * v)
        acc = math.sqrt(ax * ax + ay * ay)
        d = math.sqrt(dx * dx + dy * dy) + (speed + 0.5 * acc * w) * w
        vel = speed + acc * w
        wy = math.fabs(Y.om)
        wr = math.fabs(X.om - Y.om)
        xn, xr = wy * w, wr * w
        lever = math.fabs(ang1) + math.fabs(ang2) + 8.0
        base = w * (wy * d + vel) + xn * xn * d + self.s.tol + TWO_M30 * (1.0 + lever) * d
        per_rho = w * wr + xr * xr + TWO_M30 * (1.0 + lever)
        abase = w * (wy * d + vel) + self.s.tol + TWO_M30 * (1.0 + lever) * d
        aper_rho = w * (wy + math.fabs(X.om)) + TWO_M30 * (1.0 + lever)
        if not (xn <= 1.0 and xr <= 1.0 and base <= MAX_FLOAT and per_rho <= MAX_FLOAT):
            return None
        cb, sb = math.cos(ang2), math.sin(ang2)
        edges = []
        for ed in Y.verts:
            nx = cb * ed.nx - sb * ed.ny
            ny = sb * ed.nx + cb * ed.ny
            margin = TWO_M30 * (math.fabs(ed.s1) + math.fabs(ed.s2))
            edges.append((nx, ny, nx * dx + ny * dy - ed.h, TWO_M30 * math.fabs(ed.h), -ny * dx + nx * dy,
                          ed.s1 - margin, ed.s2 + margin))
        return math.cos(ang1), math.sin(ang1), base, per_rho, abase, aper_rho, edges

    @staticmethod
    def spares(k, v: Vertex) -> list[bool]:
        """For each edge of window_bound's k: vertex v surely stays far from
        the edge's line, or beside the edge, all through the window."""
        ca, sa, base, per_rho, abase, aper_rho, edges = k
        rx = ca * v.lx - sa * v.ly
        ry = sa * v.lx + ca * v.ly
        lim = base + per_rho * v.rho
        alim = abase + aper_rho * v.rho
        out = []
        for ex, ey, off, slack, along, lo, hi in edges:
            a = along - ey * rx + ex * ry
            out.append(math.fabs(off + ex * rx + ey * ry) > lim + slack or a < lo - alim or a > hi + alim)
        return out

    def pe_variants(self, X: Body, Y: Body, now: float) -> tuple[int, int]:
        """The point_edge variants pe_coefficients picks for X's vertices
        against Y's edges now: (a vertex off X's centre that turns relative
        to the edge, the others: rho 0 after the fold).  A variant reads
        only which effects are zero (orbit, acceleration, the two turns),
        never the positions, phases or the line's offset."""
        x1, y1, u1, v1, _ = self.state_at(X, now)
        x2, y2, u2, v2, _ = self.state_at(Y, now)
        wr = X.om - Y.om
        args = [x1 - x2, u1 - u2, X.ax - Y.ax, y1 - y2, v1 - v2, X.ay - Y.ay, 0.0, wr, 0.0, Y.om, 0.0, 0.0]
        fixed = self.pe_var(*args)
        args[6] = 0.0 if wr == 0.0 else 1.0
        return self.pe_var(*args), fixed

    def vertices_edges(self, A: Body, B: Body, now: float, w: float, best):
        """Every vertex of A against every edge of B within [0, w] after
        now; the pairs window_bound proves apart are counted, not solved."""
        k = self.window_bound(A, B, now, w)
        if k is None:
            for i, v in enumerate(A.verts):
                for j in range(len(B.verts)):
                    t = self.predict_pe(A, B, v, j, now, w, i, _before(best))
                    best = self._better(best, t, PE, A.idx, B.idx, i, j)
            return best
        turning, fixed = self.pe_variants(A, B, now)
        bodies = self.s.bodies
        for i, v in enumerate(A.verts):
            spare = self.spares(k, v)
            spared = fixed if v.rho == 0.0 else turning
            for j in range(len(B.verts)):
                if spare[j]:
                    # far from the line, or beside the edge, all through the window (window_bound):
                    # counted, not solved
                    cover = B.verts[j].cover
                    if not (cover >= 0 and not bodies[cover].gone):
                        if spared < 0:
                            raise SimError("point_edge: the scene uses an effect the generated code leaves out")
                        self.pe_counts[spared] += 1
                        self.stats.features += 1
                    continue
                best = self._better(best, self.predict_pe(A, B, v, j, now, w, i, _before(best)), PE, A.idx, B.idx, i, j)
        return best

    def predict_body(self, b: Body, now: float, skip: Body | None) -> None:
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if o is not skip and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if o is not skip and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)
        if b.sup >= 0 and (self.s.bodies[b.sup].fixed or self.s.bodies[b.sup].asleep):
            self.schedule_support(b, now)     # a carried body moves with its base: no stop, no leave of its own

    def schedule_cell(self, b: Body, now: float) -> None:
        s = self.s
        if b.large or (b.vx == 0.0 and b.vy == 0.0 and b.ax == 0.0 and b.ay == 0.0):
            return
        ulo = now - b.tb
        uhi = s.end - b.tb
        # the margin, or what the cell leaves a body added live that is wider
        # than the scene's widest (it must stay within half a cell of its cell)
        h = s.margin
        room = s.half_cell - b.bound
        if room < h:
            h = room
        best = None
        for axis in (0, 1):
            if axis == 0:
                p, v, a, i, n, origin, size = b.px, b.vx, b.ax, b.cx, s.nx, s.x0, s.cw
            else:
                p, v, a, i, n, origin, size = b.py, b.vy, b.ay, b.cy, s.ny, s.y0, s.ch
            for direction in (1, -1):
                if direction == 1:
                    if i >= n - 1:
                        continue
                    bound = origin + (i + 1) * size + h
                else:
                    if i <= 0:
                        continue
                    bound = origin + i * size - h
                c = [p - bound, v, 0.5 * a]
                if (ulo == 0.0 and c[0] * direction >= 0.0
                        and (v * direction > 0.0 or (v == 0.0 and a * direction > 0.0))):
                    # on the boundary now, or past it (cell_of's quotient and
                    # the boundary's sum origin + i size can round apart), and
                    # moving or accelerating across it: cross at once (the
                    # root finder reports no root at the interval's start,
                    # and none at all for a boundary already behind)
                    if best is None or 0.0 < best[0]:
                        best = (0.0, axis, direction)
                    continue
                lo = ulo
                for _ in range(3):
                    u = smallest_root(c, lo, uhi)
                    if u is None:
                        break
                    if (v + a * u) * direction > 0.0:
                        if best is None or u < best[0]:
                            best = (u, axis, direction)
                        break
                    lo = u
        if best is not None:
            self.push(CellEvent(b.tb + best[0], b.idx, best[1], best[2], b.stamp))
