"""A contact's response (docs/simulator.md, "Impulse"): where and along
which normal two bodies touch, whether they approach or are pressed, and
the impulse: frictionless for a fast contact, a hop for a slow pressed
one, along their edges for two bodies held on their supports, and held
as fixed for a sleeper until the impulse would jolt it."""
from __future__ import annotations

import math

from max2code_rt.sim.predict import CC
from max2code_rt.sim.scene import Body


class ContactMixin:
    """Contact frame, normal speed, impulses."""

    def contact_frame(self, t: float, feature: int, A: Body, B: Body, i: int, j: int, bang: float | None = None):
        """Contact point (cx, cy) and unit normal (nx, ny) from A to B of a
        feature at t (both bodies advanced to t, or B's angle at t given as
        bang: the TOI library's bodies stay at their time 0)."""
        vA = A.verts[i] if i >= 0 else None
        if feature == CC:
            ax_, ay_ = self.point_at(A, None, t)
            bx_, by_ = self.point_at(B, B.verts[j] if j >= 0 else None, t)
            dx, dy = bx_ - ax_, by_ - ay_
            dist = math.sqrt(dx * dx + dy * dy)
            if dist > 0.0:
                nx, ny = dx / dist, dy / dist
            else:
                nx, ny = 1.0, 0.0
            cx, cy = ax_ + A.r * nx, ay_ + A.r * ny
        else:
            px, py = self.point_at(A, vA, t)
            th = (B.ang if bang is None else bang) + B.verts[j].psi
            nx, ny = -math.cos(th), -math.sin(th)       # from A to B: against the edge's outward normal
            rad = A.r if vA is None else 0.0
            cx, cy = px + rad * nx, py + rad * ny
        return cx, cy, nx, ny

    @staticmethod
    def pressed(A: Body, B: Body, nx: float, ny: float) -> bool:
        """The bodies' accelerations push them together along the normal
        (n from A to B): the relative normal acceleration of the centres is
        negative.  (Centripetal terms of turning bodies are left out.)"""
        return (B.ax - A.ax) * nx + (B.ay - A.ay) * ny < 0.0

    def closing(self, A: Body, B: Body, feature: int, i: int, j: int) -> bool:
        """The gap polynomial of the contact's feature (feature, i, j as in a
        CollisionEvent: the one that predicted it), taken again at the
        contact (A's time: both advanced), predicts this contact now
        (touching_now: approaching, c1 < 0, or c2 < 0 and closing again
        before the gap exceeds its kappa).  Its second derivative has the
        centripetal terms of a turn, which `pressed` leaves out."""
        now = A.tb
        if feature == CC:
            vb = B.verts[j] if j >= 0 else None
            rb = B.r if vb is None else 0.0
            c = self.circles_gap(self.circle_params(A, now, None), A.r, self.circle_params(B, now, vb), rb)
            tol = self.s.tol
            kappa = tol * (2.0 * (A.r + rb) + tol)
        else:
            if i >= 0:
                v = A.verts[i]
                c = self.pe_coefficients(A, B, v.rho, v.beta, 0.0, j, now)
            else:
                c = self.pe_coefficients(A, B, A.orbit, A.ophase, A.r, j, now)
            kappa = self.s.tol
        return self.touching_now(c, len(c) - 1, kappa)

    @staticmethod
    def normal_speed(A: Body, B: Body, cx: float, cy: float, nx: float, ny: float) -> float:
        """Normal relative velocity (B's against A's, along n from A to B) of
        the material points at the contact: negative when approaching."""
        uax = A.vx - A.om * (cy - A.py)
        uay = A.vy + A.om * (cx - A.px)
        ubx = B.vx - B.om * (cy - B.py)
        uby = B.vy + B.om * (cx - B.px)
        return (ubx - uax) * nx + (uby - uay) * ny

    def contact_impulse(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                        feature: int, i: int, j: int) -> float:
        """The impulse of a contact of the feature (feature, i, j) at (cx, cy)
        with normal (nx, ny) from A to B (both advanced to the contact time):
        0.0 when the material points do not approach and are not pressed
        together, else the normal impulse j (velocities changed).  A fast
        contact is frictionless and leaves at sep = max(e |vn|, min(|vn|,
        rest_speed)); a slow pressed one hops (`hop`).  When the material
        points do not approach, the centres' accelerations do not press them
        and a body of the pair turns, the feature's gap polynomial decides
        whether they are pressed (`closing`: the turn closes the gap, which
        would otherwise predict the same contact again at once).  Never adds
        energy (docs/simulator.md, Impulse)."""
        vn = self.normal_speed(A, B, cx, cy, nx, ny)
        rest = self.s.rest_speed
        press = self.pressed(A, B, nx, ny)
        if not press and not (vn < 0.0) and (self.turn_rate(A) > 0.0 or self.turn_rate(B) > 0.0):
            press = self.closing(A, B, feature, i, j)
        if press and -vn < rest:
            return self.hop(A, B, cx, cy, nx, ny, vn)
        imp = 0.0
        if vn < 0.0:
            ran = (cx - A.px) * ny - (cy - A.py) * nx
            rbn = (cx - B.px) * ny - (cy - B.py) * nx
            k = A.inv_m + B.inv_m + A.inv_i * ran * ran + B.inv_i * rbn * rbn
            e = A.e * B.e
            sep = max(e * -vn, min(-vn, rest))
            imp = (sep - vn) / k
            A.vx = A.vx - imp * A.inv_m * nx
            A.vy = A.vy - imp * A.inv_m * ny
            A.om = A.om - imp * A.inv_i * ran
            B.vx = B.vx + imp * B.inv_m * nx
            B.vy = B.vy + imp * B.inv_m * ny
            B.om = B.om + imp * B.inv_i * rbn
        return imp

    def hop(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float, vn: float) -> float:
        """A slow pressed contact (pressed, -vn < rest_speed): the bodies
        separate at hop along n, paid from their relative motion at the
        contact, so the pair's energy stays what it was: hop = rest_speed
        when kn Q pays it, else sqrt(kn Q), but at least rest_speed / 32 (a
        pair nearly at rest on each other: the energy that adds is paid from
        the pair's common motion, `pay_floor`, else the hop sets `unpaid`).  With u = (vn, vt) the relative velocity of the material points
        in the frame (n, t), t = (-ny, nx), and K the contact's 2x2 inverse
        mass matrix (kn, knt; knt, kt), the pair's energy relative to its
        centre is Q / 2, Q = u . K^-1 u; the new relative velocity is
        (hop, x) with the same Q (x on vt's side of knt hop / kn), through
        the impulse P = K^-1 (u' - u) (normal part jn, tangential jt).
        Returns jn."""
        tx, ty = -ny, nx
        uax = A.vx - A.om * (cy - A.py)
        uay = A.vy + A.om * (cx - A.px)
        ubx = B.vx - B.om * (cy - B.py)
        uby = B.vy + B.om * (cx - B.px)
        vt = (ubx - uax) * tx + (uby - uay) * ty
        ran = (cx - A.px) * ny - (cy - A.py) * nx
        rbn = (cx - B.px) * ny - (cy - B.py) * nx
        rat = (cx - A.px) * ty - (cy - A.py) * tx
        rbt = (cx - B.px) * ty - (cy - B.py) * tx
        m = A.inv_m + B.inv_m
        kn = m + A.inv_i * ran * ran + B.inv_i * rbn * rbn
        kt = m + A.inv_i * rat * rat + B.inv_i * rbt * rbt
        knt = A.inv_i * ran * rat + B.inv_i * rbn * rbt
        det = kn * kt - knt * knt
        q = (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det
        cap = kn * q
        rest = self.s.rest_speed
        floor = 0.03125 * rest
        if cap >= rest * rest:
            hop = rest
        elif cap >= floor * floor:
            hop = math.sqrt(cap)
        else:
            hop = floor
        d = det * (cap - hop * hop)
        root = math.sqrt(d) if d > 0.0 else 0.0
        mid = knt * hop
        if vt * kn >= mid:
            x = (mid + root) / kn
        else:
            x = (mid - root) / kn
        dn = hop - vn
        dt = x - vt
        jn = (kt * dn - knt * dt) / det
        jt = (kn * dt - knt * dn) / det
        px = jn * nx + jt * tx
        py = jn * ny + jt * ty
        A.vx = A.vx - px * A.inv_m
        A.vy = A.vy - py * A.inv_m
        A.om = A.om - (jn * ran + jt * rat) * A.inv_i
        B.vx = B.vx + px * B.inv_m
        B.vy = B.vy + py * B.inv_m
        B.om = B.om + (jn * rbn + jt * rbt) * B.inv_i
        if cap < floor * floor and not self.pay_floor(A, B, (floor * floor - cap) / kn):
            self.unpaid = True
        return jn

    @staticmethod
    def pay_floor(A: Body, B: Body, need: float) -> bool:
        """A hop at the floor speed adds dE = need / 2 to the pair's energy
        (need = (floor^2 - cap) / kn): it is paid from the pair's common
        motion, the velocity V of its centre of mass (mass M), which an
        equal change of both velocities scales by f = sqrt(1 - need / (M
        V^2)) (M V^2 f^2 / 2 = M V^2 / 2 - dE) and which leaves their relative
        motion, hence the hop, untouched.  Not when a body of the pair is
        held (fixed, or a sleeper held as fixed) or the common motion cannot
        pay it (M V^2 <= need): False, the hop then adds dE (`unpaid`)."""
        if A.inv_m == 0.0 or B.inv_m == 0.0:
            return False
        ma = 1.0 / A.inv_m
        mb = 1.0 / B.inv_m
        mass = ma + mb
        vx = (ma * A.vx + mb * B.vx) / mass
        vy = (ma * A.vy + mb * B.vy) / mass
        e2 = mass * (vx * vx + vy * vy)
        if not (e2 > need):
            return False
        f = math.sqrt(1.0 - need / e2)
        dx = vx * f - vx
        dy = vy * f - vy
        A.vx = A.vx + dx
        A.vy = A.vy + dy
        B.vx = B.vx + dx
        B.vy = B.vy + dy
        return True

    @staticmethod
    def along(b: Body, nx: float, ny: float) -> float:
        """n . t of a supported body's edge tangent t (0 for a fixed body)."""
        if b.sup < 0:
            return 0.0
        return nx * b.tx + ny * b.ty

    def held(self, A: Body, B: Body, nx: float, ny: float, vn: float) -> bool:
        """A slow contact of bodies held on their supports: each supported
        (on a fixed body: a carried body is not) or fixed, approaching (vn < 0) slower than rest_speed, not pressed,
        and an impulse along their edges can change vn (kh > 0)."""
        bodies = self.s.bodies
        if not ((A.fixed or (A.sup >= 0 and bodies[A.sup].fixed)) and (B.fixed or (B.sup >= 0 and bodies[B.sup].fixed))):
            return False
        if not (vn < 0.0) or not (-vn < self.s.rest_speed) or self.pressed(A, B, nx, ny):
            return False
        ka = self.along(A, nx, ny)
        kb = self.along(B, nx, ny)
        return A.inv_m * ka * ka + B.inv_m * kb * kb > 0.0

    def held_impulse(self, A: Body, B: Body, nx: float, ny: float, vn: float) -> float:
        """The normal impulse j of a held contact (held): each supported body
        takes only its part along its support's edge, dv = -+ j (n . t) t / m,
        and keeps its support (the support's reaction takes the rest and does
        no work); the normal speed leaves at sep = max(e |vn|, min(|vn|,
        rest_speed)) = |vn| (slow), through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.
        The friction of each is set again for its new speed relative to its
        support (slide_accel; support_relative: the support may move)."""
        ka = self.along(A, nx, ny)
        kb = self.along(B, nx, ny)
        k = A.inv_m * ka * ka + B.inv_m * kb * kb
        e = A.e * B.e
        sep = max(e * -vn, min(-vn, self.s.rest_speed))
        imp = (sep - vn) / k
        if A.sup >= 0:
            d = imp * A.inv_m * ka
            A.vx = A.vx - d * A.tx
            A.vy = A.vy - d * A.ty
            self.slide_accel(A, self.support_relative(A)[1])
        if B.sup >= 0:
            d = imp * B.inv_m * kb
            B.vx = B.vx + d * B.tx
            B.vy = B.vy + d * B.ty
            self.slide_accel(B, self.support_relative(B)[1])
        return imp

    def sleeper_impulse(self, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                        feature: int, i: int, j: int) -> float:
        """The impulse of a contact of A and B, one of them (S) asleep: first
        with S held as if fixed (its 1/m and 1/I zero); when that impulse
        would change the normal speed of S's material point by less than
        rest_speed, j (1/mS + (rS x n)^2 / IS) < rest_speed, it stands (S
        stays asleep, unchanged: a gentle touch); else the other body's
        velocity is restored and the full impulse is applied (S moves:
        `jolted`, it wakes with what rests on it).  When the other body is fixed (it moves
        or turns: a sleeper is never predicted against an unmoving one) S
        cannot be held (the pair would have no mass): the full impulse at
        once.  Returns the impulse applied."""
        S = A if A.asleep else B
        M = B if A.asleep else A
        if M.fixed:
            return self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)
        vx, vy, om = M.vx, M.vy, M.om
        inv_m, inv_i = S.inv_m, S.inv_i
        S.inv_m = 0.0
        S.inv_i = 0.0
        self.unpaid = False
        imp = self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)
        S.inv_m = inv_m
        S.inv_i = inv_i
        rsn = (cx - S.px) * ny - (cy - S.py) * nx
        if (imp * (S.inv_m + S.inv_i * rsn * rsn) < self.s.rest_speed and not self.unpaid) or self.held_now(S):
            return imp
        M.vx, M.vy, M.om = vx, vy, om
        return self.contact_impulse(A, B, cx, cy, nx, ny, feature, i, j)
