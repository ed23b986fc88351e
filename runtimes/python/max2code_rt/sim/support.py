"""Support (docs/simulator.md, "Contact model: supported, sliding,
friction"): a movable body resting and sliding on an edge of a fixed
polygon, with Coulomb friction, or carried at rest on a movable polygon
that does not turn ("Carried bodies"); when such a body leaves, and what
it carries leaves with it.  A supported or carried body's motion stays
p + v dt + a dt^2/2, so every generated equation predicts it unchanged."""
from __future__ import annotations

import math

from max2code_rt.roots import smallest_root
from max2code_rt.sim.predict import PE
from max2code_rt.sim.queue import LeaveEvent, StopEvent
from max2code_rt.sim.scene import Body


class SupportMixin:
    """Entering, sliding on and leaving a support or a carrier."""

    @staticmethod
    def support_frame(B: Body, j: int):
        """Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j
        of B in the world (B does not turn)."""
        ed = B.verts[j]
        c = math.cos(B.ang)
        s = math.sin(B.ang)
        ox = c * ed.nx - s * ed.ny
        oy = s * ed.nx + c * ed.ny
        return -oy, ox, ox, oy

    @staticmethod
    def static(B: Body) -> bool:
        return B.vx == 0.0 and B.vy == 0.0 and B.ax == 0.0 and B.ay == 0.0 and B.om == 0.0

    def can_support(self, A: Body, B: Body, feature: int, i: int, j: int, vn: float) -> bool:
        """A point-edge contact of movable A on edge j of a fixed polygon B
        that does not turn (it may translate) becomes support, everything
        relative to B (docs/simulator.md, Contact model); both advanced."""
        if feature != PE or A.fixed or not B.fixed or B.om != 0.0:
            return False
        return self.supportable(A, B, i, j, vn)

    def can_ride(self, A: Body, B: Body, feature: int, i: int, j: int, vn: float) -> bool:
        """A point-edge contact of movable A on edge j of a sleeping polygon B
        that fell asleep supported on a fixed body (B.rest) becomes support
        on B, as on a fixed body that does not move (docs/simulator.md,
        "Sliding on a sleeping base"), when B's resting contact holds the
        force A's sliding puts on B besides B's other riders (`base_holds`)."""
        if feature != PE or A.fixed or not B.asleep or B.rest < 0 or not B.polygon:
            return False
        if not self.supportable(A, B, i, j, vn):
            return False
        tx, ty, ox, oy = self.support_frame(B, j)
        u = A.vx * tx + A.vy * ty
        a = self.friction_accel(A.fax * tx + A.fay * ty, A.mu * B.mu * -(A.fax * ox + A.fay * oy), u)
        return self.base_holds(B, -(a * tx - A.fax) / A.inv_m, -(a * ty - A.fay) / A.inv_m)

    def base_holds(self, B: Body, px: float, py: float) -> bool:
        """Sleeping base B (at rest on edge frame (B.tx, B.ty) of fixed body
        B.rest) stays at rest under its free acceleration, the force
        (px, py) and the force of each body supported on it (by index, its
        reaction -m (a - fa)): the resting contact's normal force
        n = -(mB faB + P) . o is positive and its tangential force
        t = -(mB faB + P) . t lies within static friction, |t| <= mu n."""
        bodies = self.s.bodies
        if B.carry > 0:
            for R in bodies:
                if R.sup == B.idx:
                    px = px - (R.ax - R.fax) / R.inv_m
                    py = py - (R.ay - R.fay) / R.inv_m
        mB = 1.0 / B.inv_m
        fx = mB * B.fax + px
        fy = mB * B.fay + py
        n = -(fx * B.ty - fy * B.tx)
        t = -(fx * B.tx + fy * B.ty)
        f = B.mu * bodies[B.rest].mu * n
        return n > 0.0 and not (t > f) and not (t < -f)

    def supportable(self, A: Body, B: Body, i: int, j: int, vn: float) -> bool:
        """The checks of can_support after the bodies' kinds: pressed onto
        edge j, slow, over the edge and not leaving it, a polygon flat on it."""
        tx, ty, ox, oy = self.support_frame(B, j)
        load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        rest = self.s.rest_speed
        if not (load > 0.0) or vn >= rest or A.e * B.e * -vn >= rest:
            return False
        ed = B.verts[j]
        q = (A.px - B.px) * tx + (A.py - B.py) * ty
        if q < ed.s1 or q > ed.s2:
            return False
        # at an end of the edge (within the tolerance) and moving past it: it
        # is leaving (a support would end at once, again and again)
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        tol = self.s.tol
        if (u > 0.0 and q >= ed.s2 - tol) or (u < 0.0 and q <= ed.s1 + tol):
            return False
        if A.polygon:
            if math.fabs(A.om) * A.bound >= rest:
                return False
            return self.flat(A, B, i, j, ox, oy, load)
        return True

    def flat(self, A: Body, B: Body, i: int, j: int, ox: float, oy: float, load: float) -> bool:
        """A neighbour of A's vertex i lies on edge j's line within the face
        tolerance max(tol, rest_speed^2 / load): A rests on a face."""
        ftol = max(self.s.tol, self.s.rest_speed * self.s.rest_speed / load)
        n = len(A.verts)
        h = B.verts[j].h
        for k in ((i + n - 1) % n, (i + 1) % n):
            px, py = self.point_at(A, A.verts[k], A.tb)
            if (px - B.px) * ox + (py - B.py) * oy - h <= ftol:
                return True
        return False

    def enter_support(self, A: Body, B: Body, j: int) -> None:
        """A (advanced to now, as B) keeps only its velocity relative to B
        along the edge, stops turning, and from now on accelerates relative
        to B along the edge only."""
        tx, ty, ox, oy = self.support_frame(B, j)
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        if self.static(B):
            A.vx = u * tx
            A.vy = u * ty
        else:
            A.vx = B.vx + u * tx
            A.vy = B.vy + u * ty
        if A.polygon:
            A.om = 0.0
        A.sup = B.idx
        A.sup_edge = j
        A.tx = tx
        A.ty = ty
        A.load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        A.at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        if not B.fixed:
            B.carry += 1
        self.slide_accel(A, u)

    def slide_accel(self, A: Body, u: float) -> None:
        """Acceleration of supported A with tangential speed u relative to
        its support B: the relative free acceleration along the edge less
        Coulomb friction mu |a_n| against the relative motion; at relative
        rest, none while friction can hold it; plus B's acceleration when B
        moves."""
        B = self.s.bodies[A.sup]
        a = self.friction_accel(A.at, A.mu * B.mu * A.load, u)
        if self.static(B):
            A.ax = a * A.tx
            A.ay = a * A.ty
        else:
            A.ax = B.ax + a * A.tx
            A.ay = B.ay + a * A.ty

    @staticmethod
    def friction_accel(at: float, f: float, u: float) -> float:
        """Acceleration along an edge of a body sliding at u relative to it:
        the free part at less Coulomb friction f (mu times the load) against
        the motion; at relative rest none while static friction holds."""
        if u > 0.0:
            return at - f
        if u < 0.0:
            return at + f
        if at > f:
            return at - f
        if at < -f:
            return at + f
        return 0.0

    def end_support(self, A: Body) -> None:
        """A's support (or carrier) ends: its free acceleration again."""
        B = self.s.bodies[A.sup]
        if not B.fixed:
            B.carry -= 1
        A.ax = A.fax
        A.ay = A.fay
        A.sup = -1
        A.sup_edge = -1

    def can_carry(self, A: Body, B: Body, feature: int, i: int, j: int, vn: float) -> bool:
        """A point-edge contact of movable A on edge j of a movable polygon B
        that does not turn and is itself supported or carried (its motion a
        polynomial: constant acceleration) becomes carrying (docs/simulator.md,
        "Carried bodies"); both advanced.  As can_support, everything relative
        to B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn)
        < rest_speed), A's centre over the edge; and A at relative rest along
        it (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds
        it (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A
        (no loop), and |vB|^2 <= |vA|^2: taking B's velocity never raises
        A's kinetic energy.  A polygon also turns slower than rest_speed /
        bound and lies on a face (`flat`)."""
        if feature != PE or A.fixed or B.fixed or not B.polygon or B.om != 0.0 or B.sup < 0:
            return False
        bodies = self.s.bodies
        k = B.sup
        while k >= 0:
            if k == A.idx:
                return False
            k = bodies[k].sup
        tx, ty, ox, oy = self.support_frame(B, j)
        load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        rest = self.s.rest_speed
        if not (load > 0.0) or vn >= rest or A.e * B.e * -vn >= rest:
            return False
        ed = B.verts[j]
        q = (A.px - B.px) * tx + (A.py - B.py) * ty
        if q < ed.s1 or q > ed.s2:
            return False
        u = (A.vx - B.vx) * tx + (A.vy - B.vy) * ty
        if not (u * u < rest * rest):
            return False
        at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        f = A.mu * B.mu * load
        if at > f or at < -f:
            return False
        if B.vx * B.vx + B.vy * B.vy > A.vx * A.vx + A.vy * A.vy:
            return False
        if A.polygon:
            if math.fabs(A.om) * A.bound >= rest:
                return False
            return self.flat(A, B, i, j, ox, oy, load)
        return True

    def enter_carried(self, A: Body, B: Body, j: int) -> None:
        """A (advanced to now, as B) moves with B from now on: B's velocity
        and acceleration exactly (its offset from B constant), no turn."""
        tx, ty, ox, oy = self.support_frame(B, j)
        A.vx = B.vx
        A.vy = B.vy
        if A.polygon:
            A.om = 0.0
        A.sup = B.idx
        A.sup_edge = j
        A.tx = tx
        A.ty = ty
        A.load = -((A.fax - B.ax) * ox + (A.fay - B.ay) * oy)
        A.at = (A.fax - B.ax) * tx + (A.fay - B.ay) * ty
        A.ax = B.ax
        A.ay = B.ay
        B.carry += 1

    def leave(self, A: Body, t: float, skip: Body | None, left: list) -> None:
        """A leaves its support or carrier at t (E leave, its state: world
        velocity kept, free acceleration), then what A carries, depth-first
        (release); each appended to left with the body its prediction
        skips (predict_released)."""
        self.stats.leaves += 1
        self.rebase(A, t)
        sup, edge = A.sup, A.sup_edge
        self.end_support(A)
        A.stamp += 1
        self.emit_support_end("leave", t, A.idx, sup, edge)
        self.emit_state(A)
        left.append((A, skip))
        self.release(A, t, left)

    def release(self, B: Body, t: float, left: list) -> None:
        """B's motion changes at t: every body B carries leaves (by index,
        each with what it carries: leave), skipping B in its prediction."""
        if B.carry == 0:
            return
        for A in self.s.bodies:
            if A.sup == B.idx:
                self.leave(A, t, B, left)

    def predict_released(self, left: list, t: float) -> None:
        """Predict the bodies that left (leave), in the order they left,
        each but against the body it skips (already predicted with it)."""
        for A, skip in left:
            self.predict_body(A, t, skip)

    def support_relative(self, b: Body):
        """Supported b's motion relative to its support B along the edge, at
        b's time: (q, u, a), q the centre's coordinate along the tangent
        from B's centre, u, a its speed and acceleration."""
        B = self.s.bodies[b.sup]
        bx, by, bvx, bvy, _ = self.state_at(B, b.tb)
        q = (b.px - bx) * b.tx + (b.py - by) * b.ty
        u = (b.vx - bvx) * b.tx + (b.vy - bvy) * b.ty
        a = (b.ax - B.ax) * b.tx + (b.ay - B.ay) * b.ty
        return q, u, a

    def schedule_support(self, b: Body, now: float) -> None:
        """A supported body's stop (its tangential speed relative to the
        support reaches zero) and leave (its centre, projected on the
        edge, reaches an end) events."""
        q, u, a = self.support_relative(b)
        if u != 0.0 and a != 0.0 and (u > 0.0) != (a > 0.0):
            self.push(StopEvent(b.tb + -u / a, b.idx, b.stamp))
        ed = self.s.bodies[b.sup].verts[b.sup_edge]
        hi = self.s.end - b.tb
        s2 = self.first_crossing(q - ed.s2, u, a, 1, 0.0, hi)
        s1 = self.first_crossing(q - ed.s1, u, a, -1, 0.0, hi)
        if s1 is not None and (s2 is None or s1 < s2):
            s2 = s1
        if s2 is not None:
            self.push(LeaveEvent(b.tb + s2, b.idx, b.stamp))

    @staticmethod
    def first_crossing(p: float, v: float, a: float, direction: int, lo: float, hi: float) -> float | None:
        """The first u in [lo, hi] where p + v u + a u^2 / 2 crosses zero
        moving in the direction (+1 up, -1 down)."""
        c = [p, v, 0.5 * a]
        for _ in range(3):
            u = smallest_root(c, lo, hi)
            if u is None:
                return None
            if (v + a * u) * direction > 0.0:
                return u
            lo = u
        return None
