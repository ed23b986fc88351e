"""Sleeping islands (docs/simulator.md, "Contact model: sleeping
islands"): when a body falls asleep on a grounded one, what it rests on,
and what wakes with a sleeper (a jolt, an input, a body removed or driven
next to it): the sleepers resting on it, going up."""
from __future__ import annotations

import math

from max2code_rt.sim.predict import PE
from max2code_rt.sim.queue import CollisionEvent
from max2code_rt.sim.scene import Body

REST_SLOTS = 4      # slow contacts kept per body (note_rest)
WAKING = -2         # island of the sleepers handle_wake is waking


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def balanced(M: Body, pts: list, fa: float, tol: float) -> bool:
    """Contacts pts = (px, py, mx, my, mu) of M (unit normal m from M to the
    other body) admit a static equilibrium with a margin: every target
    T of `targets` is a combination with coefficients >= 0 of the contact
    rays (per contact -m + mu t and -m - mu t, t = (-my, mx); -m alone when
    mu = 0), each ray written (dx, dy, (p - pM) x d).  By Caratheodory a
    target in the cone of the rays is in the cone of three independent
    ones: the triples i < j < k (rays in order) are tried with Cramer's
    rule until every target is found in one."""
    rays = []
    for (px, py, mx, my, mu) in pts:
        rx = px - M.px
        ry = py - M.py
        if mu > 0.0:
            for (dx, dy) in ((-mx - mu * my, -my + mu * mx), (-mx + mu * my, -my - mu * mx)):
                rays.append((dx, dy, rx * dy - ry * dx))
        else:
            dx = -mx
            dy = -my
            rays.append((dx, dy, rx * dy - ry * dx))
    n = len(rays)
    if n < 3:
        return False
    e = tol / M.bound
    wx = -e * M.fay
    wy = e * M.fax
    tq = fa * tol
    targets = ((-M.fax + wx, -M.fay + wy, 0.0), (-M.fax - wx, -M.fay - wy, 0.0),
               (-M.fax, -M.fay, tq), (-M.fax, -M.fay, -tq))
    found = [False, False, False, False]
    left = 4
    for i in range(n - 2):
        for j in range(i + 1, n - 1):
            cij = _cross(rays[i], rays[j])
            for k in range(j + 1, n):
                cjk = _cross(rays[j], rays[k])
                cki = _cross(rays[k], rays[i])
                d = _dot(rays[i], cjk)
                if not (d > 0.0) and not (d < 0.0):
                    continue
                for q in range(4):
                    if found[q]:
                        continue
                    T = targets[q]
                    li = _dot(T, cjk)
                    lj = _dot(T, cki)
                    lk = _dot(T, cij)
                    if (li < 0.0 or lj < 0.0 or lk < 0.0) if d > 0.0 else (li > 0.0 or lj > 0.0 or lk > 0.0):
                        continue
                    found[q] = True
                    left -= 1
                    if left == 0:
                        return True
    return False


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
        load = M.fax * mx + M.fay * my
        return load > 0.0 and self.slow_touch(M, G, ev, nx, ny, vn, self.s.rest_speed)

    @staticmethod
    def slow_touch(M: Body, G: Body, ev: CollisionEvent, nx: float, ny: float, vn: float, rest: float) -> bool:
        """The contact of ev of awake movable M with G is slow: slow_press
        without the load (a contact across M's free acceleration, a wall a
        box leans on, counts): vn < rest_speed, eM eG (-vn) < rest_speed,
        M's speed across the normal below rest_speed, a polygon M turning
        slower than rest_speed / bound."""
        if M.fixed or M.asleep:
            return False
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        if vn >= rest or M.e * G.e * -vn >= rest:
            return False
        ut = M.vy * mx - M.vx * my
        if ut * ut >= rest * rest:
            return False
        return not M.polygon or math.fabs(M.om) * M.bound < rest

    def note_rest(self, M: Body, G: Body, ev: CollisionEvent, cx: float, cy: float, nx: float, ny: float) -> None:
        """With G grounded, keeps the slow contact of ev at (cx, cy) first among M's last
        REST_SLOTS slow contacts (distinct by the other body and the
        feature: ev's kind, i, j and which side M is), with G's and M's
        positions and angles now: an earlier one with the same key leaves
        its place, the others move down one, the oldest beyond REST_SLOTS
        is dropped."""
        if not self.grounded(G):
            return          # an awake body moves: a contact with it would not hold
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        r = (G.idx, ev.feature, ev.i, ev.j, M.idx == ev.a, cx, cy, mx, my, G.px, G.py, G.ang, M.px, M.py, M.ang)
        old = self.restc.get(M.idx)
        if old is None:
            self.restc[M.idx] = [r]
            return
        for k, o in enumerate(old):
            if o[:5] == r[:5]:
                del old[k]
                break
        old.insert(0, r)
        if len(old) > REST_SLOTS:
            del old[REST_SLOTS]

    def holding(self, M: Body, ev: CollisionEvent, ftol: float) -> list:
        """M's noted slow contacts that still hold, in slot order, but the
        one with ev's key: the other body is not removed, grounded, at the
        position and angle noted (bit for bit), and M has moved less than
        ftol since (its centre, and its angle times its bound)."""
        out = []
        slots = self.restc.get(M.idx)
        if slots is None:
            return out
        side = M.idx == ev.a
        other = ev.b if side else ev.a
        bodies = self.s.bodies
        for r in slots:
            if r[0] == other and r[1] == ev.feature and r[2] == ev.i and r[3] == ev.j and r[4] == side:
                continue
            O = bodies[r[0]]
            if O.gone or not self.grounded(O) or O.px != r[9] or O.py != r[10] or O.ang != r[11]:
                continue
            dx = M.px - r[12]
            dy = M.py - r[13]
            if dx * dx + dy * dy > ftol * ftol or math.fabs(M.ang - r[14]) * M.bound > ftol:
                continue
            out.append(r)
        return out

    def can_sleep_many(self, M: Body, G: Body, ev: CollisionEvent, cx: float, cy: float, nx: float, ny: float,
                       vn: float) -> bool:
        """Awake movable M, in the slow pressing contact of ev with grounded G
        at (cx, cy), falls asleep resting on several contacts
        (docs/simulator.md, "Several contacts"): this contact and M's noted
        ones that still hold (holding) admit a static equilibrium with a
        margin (balanced)."""
        if not self.grounded(G) or not self.slow_press(M, G, ev, nx, ny, vn):
            return False
        fa = math.sqrt(M.fax * M.fax + M.fay * M.fay)
        rest = self.s.rest_speed
        ftol = max(self.s.tol, rest * rest / fa)
        held = self.holding(M, ev, ftol)
        if not held:
            return False
        mx = nx if M.idx == ev.a else -nx
        my = ny if M.idx == ev.a else -ny
        pts = [(cx, cy, mx, my, M.mu * G.mu)]
        bodies = self.s.bodies
        for r in held:
            pts.append((r[5], r[6], r[7], r[8], M.mu * bodies[r[0]].mu))
        return balanced(M, pts, fa, self.s.tol)

    def handle_sleep_many(self, A: Body, G: Body, ev: CollisionEvent, t: float) -> None:
        """A falls asleep on G (handle_sleep); then the body of each noted
        contact that still holds (in slot order) is added to what A rests
        on, so a jolt on any of them wakes A."""
        fa = math.sqrt(A.fax * A.fax + A.fay * A.fay)
        rest = self.s.rest_speed
        held = self.holding(A, ev, max(self.s.tol, rest * rest / fa))
        self.handle_sleep(A, G, t)
        for r in held:
            A.on.append(r[0])

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
        A.on = [G.idx]
        A.stamp += 1
        self.emit_sleep(t, A.idx, G.idx, A.island)
        self.emit_state(A)
        left = []
        self.release(A, t, left)
        self.predict_body(A, t, None)
        self.predict_released(left, t)

    def handle_wake(self, S: Body, t: float) -> None:
        """Sleeper S wakes at t, and with it every sleeper that rests on a
        woken body (the upward closure, marked island WAKING): each (by
        index) gets its free acceleration back, then fresh predictions (a
        pair of woken bodies once)."""
        self.stats.wakes += 1
        self.emit_wake(t, S.idx, S.island)
        bodies = self.s.bodies
        S.island = WAKING
        grown = True
        while grown:
            grown = False
            for b in bodies:
                if b.asleep and b.island != WAKING:
                    for g in b.on:
                        if bodies[g].island == WAKING:
                            b.island = WAKING
                            grown = True
                            break
        island = WAKING
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
        """The sleepers whose bounding circles reach the body's (within the
        tolerance; a body removed, or a fixed one whose velocity an input
        set) wake, each with what rests on it: it may have held them (by
        index; one woken with an earlier one is awake already)."""
        tol = self.s.tol
        for o in self.s.bodies:
            if o.asleep:
                dx = o.px - body.px
                dy = o.py - body.py
                reach = o.bound + body.bound + tol
                if dx * dx + dy * dy <= reach * reach:
                    self.handle_wake(o, t)
