"""Simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
contacts"): a contact met again at the instant it was handled is solved
together with the contacts handled at that instant that reach it, by
sequential impulses that never add kinetic energy."""
from __future__ import annotations

import math

from max2code_rt.sim.queue import CollisionEvent
from max2code_rt.sim.scene import Body
from max2code_rt.sim.world import Contact

# simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
# contacts"): how many times one contact is handled at one instant before it
# and the contacts that reach it are solved together; the most sweeps of the
# cluster's sequential impulses, and the sweep that ends them: no impulse in
# it changed a normal speed by more than CLUSTER_TOL rest_speed
CLUSTER_REPEATS = 64
# a contact met CLUSTER_REPEATS + CLUSTER_JAM times at one instant (its
# cluster solved CLUSTER_JAM times there and met again) jams its cluster: the
# movers come to rest and fall asleep, held until the instant ends
CLUSTER_JAM = 4
CLUSTER_SWEEPS = 100
CLUSTER_TOL = 1e-9
# the separation speed (times rest_speed) of a cluster's contact that nothing
# presses: above the rounding of a normal speed, so that it is not met again at once
CLUSTER_APART = 2.0 ** -20
# the angle (rad) within which one push holds a free acceleration (wedged)
HOLD_TOL = 1e-9
# a body's part in a cluster's solve: held (fixed, or asleep: infinite mass),
# free, or sliding on a fixed body's edge (moves along the edge only)
HELD, FREE, SLIDER = 0, 1, 2


class ClusterMixin:
    """The contacts handled at one instant (self.touched) and their joint solve."""

    def touch(self, t: float, a: int, b: int, feature: int, i: int, j: int) -> None:
        """Count a contact handled at t (an E collision or E support line)."""
        if t != self.touched_t:
            self.touched_t = t
            self.touched = []
        for c in self.touched:
            if c[0] == a and c[1] == b and c[2] == feature and c[3] == i and c[4] == j:
                c[5] += 1
                return
        self.touched.append([a, b, feature, i, j, 1])

    def jam_count(self, ev: CollisionEvent) -> int:
        """How many times the collision's contact was handled at this instant."""
        if ev.t != self.touched_t:
            return 0
        for c in self.touched:
            if c[0] == ev.a and c[1] == ev.b and c[2] == ev.feature and c[3] == ev.i and c[4] == ev.j:
                return c[5]
        return 0

    def held_now(self, S: Body) -> bool:
        """A sleeper a jam put to sleep at the current instant: no touch wakes it before the instant ends."""
        return self.jammed_t == self.last_t and S.idx in self.jammed

    def repeated(self, ev: CollisionEvent) -> bool:
        """The collision's contact (a, b, feature, i, j) was handled
        CLUSTER_REPEATS times already at this instant: other contacts keep
        undoing its impulse (a settling pile meets one contact up to 32
        times at one instant and goes on: ball-pit.json)."""
        if ev.t != self.touched_t:
            return False
        for c in self.touched:
            if c[0] == ev.a and c[1] == ev.b and c[2] == ev.feature and c[3] == ev.i and c[4] == ev.j:
                return c[5] >= CLUSTER_REPEATS
        return False

    @staticmethod
    def joins(b: Body) -> bool:
        """A body that links a cluster's contacts: movable and awake (fixed
        bodies and sleepers are held: the cluster ends at them)."""
        return not b.fixed and not b.asleep

    def cluster(self, ev: CollisionEvent) -> list:
        """The contacts handled at this instant (touched, in the order first
        handled) that reach the collision's bodies through bodies that join,
        each as (A, B, feature, i, j)."""
        bodies = self.s.bodies
        inside = []
        for x in (ev.a, ev.b):
            if self.joins(bodies[x]):
                inside.append(x)
        grow = True
        while grow:
            grow = False
            for c in self.touched:
                if c[0] in inside or c[1] in inside:
                    for x in (c[0], c[1]):
                        if x not in inside and self.joins(bodies[x]):
                            inside.append(x)
                            grow = True
        out = []
        for c in self.touched:
            if c[0] in inside or c[1] in inside:
                out.append((bodies[c[0]], bodies[c[1]], c[2], c[3], c[4]))
        return out

    def part(self, b: Body) -> int:
        """b's part in a cluster's solve: HELD (fixed or asleep), SLIDER
        (supported on a fixed body: it moves along the edge only, as in
        held_impulse) or FREE."""
        if b.fixed or b.asleep:
            return HELD
        if b.sup >= 0 and self.s.bodies[b.sup].fixed:
            return SLIDER
        return FREE

    def give(self, b: Body, nx: float, ny: float, rn: float) -> float:
        """How much a unit impulse along n at the contact (rn: the contact's
        arm across n) changes b's normal speed there."""
        part = self.part(b)
        if part == HELD:
            return 0.0
        if part == SLIDER:
            k = nx * b.tx + ny * b.ty
            return b.inv_m * k * k
        return b.inv_m + b.inv_i * rn * rn

    def nudge(self, b: Body, j: float, nx: float, ny: float, rn: float) -> None:
        """An impulse j along n on b at the contact (rn its arm across n)."""
        part = self.part(b)
        if part == HELD:
            return
        if part == SLIDER:
            d = j * b.inv_m * (nx * b.tx + ny * b.ty)
            b.vx = b.vx + d * b.tx
            b.vy = b.vy + d * b.ty
            return
        b.vx = b.vx + j * b.inv_m * nx
        b.vy = b.vy + j * b.inv_m * ny
        b.om = b.om + j * b.inv_i * rn

    def sweeps(self, rows: list, acc: list, target: list) -> None:
        """Sequential impulses over the cluster's contacts (rows, in order):
        each contact's accumulated normal impulse acc[k] moves so that its
        normal speed becomes target[k], but never below zero (a contact only
        pushes); sweep after sweep until no impulse of a sweep changed a
        normal speed by more than CLUSTER_TOL rest_speed, at most
        CLUSTER_SWEEPS sweeps."""
        tol = CLUSTER_TOL * self.s.rest_speed
        for _ in range(CLUSTER_SWEEPS):
            big = 0.0
            for k in range(len(rows)):
                A, B, cx, cy, nx, ny, ran, rbn, kn = rows[k]
                if not (kn > 0.0):
                    continue
                vn = self.normal_speed(A, B, cx, cy, nx, ny)
                new = acc[k] + (target[k] - vn) / kn
                if new < 0.0:
                    new = 0.0
                dj = new - acc[k]
                acc[k] = new
                self.nudge(A, -dj, nx, ny, ran)
                self.nudge(B, dj, nx, ny, rbn)
                ch = math.fabs(dj) * kn
                if ch > big:
                    big = ch
            if big <= tol:
                return

    @staticmethod
    def kinetic(movers: list) -> float:
        """The kinetic energy of the bodies (linear, and turning where 1/I > 0)."""
        e = 0.0
        for b in movers:
            e = e + 0.5 * (b.vx * b.vx + b.vy * b.vy) / b.inv_m
            if b.inv_i > 0.0:
                e = e + 0.5 * b.om * b.om / b.inv_i
        return e

    @staticmethod
    def velocities(movers: list) -> list:
        return [(b.vx, b.vy, b.om) for b in movers]

    @staticmethod
    def set_velocities(movers: list, vs: list) -> None:
        for k in range(len(movers)):
            movers[k].vx, movers[k].vy, movers[k].om = vs[k]

    @staticmethod
    def mix(movers: list, v1: list, budget: float) -> float:
        """The largest mu in [0, 1] for which the bodies' velocities
        v1 + mu (v - v1) (v: theirs now, v1 as given; the kinetic energy
        at v1 at most budget) have a kinetic energy at most budget: with a
        the energy of the change, b the cross term and e1 the energy at v1,
        a mu^2 + b mu <= budget - e1."""
        a = 0.0
        b = 0.0
        e1 = 0.0
        for k in range(len(movers)):
            m = movers[k]
            vx, vy, om = v1[k]
            dx = m.vx - vx
            dy = m.vy - vy
            a = a + 0.5 * (dx * dx + dy * dy) / m.inv_m
            b = b + (vx * dx + vy * dy) / m.inv_m
            e1 = e1 + 0.5 * (vx * vx + vy * vy) / m.inv_m
            if m.inv_i > 0.0:
                dw = m.om - om
                a = a + 0.5 * dw * dw / m.inv_i
                b = b + om * dw / m.inv_i
                e1 = e1 + 0.5 * om * om / m.inv_i
        if not (a > 0.0):
            return 1.0
        spare = budget - e1
        if spare < 0.0:
            spare = 0.0
        root = math.sqrt(b * b + 4.0 * a * spare)
        if b > 0.0:
            mu = 2.0 * spare / (b + root)
        else:
            mu = (root - b) / (2.0 * a)
        return mu if mu < 1.0 else 1.0

    def pressing_contact(self, row: tuple, c: tuple) -> bool:
        """A contact of the cluster that must separate: its bodies' accelerations
        press them together (pressed) or, a body turning, its gap closes now
        (closing), as contact_impulse decides."""
        A, B, cx, cy, nx, ny, ran, rbn, kn = row
        if self.pressed(A, B, nx, ny):
            return True
        if self.turn_rate(A) > 0.0 or self.turn_rate(B) > 0.0:
            return self.closing(A, B, c[2], c[3], c[4])
        return False

    def solve_cluster(self, cs: list, t: float):
        """The cluster's joint impulses (docs/simulator.md, "Contact model:
        simultaneous contacts"): inelastic sequential impulses (target
        normal speed 0: kinetic energy e1); then the pressed contacts
        separate at rest_speed (the others at CLUSTER_APART rest_speed): sequential
        impulses from v1 (v2), taken when they cost no more than e1; else
        the same from the movers at rest (vs, energy es), mixed towards v2
        as far as e1 pays (mix) when es <= e1, else vs scaled to energy e1.
        Returns (rows, acc, movers, saved): each contact's frame and its
        normal impulse, the bodies that move and their velocities before."""
        rows = []
        for A, B, feature, i, j in cs:
            cx, cy, nx, ny = self.contact_frame(t, feature, A, B, i, j)
            ran = (cx - A.px) * ny - (cy - A.py) * nx
            rbn = (cx - B.px) * ny - (cy - B.py) * nx
            kn = self.give(A, nx, ny, ran) + self.give(B, nx, ny, rbn)
            rows.append((A, B, cx, cy, nx, ny, ran, rbn, kn))
        movers = []
        for A, B, _, _, _ in cs:
            for b in (A, B):
                if self.part(b) != HELD and b not in movers:
                    movers.append(b)
        saved = self.velocities(movers)
        n = len(rows)
        acc = [0.0] * n
        self.sweeps(rows, acc, [0.0] * n)
        e1 = self.kinetic(movers)
        target = [0.0] * n
        for k in range(n):
            if self.pressing_contact(rows[k], cs[k]):
                target[k] = self.s.rest_speed
            else:
                target[k] = CLUSTER_APART * self.s.rest_speed
        self.sweeps(rows, acc, target)
        if self.kinetic(movers) <= e1:
            return rows, acc, movers, saved
        v2 = self.velocities(movers)
        acc2 = acc
        for b in movers:
            if b.sup >= 0 and self.s.bodies[b.sup].fixed:
                u = self.support_relative(b)[1]
                b.vx = b.vx - u * b.tx
                b.vy = b.vy - u * b.ty
            else:
                b.vx = 0.0
                b.vy = 0.0
            b.om = 0.0
        acc = [0.0] * n
        self.sweeps(rows, acc, target)
        es = self.kinetic(movers)
        if es <= e1:
            vs = self.velocities(movers)
            self.set_velocities(movers, v2)
            mu = self.mix(movers, vs, e1)
            for k in range(len(movers)):
                b = movers[k]
                vx, vy, om = vs[k]
                b.vx = vx + mu * (b.vx - vx)
                b.vy = vy + mu * (b.vy - vy)
                b.om = om + mu * (b.om - om)
            for k in range(n):
                acc[k] = acc[k] + mu * (acc2[k] - acc[k])
            return rows, acc, movers, saved
        f = math.sqrt(e1 / es)
        for b in movers:
            b.vx = f * b.vx
            b.vy = f * b.vy
            b.om = f * b.om
        for k in range(n):
            acc[k] = f * acc[k]
        return rows, acc, movers, saved

    def jolted_sleeper(self, rows: list, acc: list) -> Body | None:
        """The first sleeper (in the contacts' order) whose held impulses,
        summed, would change its material points' normal speed by at least
        rest_speed (as a touch that is not gentle, sleeper_impulse); None."""
        for k in range(len(rows)):
            for S in (rows[k][0], rows[k][1]):
                if not S.asleep or self.held_now(S):
                    continue
                total = 0.0
                for q in range(len(rows)):
                    A, B, cx, cy, nx, ny, ran, rbn, kn = rows[q]
                    if A is S or B is S:
                        rsn = ran if A is S else rbn
                        total = total + acc[q] * (S.inv_m + S.inv_i * rsn * rsn)
                if total >= self.s.rest_speed:
                    return S
        return None

    def wedged(self, M: Body, rows: list) -> Body | None:
        """The grounded body awake M falls asleep on after its cluster's
        solve, or None: M slower than rest_speed (a polygon also turning
        slower than rest_speed / bound) and its free acceleration held by
        what it rests on (holds): the outward normal of its support when it
        is supported on an unmoving fixed body, and each contact of the
        cluster with a grounded body (pushing M along -m, m the contact's
        normal from M).  It falls asleep on its support, else on the first
        grounded body of those contacts."""
        rest = self.s.rest_speed
        if not (M.vx * M.vx + M.vy * M.vy < rest * rest):
            return None
        if M.polygon and not (math.fabs(M.om) * M.bound < rest):
            return None
        pushes = []
        G = None
        if M.sup >= 0:
            S = self.s.bodies[M.sup]
            if not (S.fixed and self.grounded(S)):
                return None
            _, _, ox, oy = self.support_frame(S, M.sup_edge)
            pushes.append((ox, oy))
            G = S
        for A, B, cx, cy, nx, ny, ran, rbn, kn in rows:
            if A is M and self.grounded(B):
                pushes.append((-nx, -ny))
                if G is None:
                    G = B
            if B is M and self.grounded(A):
                pushes.append((nx, ny))
                if G is None:
                    G = A
        if G is None or not self.holds(pushes, -M.fax, -M.fay):
            return None
        return G

    @staticmethod
    def holds(pushes: list, dx: float, dy: float) -> bool:
        """The pushes (unit directions) can make (dx, dy) with non-negative
        weights through one push (its direction within HOLD_TOL rad of d) or
        two: d = a p + b q, a >= 0, b >= 0 (Cramer, p x q != 0), pairs in
        order.  (dx, dy) = (0, 0) needs nothing."""
        if dx == 0.0 and dy == 0.0:
            return True
        for px, py in pushes:
            dot = px * dx + py * dy
            if dot > 0.0 and math.fabs(px * dy - py * dx) <= HOLD_TOL * dot:
                return True
        n = len(pushes)
        for k in range(n):
            px, py = pushes[k]
            for q in range(k + 1, n):
                qx, qy = pushes[q]
                det = px * qy - py * qx
                if det == 0.0:
                    continue
                a = (dx * qy - dy * qx) / det
                b = (px * dy - py * dx) / det
                if a >= 0.0 and b >= 0.0:
                    return True
        return False

    def handle_cluster(self, ev: CollisionEvent) -> None:
        """A contact met again at the instant it was handled (repeated):
        the contacts handled at this instant that reach it (cluster) are
        solved together (solve_cluster); a sleeper the solve would jolt
        wakes and the solve is made again with it moving.  Then an E
        collision line per contact (its normal impulse), each followed by
        the states of its moving bodies not written yet (settle); what a
        body whose velocity changed carries leaves; those slow enough fall
        asleep (wedged), and the others are predicted again."""
        t = ev.t
        if self.jam_count(ev) >= CLUSTER_REPEATS + CLUSTER_JAM:
            self.jam(ev)
            return
        self.touch(t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        while True:
            cs = self.cluster(ev)
            for A, B, _, _, _ in cs:
                self.rebase(A, t)
                self.rebase(B, t)
            rows, acc, movers, saved = self.solve_cluster(cs, t)
            S = self.jolted_sleeper(rows, acc)
            if S is None:
                break
            for k in range(len(movers)):
                movers[k].vx, movers[k].vy, movers[k].om = saved[k]
            self.handle_wake(S, t)
        written = []
        for k in range(len(rows)):
            A, B, cx, cy, nx, ny, ran, rbn, kn = rows[k]
            _, _, feature, i, j = cs[k]
            self.stats.collisions += 1
            self.emit_contact("collision", t, A.idx, B.idx, feature, i, j, cx, cy, nx, ny, acc[k])
            self.contacts.append(Contact(t, A.idx, B.idx, feature, i, j, cx, cy, nx, ny, acc[k], False))
            for b in (A, B):
                if b in movers and b not in written:
                    written.append(b)
                    self.settle(b)
        left = []
        for k in range(len(movers)):
            b = movers[k]
            if b.vx != saved[k][0] or b.vy != saved[k][1] or b.om != saved[k][2]:
                self.release(b, t, left)
        done = []
        grow = True
        while grow:
            grow = False
            for b in movers:
                if not b.asleep:
                    G = self.wedged(b, rows)
                    if G is not None:
                        self.handle_sleep(b, G, t)
                        done.append(b)
                        grow = True
        for b in movers:
            if not b.asleep:
                self.predict_apart(b, t, done)
                done.append(b)
        self.predict_released(left, t)

    def jam(self, ev: CollisionEvent) -> None:
        """A cluster its solves do not settle (met again after CLUSTER_JAM
        solves at one instant): inelastic collapse, resolved as in Luding's
        TC model with a contact time of zero: contacts met again at once
        lose all restitution and all sliding.  An E collision line per
        contact of the cluster (impulse 0), then each mover (a body of the
        cluster that is not held, in the contacts' order) falls asleep, at
        rest (handle_sleep), on its support when that is fixed, else on the
        first body it touches in the cluster that is fixed or asleep, else
        on the other body of its first contact; it is held until the
        instant ends (held_now: no touch wakes it at this instant).  Kinetic
        energy only falls."""
        t = ev.t
        self.touch(t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        cs = self.cluster(ev)
        for A, B, _, _, _ in cs:
            self.rebase(A, t)
            self.rebase(B, t)
        movers = []
        for A, B, _, _, _ in cs:
            for b in (A, B):
                if self.part(b) != HELD and b not in movers:
                    movers.append(b)
        for A, B, feature, i, j in cs:
            cx, cy, nx, ny = self.contact_frame(t, feature, A, B, i, j)
            self.stats.collisions += 1
            self.emit_contact("collision", t, A.idx, B.idx, feature, i, j, cx, cy, nx, ny, 0.0)
            self.contacts.append(Contact(t, A.idx, B.idx, feature, i, j, cx, cy, nx, ny, 0.0, False))
        if self.jammed_t != t:
            self.jammed_t = t
            self.jammed = []
        for b in movers:
            if b.asleep:
                continue
            G = None
            if b.sup >= 0 and self.s.bodies[b.sup].fixed:
                G = self.s.bodies[b.sup]
            else:
                for A, B, _, _, _ in cs:
                    o = B if A is b else (A if B is b else None)
                    if o is not None and (o.fixed or o.asleep):
                        G = o
                        break
                if G is None:
                    for A, B, _, _, _ in cs:
                        if A is b or B is b:
                            G = B if A is b else A
                            break
            self.jammed.append(b.idx)
            self.handle_sleep(b, G, t)

    def settle(self, b: Body) -> None:
        """A body of a solved cluster after its impulses: one sliding on a
        fixed body gets its friction again for its new speed (as
        held_impulse), a carried one leaves its base's motion (end_support:
        it is not held); a new stamp, its state."""
        if b.sup >= 0:
            if self.s.bodies[b.sup].fixed:
                self.slide_accel(b, self.support_relative(b)[1])
            else:
                self.end_support(b)
        b.stamp += 1
        self.emit_state(b)

    def predict_apart(self, b: Body, now: float, done: list) -> None:
        """predict_body for a body of a solved cluster, but against the
        bodies in done (predicted already, or fallen asleep and predicted
        against it by handle_sleep)."""
        for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
            if o not in done and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        for o in self.large_near(b):
            if o not in done and not (b.fixed and o.fixed):
                self.predict_pair(b, o, now)
        self.schedule_cell(b, now)
        if b.sup >= 0 and self.s.bodies[b.sup].fixed:
            self.schedule_support(b, now)
