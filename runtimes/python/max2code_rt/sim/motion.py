"""Motion between events: every body moves exactly, p + (v + a dt/2) dt,
v + a dt, angle + w dt, from its state at its own update time tb
(MotionMixin: rebase, state_at, turn_rate, point_at)."""
from __future__ import annotations

import math

from max2code_rt.sim.scene import Body, Vertex


class MotionMixin:
    """A body's state at a time, and the world position of its features."""

    @staticmethod
    def rebase(b: Body, t: float) -> None:
        """Carry b's state to time t (only events do this: re-basing rounds)."""
        dt = t - b.tb
        b.px = b.px + (b.vx + 0.5 * b.ax * dt) * dt
        b.py = b.py + (b.vy + 0.5 * b.ay * dt) * dt
        b.vx = b.vx + b.ax * dt
        b.vy = b.vy + b.ay * dt
        b.ang = b.ang + b.om * dt
        b.tb = t

    @staticmethod
    def state_at(b: Body, t: float):
        """Centre, velocity and angle at time t (the body is not changed)."""
        dt = t - b.tb
        return (b.px + (b.vx + 0.5 * b.ax * dt) * dt, b.py + (b.vy + 0.5 * b.ay * dt) * dt,
                b.vx + b.ax * dt, b.vy + b.ay * dt, b.ang + b.om * dt)

    @staticmethod
    def turn_rate(b: Body) -> float:
        if b.polygon or b.orbit > 0.0:
            return math.fabs(b.om)
        return 0.0

    def point_at(self, b: Body, v: Vertex | None, t: float) -> tuple[float, float]:
        """World position of a circle's centre (v None) or of a vertex, at t."""
        x, y, _, _, ang = self.state_at(b, t)
        d, beta = (b.orbit, b.ophase) if v is None else (v.rho, v.beta)
        if d == 0.0:
            return x, y
        return x + d * math.cos(ang + beta), y + d * math.sin(ang + beta)
