"""The handlers: one per event kind (input, collision and the support it
may end in, stop, leave, cell, horizon, frame), the dispatch over them,
the loop that handles the queued events up to a time, and the start of a
run: cells, inputs, the first frame and every pair's first prediction."""
from __future__ import annotations

import heapq

from max2code_rt.sim.out import SimError, _fmt
from max2code_rt.sim.queue import (CellEvent, CollisionEvent, FrameEvent, HorizonEvent, InputEvent, LeaveEvent,
                                   StopEvent)
from max2code_rt.sim.scene import (ADD_VELOCITY, IMPULSE, LENGTH_MAX, REMOVE, SET_VELOCITY, TELEPORT, Body,
                                   after_input, live_reach)
from max2code_rt.sim.world import Contact


class HandlersMixin:
    """Events handled: self.handlers holds these by kind (live.World)."""

    def handle_collision(self, ev: CollisionEvent) -> None:
        t = ev.t
        A = self.s.bodies[ev.a]
        B = self.s.bodies[ev.b]
        if self.repeated(ev):
            self.handle_cluster(ev)
            return
        self.rebase(A, t)
        self.rebase(B, t)
        cx, cy, nx, ny = self.contact_frame(t, ev.feature, A, B, ev.i, ev.j)
        vn = self.normal_speed(A, B, cx, cy, nx, ny)
        if self.can_support(A, B, ev.feature, ev.i, ev.j, vn) or self.can_carry(A, B, ev.feature, ev.i, ev.j, vn):
            self.handle_support(ev, A, B, cx, cy, nx, ny, vn)
            return
        if self.can_sleep(A, B, ev, nx, ny, vn):
            self.handle_sleep(A, B, t)
            return
        if self.can_sleep(B, A, ev, nx, ny, vn):
            self.handle_sleep(B, A, t)
            return
        if self.can_sleep_many(A, B, ev, cx, cy, nx, ny, vn):
            self.handle_sleep_many(A, B, ev, t)
            return
        if self.can_sleep_many(B, A, ev, cx, cy, nx, ny, vn):
            self.handle_sleep_many(B, A, ev, t)
            return
        if self.can_ride(A, B, ev.feature, ev.i, ev.j, vn):
            self.handle_support(ev, A, B, cx, cy, nx, ny, vn)
            return
        rest = self.s.rest_speed
        press_a = self.slow_touch(A, B, ev, nx, ny, vn, rest)
        press_b = self.slow_touch(B, A, ev, nx, ny, vn, rest)
        self.stats.collisions += 1
        # a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
        # on it); a gentle touch leaves it asleep, a real impulse wakes it and what rests on it;
        # a slow contact of bodies held on their supports keeps them there
        held = self.held(A, B, nx, ny, vn)
        if held:
            imp = self.held_impulse(A, B, nx, ny, vn)
        elif A.asleep or B.asleep:
            imp = self.sleeper_impulse(A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
        else:
            imp = self.contact_impulse(A, B, cx, cy, nx, ny, ev.feature, ev.i, ev.j)
        if imp != 0.0 and not held:
            if A.asleep and self.jolted(A):
                self.handle_wake(A, t)
            if B.asleep and self.jolted(B):
                self.handle_wake(B, t)
            if A.sup >= 0:
                self.end_support(A)
            if B.sup >= 0:
                self.end_support(B)
        self.emit_contact("collision", t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp)
        self.contacts.append(Contact(t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, False))
        self.touch(t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        # a sleeper still asleep is unchanged; the other is predicted again,
        # against it too unless they only grazed (zero impulse: the graze
        # would be found again at once; a later change of the other's motion
        # predicts the pair again).  After a gentle touch (an impulse that
        # left the sleeper asleep) the other leaves and may fall back onto
        # it: that pair must stay predicted, or it passes through the sleeper
        for b in (A, B):
            if not b.fixed and not b.asleep:
                b.stamp += 1
                self.emit_state(b)
        if press_a and not A.asleep:
            self.note_rest(A, B, ev, cx, cy, nx, ny)
        if press_b and not B.asleep:
            self.note_rest(B, A, ev, cx, cy, nx, ny)
        # an impulse changes the motion of what it hit: what they carried leaves
        # (a sleeper a gentle touch left asleep has not moved: what slides on it stays)
        left = []
        if imp != 0.0:
            for b in (A, B):
                if not b.fixed and not b.asleep:
                    self.release(b, t, left)
        if not A.fixed and not A.asleep:
            self.predict_body(A, t, B if (B.asleep and imp == 0.0) else None)
        if not B.fixed and not B.asleep:
            self.predict_body(B, t, A if ((not A.fixed and not A.asleep) or (A.asleep and imp == 0.0)) else None)
        self.predict_released(left, t)

    def handle_support(self, ev: CollisionEvent, A: Body, B: Body, cx: float, cy: float, nx: float, ny: float,
                       vn: float) -> None:
        """A collision that ends in support (called by handle_collision)."""
        self.stats.supports += 1
        imp = -vn / A.inv_m
        if B.fixed or B.asleep:
            self.enter_support(A, B, ev.j)
        else:
            self.enter_carried(A, B, ev.j)
        self.emit_contact("support", ev.t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp)
        self.contacts.append(Contact(ev.t, A.idx, B.idx, ev.feature, ev.i, ev.j, cx, cy, nx, ny, imp, True))
        self.touch(ev.t, ev.a, ev.b, ev.feature, ev.i, ev.j)
        if self.at_rest(A):
            self.handle_sleep(A, B, ev.t)
            return
        A.stamp += 1
        self.emit_state(A)
        left = []
        self.release(A, ev.t, left)
        self.predict_body(A, ev.t, None)
        self.predict_released(left, ev.t)

    def handle_stop(self, ev: StopEvent) -> None:
        """Sliding stops: velocity exactly the support's (zero when it does
        not move), then rest or slide back."""
        self.stats.stops += 1
        A = self.s.bodies[ev.body]
        self.rebase(A, ev.t)
        B = self.s.bodies[A.sup]
        if self.static(B):
            A.vx = 0.0
            A.vy = 0.0
        else:
            _, _, A.vx, A.vy, _ = self.state_at(B, ev.t)
        self.slide_accel(A, 0.0)
        self.emit_support_end("stop", ev.t, A.idx, A.sup, A.sup_edge)
        if self.at_rest(A):
            self.handle_sleep(A, self.s.bodies[A.sup], ev.t)
            return
        if B.asleep and not self.base_holds(B, 0.0, 0.0):
            left = []          # sliding back, its friction turned: the sleeping base no longer holds it
            self.leave(A, ev.t, None, left)
            self.predict_released(left, ev.t)
            return
        A.stamp += 1
        self.emit_state(A)
        left = []
        self.release(A, ev.t, left)
        self.predict_body(A, ev.t, None)
        self.predict_released(left, ev.t)

    def handle_leave(self, ev: LeaveEvent) -> None:
        """The support's edge ends under the body: free motion again."""
        left = []
        self.leave(self.s.bodies[ev.body], ev.t, None, left)
        self.predict_released(left, ev.t)

    def handle_input(self, ev: InputEvent) -> None:
        self.stats.inputs += 1
        t = ev.t
        inp = self.s.inputs[ev.k]
        body = self.s.bodies[inp.body]
        if body.gone:
            raise SimError(f"input {ev.k}: body {body.idx} was removed before t = {_fmt(t)}")
        if body.asleep:
            self.handle_wake(body, t)      # any input on a sleeper wakes it (and what rests on it) first
        self.rebase(body, t)
        if inp.mode != REMOVE:
            self.check_reach(body, ev.k, t, inp.mode, inp.vx, inp.vy)
        if inp.mode == REMOVE:
            self.remove(body, ev.k, t)
            return
        if body.fixed:
            self.drive(body, ev.k, t, inp.vx, inp.vy)
            return
        if inp.mode == TELEPORT:
            o = self.overlapping(body, inp.vx, inp.vy, t)
            if o >= 0:
                raise SimError(f"input {ev.k}: body {body.idx} teleported to ({_fmt(inp.vx)}, {_fmt(inp.vy)}) at "
                               f"t = {_fmt(t)} would overlap body {o}")
        if body.sup >= 0:
            self.end_support(body)
        if inp.mode == SET_VELOCITY:
            body.vx, body.vy = inp.vx, inp.vy
        elif inp.mode == ADD_VELOCITY:
            body.vx, body.vy = body.vx + inp.vx, body.vy + inp.vy
        elif inp.mode == IMPULSE:
            body.vx, body.vy = body.vx + inp.vx * body.inv_m, body.vy + inp.vy * body.inv_m
        else:
            body.px, body.py = inp.vx, inp.vy
            if not body.large:          # a large body is in no cell: every body checks it
                self.cell_remove(body)
                body.cx, body.cy = self.cell_of(body.px, body.py)
                self.cell_add(body)
        body.stamp += 1
        self.emit_input(t, body.idx, ev.k)
        self.emit_state(body)
        left = []
        self.release(body, t, left)
        self.predict_body(body, t, None)
        self.predict_released(left, t)

    def check_reach(self, body: Body, k: int, t: float, mode: int, x: float, y: float) -> None:
        """Input k (not a removal) on the body, based at t, refused when the
        body's motion after it would reach more than 2e150 m from the
        origin by the end (the live inputs' rule, from the state at t; a
        velocity or position that is not finite is refused by it too)."""
        px, py, vx, vy = after_input(body, mode, x, y, body.px, body.py, body.vx, body.vy)
        if not live_reach(body, px, py, vx, vy, self.s.end) <= 2 * LENGTH_MAX:
            raise SimError(f"input {k}: body {body.idx} at t = {_fmt(t)}: reaches more than 2e150 m from the origin "
                           f"by the end")

    def remove(self, body: Body, k: int, t: float) -> None:
        """Input k removes the body (based at t): it stops where it is (v, a,
        w zero), leaves the grid, its stamp changes (its queued events go
        stale) and it is never predicted again; bodies it supported leave."""
        body.vx = body.vy = body.ax = body.ay = body.fax = body.fay = body.om = 0.0
        if body.sup >= 0:
            self.end_support(body)
        body.gone = True
        body.stamp += 1
        if body.large:
            self.unplace_large(body)
        else:
            self.cell_remove(body)
        self.emit_input(t, body.idx, k)
        for A in self.s.bodies:
            if A.sup == body.idx:
                left = []
                self.leave(A, t, None, left)
                self.predict_released(left, t)
        self.wake_touching(body, t)

    def drive(self, B: Body, k: int, t: float, vx: float, vy: float) -> None:
        """Input k sets the velocity of fixed polygon B (based at t, it does
        not turn): a large one placed in grid cells moves to the large list
        for good; every body it supported leaves (E leave, free motion: it
        meets B again at once and is supported again relative to B's new
        motion, or bounces, or falls); B is predicted against every body
        again (a large B: each small one that is not fixed or removed, in
        index order; a small one: predict_body), the bodies that left
        against the others; last the sleepers touching B wake (wake_touching:
        B may have held them, or carries them into others)."""
        B.vx = vx
        B.vy = vy
        B.stamp += 1
        if B.wcells is not None:
            self.unplace_large(B)
            B.wcells = None
            self.large.append(B)
        self.emit_input(t, B.idx, k)
        self.emit_state(B)
        bodies = self.s.bodies
        left = []
        for A in bodies:
            if A.sup == B.idx:
                self.leave(A, t, B, left)
        if B.large:
            for o in bodies:
                if not o.large and not o.gone and not o.fixed:
                    self.predict_pair(o, B, t)
        else:
            self.predict_body(B, t, None)
        self.predict_released(left, t)
        self.wake_touching(B, t)

    def handle_cell(self, ev: CellEvent) -> None:
        """The body's centre went the grid's margin past its cell's edge along
        an axis: move it to the next cell and predict it against the row or
        column it now neighbours."""
        self.stats.cells += 1
        body = self.s.bodies[ev.body]
        d = ev.direction
        self.cell_remove(body)
        if ev.axis == 0:
            body.cx += d
            col = body.cx + d
            x_lo, x_hi, y_lo, y_hi = col, col, body.cy - 1, body.cy + 1
        else:
            body.cy += d
            row = body.cy + d
            x_lo, x_hi, y_lo, y_hi = body.cx - 1, body.cx + 1, row, row
        self.cell_add(body)
        for o in self.candidates(body, x_lo, x_hi, y_lo, y_hi):
            if not (body.fixed and o.fixed):
                self.predict_pair(body, o, ev.t)
        # the walls of the new row or column but those also listed in the
        # two it shares with the old neighbourhood (predicted at its last change)
        self.mark += 1
        news: list[Body] = []
        if ev.axis == 0:
            lo = body.cx - 1 if d > 0 else body.cx
            self.walls_in(body, lo, lo + 1, body.cy - 1, body.cy + 1, [])
        else:
            lo = body.cy - 1 if d > 0 else body.cy
            self.walls_in(body, body.cx - 1, body.cx + 1, lo, lo + 1, [])
        self.walls_in(body, x_lo, x_hi, y_lo, y_hi, news)
        news.sort(key=lambda o: o.idx)
        if not body.fixed:
            for o in news:
                self.predict_pair(body, o, ev.t)
        self.schedule_cell(body, ev.t)

    def handle_horizon(self, ev: HorizonEvent) -> None:
        self.stats.horizons += 1
        self.predict_pair(self.s.bodies[ev.a], self.s.bodies[ev.b], ev.t)

    def handle_frame(self, ev: FrameEvent) -> None:
        self.stats.frames += 1
        self.emit_frame(ev.t)
        nxt = (ev.k + 1) * self.s.frame_dt
        if nxt <= self.s.end:
            self.push(FrameEvent(nxt, ev.k + 1))

    def start(self) -> None:
        """Cells, inputs, the first frame and every pair's first prediction."""
        s = self.s
        bodies = s.bodies
        for b in bodies:
            if not b.large:
                b.cx, b.cy = self.cell_of(b.px, b.py)
                self.cell_add(b)
        for k, inp in enumerate(s.inputs):
            self.push(InputEvent(inp.t, k))
        if s.frame_dt > 0.0 and s.frame_dt <= s.end:
            self.push(FrameEvent(s.frame_dt, 1))
        for b in bodies:
            if b.large:
                continue
            for o in self.candidates(b, b.cx - 1, b.cx + 1, b.cy - 1, b.cy + 1):
                if o.idx > b.idx and not (b.fixed and o.fixed):
                    self.predict_pair(b, o, 0.0)
            for o in self.large_near(b):
                if not (b.fixed and o.fixed):
                    self.predict_pair(b, o, 0.0)
            self.schedule_cell(b, 0.0)

    def dispatch(self, ev) -> None:
        """Handle one event popped from the queue: drop it when stale, count
        it against max_events (every kind: cell crossings and horizons too)
        and among the events at one instant (max_same_time), call its kind's
        handler."""
        if self.is_stale(ev):
            self.stats.stale += 1
            return
        self.handled += 1
        if self.handled > self.s.max_events:
            raise SimError(f"more than {self.s.max_events} events (collisions, inputs, frames, cell crossings, "
                           f"horizons) at t = {_fmt(ev.t)}: the run was stopped; raise max_events in the scene "
                           f"or --max-events, or shorten end_time")
        if ev.t == self.last_t:
            self.same += 1
            if self.same > self.s.max_same:
                raise SimError(f"more than {self.s.max_same} events at t = {_fmt(ev.t)}: the scene is stuck")
        else:
            self.last_t, self.same = ev.t, 0
        self.handlers[ev.kind](ev)

    def process(self, t: float, inclusive: bool) -> None:
        """Handle every queued event before t (inclusive: at t too), in
        (t, kind, seq) order, events that handling schedules included."""
        heap = self.heap
        while heap:
            top = heap[0][0]
            if top > t or (top == t and not inclusive):
                return
            self.dispatch(heapq.heappop(heap)[3])
