"""Sleeping islands (docs/simulator.md, "Contact model: sleeping
islands"): when a body falls asleep on a grounded one, the island it
joins, and how an island wakes (a jolt, an input, a body removed or
driven next to it)."""
from __future__ import annotations

import math

from max2code_rt.sim.predict import PE
from max2code_rt.sim.queue import CollisionEvent
from max2code_rt.sim.scene import Body


class SleepMixin:
    """Falling asleep and waking."""

    def grounded(self, G: Body) -> bool:
        """A body others can fall asleep on: asleep, or fixed and unmoving."""
        return G.asleep or (G.fixed and self.static(G))

    def at_rest(self, A: Body) -> bool:
        """A body supported by an unmoving body, slower than rest_speed along
        its edge, that static friction would hold there (|at| <= mu load, as
        in slide_accel at u = 0; on a level frictionless edge at = 0): it
        stays where it is.  On a moving support: never (it does not sleep);
        nor on a movable one (carried: grounded is false while it carries)."""
        B = self.s.bodies[A.sup]
        if not self.grounded(B):
            return False
        u = A.vx * A.tx + A.vy * A.ty
        if not (u * u < self.s.rest_speed * self.s.rest_speed):
            return False
        f = A.mu * B.mu * A.load
        return not (A.at > f) and not (A.at < -f)

    def can_sleep(self, M: Body, G: Body, ev: CollisionEvent, nx: float, ny: float, vn: float) -> bool:
        """Awake movable M, one body of the collision ev with grounded G (both
        advanced; (nx, ny) the contact's unit normal from ev.a to ev.b, vn its
        normal speed), falls asleep on G: M's free acceleration presses it
        onto G (load > 0), the contact is slow (vn < rest_speed and
        eM eG (-vn) < rest_speed), M's speed across the normal is below
        rest_speed, and a polygon M turns slower than rest_speed / bound and
        lies on a face: a vertex-edge contact with a neighbour of the vertex
        on the edge's line (`flat`, whichever body has the vertex)."""
        if not self.grounded(G) or not self.slow_press(M, G, ev, nx, ny, vn):
            return False
        if M.polygon:
            if ev.feature != PE or ev.i < 0:
                return False
            load = M.fax * nx + M.fay * ny if M.idx == ev.a else M.fax * -nx + M.fay * -ny
            bodies = self.s.bodies
            V = bodies[ev.a]
            E = bodies[ev.b]
            return self.flat(V, E, ev.i, ev.j, -nx, -ny, load) and self.over_face(M, V, E, ev.i, ev.j, load)
        return True

    def over_face(self, M: Body, V: Body, E: Body, i: int, j: int, load: float) -> bool:
        """M's centre of mass projects inside the support segment of the
        contact of V's vertex i on E's edge j, shrunk by the tolerance: along
        the edge's tangent t, the overlap of the edge [s1, s2] with V's face
        (vertex i and each neighbour on the edge's line within the face
        tolerance of `flat`), all relative to E's centre.  A polygon whose
        centre lies past its support's end would tip: it does not sleep."""
        tx, ty, ox, oy = self.support_frame(E, j)
        ftol = max(self.s.tol, self.s.rest_speed * self.s.rest_speed / load)
        ed = E.verts[j]
        h = ed.h
        px, py = self.point_at(V, V.verts[i], V.tb)
        lo = (px - E.px) * tx + (py - E.py) * ty
        hi = lo
        n = len(V.verts)
        for k in ((i + n - 1) % n, (i + 1) % n):
            px, py = self.point_at(V, V.verts[k], V.tb)
            if (px - E.px) * ox + (py - E.py) * oy - h <= ftol:
                q = (px - E.px) * tx + (py - E.py) * ty
                if q < lo:
                    lo = q
                if q > hi:
                    hi = q
        if ed.s1 > lo:
            lo = ed.s1
        if ed.s2 < hi:
            hi = ed.s2
        c = (M.px - E.px) * tx + (M.py - E.py) * ty
        tol = self.s.tol
        return not (c < lo + tol) and not (c > hi - tol)

    @staticmethod
    def jolted(S: Body) -> bool:
        """A sleeper an impulse has set moving."""
        return S.vx != 0.0 or S.vy != 0.0 or S.om != 0.0

    def slow_press(self, M: Body, G: Body, ev: CollisionEvent, nx: float, ny: float, vn: float) -> bool:
        """The contact of ev of awake movable M with G is slow and presses M
        onto G: M's free acceleration has a positive load along the normal
        from M to G, vn < rest_speed and eM eG (-vn) < rest_speed, M's speed
        across the normal is below rest_speed, and a polygon M turns slower
        than rest_speed / bound."""
        if M.fixed or M.asleep:
            return False
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        rest = self.s.rest_speed
        load = M.fax * mx + M.fay * my
        if not (load > 0.0) or vn >= rest or M.e * G.e * -vn >= rest:
            return False
        ut = M.vy * mx - M.vx * my
        if ut * ut >= rest * rest:
            return False
        return not M.polygon or math.fabs(M.om) * M.bound < rest

    def note_rest(self, M: Body, G: Body, ev: CollisionEvent, cx: float, cy: float, nx: float, ny: float) -> None:
        """Keeps the contact of ev at (cx, cy) as M's last slow pressing
        contact, with G's and M's positions and angles now; the one before,
        when it was with another body, is kept too."""
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        r = (G.idx, cx, cy, mx, my, M.fax * mx + M.fay * my, G.px, G.py, G.ang, M.px, M.py, M.ang)
        old = self.restc.get(M.idx)
        if old is None:
            self.restc[M.idx] = [r, None]
        elif old[0][0] != G.idx:
            self.restc[M.idx] = [r, old[0]]
        else:
            old[0] = r

    def rest_other(self, M: Body, G: Body):
        """M's last slow pressing contact with a body other than G, or None."""
        slots = self.restc.get(M.idx)
        if slots is None:
            return None
        r = slots[0] if slots[0][0] != G.idx else slots[1]
        return r if r is not None and r[0] != G.idx else None

    @staticmethod
    def in_cone(mx: float, my: float, gx: float, gy: float, mu: float) -> bool:
        """A contact force along (gx, gy) at a contact of unit normal (mx, my)
        lies in the friction cone: c > 0 and |m x g| <= mu c."""
        c = mx * gx + my * gy
        s = math.fabs(mx * gy - my * gx)
        return c > 0.0 and not (s > mu * c)

    def can_sleep_two(self, M: Body, G: Body, ev: CollisionEvent, cx: float, cy: float, nx: float, ny: float,
                      vn: float) -> bool:
        """Awake movable M, in the slow pressing contact of ev with grounded G
        at (cx, cy), falls asleep on two supports (docs/simulator.md, "Two
        supports"): its last slow pressing contact with another body G1 that
        is grounded and has not moved since; M has moved less than the face
        tolerance since (its centre, and its angle times its bound); both
        contacts can push along M's free acceleration within their friction
        cones, and M's centre lies strictly between the two contact points
        across that direction (by more than the tolerance)."""
        if not self.grounded(G) or not self.slow_press(M, G, ev, nx, ny, vn):
            return False
        r = self.rest_other(M, G)
        if r is None:
            return False
        G1 = self.s.bodies[r[0]]
        if G1.gone or not self.grounded(G1) or G1.px != r[6] or G1.py != r[7] or G1.ang != r[8]:
            return False
        ftol = max(self.s.tol, self.s.rest_speed * self.s.rest_speed / r[5])
        dx = M.px - r[9]
        dy = M.py - r[10]
        if dx * dx + dy * dy > ftol * ftol or math.fabs(M.ang - r[11]) * M.bound > ftol:
            return False
        fa = math.sqrt(M.fax * M.fax + M.fay * M.fay)
        gx = M.fax / fa
        gy = M.fay / fa
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        if not self.in_cone(r[3], r[4], gx, gy, M.mu * G1.mu) or not self.in_cone(mx, my, gx, gy, M.mu * G.mu):
            return False
        x1 = (r[1] - M.px) * -gy + (r[2] - M.py) * gx
        x2 = (cx - M.px) * -gy + (cy - M.py) * gx
        tol = self.s.tol
        return (x1 < -tol and x2 > tol) or (x1 > tol and x2 < -tol)

    def handle_sleep_two(self, A: Body, G: Body, t: float) -> None:
        """A falls asleep on G (handle_sleep) and on its other support: when
        that one sleeps in another island, the two islands become one (A's)."""
        G1 = self.s.bodies[self.rest_other(A, G)[0]]
        self.handle_sleep(A, G, t)
        if G1.asleep and G1.island != A.island:
            old = G1.island
            for b in self.s.bodies:
                if b.asleep and b.island == old:
                    b.island = A.island

    def handle_sleep(self, A: Body, G: Body, t: float) -> None:
        """A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0)
        in G's island, or in a new one numbered A's index when G is fixed.
        Its awake neighbours are predicted against it again."""
        self.stats.sleeps += 1
        A.rest = A.sup if A.sup >= 0 and self.s.bodies[A.sup].fixed else -1
        if A.sup >= 0:
            self.end_support(A)
        A.vx = 0.0
        A.vy = 0.0
        A.om = 0.0
        A.ax = 0.0
        A.ay = 0.0
        A.asleep = True
        A.island = G.island if G.asleep else A.idx
        A.stamp += 1
        self.emit_sleep(t, A.idx, G.idx, A.island)
        self.emit_state(A)
        left = []
        self.release(A, t, left)
        self.predict_body(A, t, None)
        self.predict_released(left, t)

    def handle_wake(self, S: Body, t: float) -> None:
        """S's island wakes at t: every member (by index) gets its free
        acceleration back, then fresh predictions (a pair of members once)."""
        self.stats.wakes += 1
        island = S.island
        self.emit_wake(t, S.idx, island)
        bodies = self.s.bodies
        for b in bodies:
            if b.asleep and b.island == island:
                self.rebase(b, t)
                b.asleep = False
                b.rest = -1
                b.ax = b.fax
                b.ay = b.fay
                b.stamp += 1
                self.emit_state(b)
        left = []
        for b in bodies:
            if b.island == island:
                self.release(b, t, left)       # bodies sliding on a member leave it: it may move
        for b in bodies:
            if b.island == island:
                self.predict_woken(b, t, island)
        self.predict_released(left, t)
        for b in bodies:
            if b.island == island:
                b.island = -1

    def predict_woken(self, b: Body, now: float, island: int) -> None:
        """predict_body for a member of a waking island: a pair of two
        members is predicted by the one with the smaller index."""
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if not (o.island == island and o.idx < b.idx) and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if not (o.island == island and o.idx < b.idx):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)

    def wake_touching(self, body: Body, t: float) -> None:
        """The islands of the sleepers whose bounding circles reach the
        body's (within the tolerance; a body removed, or a fixed one whose
        velocity an input set) wake: it may have held them (by index; a
        woken island's other members are awake already)."""
        tol = self.s.tol
        for o in self.s.bodies:
            if o.asleep:
                dx = o.px - body.px
                dy = o.py - body.py
                reach = o.bound + body.bound + tol
                if dx * dx + dy * dy <= reach * reach:
                    self.handle_wake(o, t)
