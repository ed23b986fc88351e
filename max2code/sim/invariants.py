"""Invariants of a simulated trace, checked at every collision and input
event: no two bodies overlap by more than a tolerance, and (for scenes whose
restitutions are all 1) kinetic plus potential energy stays what it was."""
from __future__ import annotations

import math
from dataclasses import dataclass

from max2code.sim.replay import Replay
from max2code.sim.scene import Body, Scene, circle_centre, penetration_placed, world_vertices


@dataclass
class InvariantReport:
    events: int                 # events checked
    max_overlap: float          # deepest overlap of two bodies seen at an event (m; <= 0: never)
    overlap_where: str
    energy0: float              # total energy at t = 0 (J)
    max_energy_drift: float     # largest |E - E0| / E0 at an event
    drift_where: str


def _frame_at(scene: Scene, rp: Replay, frame, t: float, before: bool = False):
    """(velocity, displacement since t = 0) of the frame at t: a constant
    velocity (vx, vy), or a body's name (a fixed body that does not
    accelerate: its velocity changes only at the inputs that set it)."""
    if isinstance(frame, str):
        k = rp.body_index(frame)
        s = rp.state_before(k, t) if before else rp.state_at(k, t)
        x0, y0 = scene.bodies[k].position
        return (s.vx, s.vy), (s.px - x0, s.py - y0)
    return frame, (frame[0] * t, frame[1] * t)


def energy(scene: Scene, rp: Replay, t: float, before: bool = False, frame=(0.0, 0.0)) -> float:
    """Kinetic (linear and rotational) plus potential energy of the movable
    bodies at time t: the potential of each body's free acceleration (the
    scene's, gravity included: a body whose own acceleration cancels
    gravity has none).  before: with the states in force just before t
    (carried to t), not the ones the events at t left.  frame: measured in
    the frame moving at that constant velocity (or with that fixed body,
    see _frame_at), which is the world's at t = 0: velocities less the
    frame's, positions less its displacement (the default: the world's)."""
    (fx, fy), (dx, dy) = _frame_at(scene, rp, frame, t, before)
    total = 0.0
    for k, b in enumerate(scene.bodies):
        if b.fixed:
            continue
        s = rp.state_before(k, t) if before else rp.state_at(k, t)
        ax, ay = b.acceleration
        vx, vy = s.vx - fx, s.vy - fy
        total += 0.5 * b.mass * (vx * vx + vy * vy) + 0.5 * b.inertia * s.omega * s.omega
        total -= b.mass * (ax * (s.px - dx) + ay * (s.py - dy))
    return total


@dataclass
class EnergyReport:
    instants: int               # event instants checked
    max_growth: float           # largest (E(t) - lowest E before t) / |Eref| (see energy_growth)
    growth_where: str
    max_jump: float             # largest E(t) - E(t-) at one instant (J), driven instants left out
    jump_where: str


def driven_instants(scene: Scene, rp: Replay, frame=(0.0, 0.0)) -> set[float]:
    """The instants at which something outside the bodies may add energy: an
    input, or a contact with a fixed body that moves or turns in the frame
    (see energy) (it does work)."""
    bodies = scene.bodies
    out = set()
    for e in rp.events:
        if e.kind == "input":
            out.add(e.t)
        elif e.kind in ("collision", "support"):
            for k in e.bodies:
                b = bodies[k]
                if not b.fixed:
                    continue
                s = rp.state_at(k, e.t)
                if (s.vx, s.vy) != _frame_at(scene, rp, frame, e.t)[0] or b.acceleration != (0.0, 0.0) \
                        or b.angular_velocity != 0.0:
                    out.add(e.t)
    return out


def energy_growth(scene: Scene, rp: Replay, frame=(0.0, 0.0)) -> EnergyReport:
    """Energy never grows: at every event instant t (frames left out), E(t)
    against the lowest energy at an instant since t = 0 or since the last
    driven instant (driven_instants: there it starts again from E after it),
    relative to the energy Eref at that start; and the jump E(t) - E(t-)
    across each instant that is not driven.  Between events, free motion and
    frictionless sliding keep E; friction and sleep only take it away.
    frame: measured in the frame moving at that constant velocity, or with
    that fixed body (energy), where a fixed body moving with the frame (a
    platform carrying bodies) does no work and every fixed body that does
    not (walls) drives; an input (one that sets the platform's velocity
    too) drives."""
    driven = driven_instants(scene, rp, frame)
    ref = low = energy(scene, rp, 0.0, frame=frame)
    growth, gwhere = -math.inf, ""
    jump, jwhere = -math.inf, ""
    times = sorted({e.t for e in rp.events if e.kind != "frame"})
    for t in times:
        e = energy(scene, rp, t, frame=frame)
        if t in driven:
            ref = low = e
            continue
        rel = (e - low) / abs(ref) if ref != 0.0 else e - low
        if rel > growth:
            growth, gwhere = rel, f"t={t!r}"
        low = min(low, e)
        d = e - energy(scene, rp, t, before=True, frame=frame)
        if d > jump:
            jump, jwhere = d, f"t={t!r}"
    return EnergyReport(len(times), growth, gwhere, jump, jwhere)


def _at(b: Body, s) -> Body:
    """A copy of the body placed at state s (for scene.penetration)."""
    return Body(b.name, b.polygon, b.fixed, b.mass, b.inertia, b.restitution, (s.px, s.py), (s.vx, s.vy),
                b.acceleration, s.angle, s.omega, b.radius, b.orbit_radius, b.orbit_angle, b.vertices, b.friction)


def check(scene: Scene, rp: Replay, kinds=("collision", "support", "stop", "leave", "sleep", "wake", "input")) -> InvariantReport:
    """Check at the time of every event of these kinds (add "frame" to
    sample between collisions too, where a missed contact would show)."""
    bodies = scene.bodies
    e0 = energy(scene, rp, 0.0)
    deepest, where = -math.inf, ""
    drift, dwhere = 0.0, ""
    times = sorted({e.t for e in rp.events if e.kind in kinds})
    # a pair is measured again only when one of its bodies has moved since the
    # pair was last measured: the same places give the same depth, which could
    # not raise `deepest` a second time
    measured: dict[tuple[int, int], tuple] = {}
    for t in times:
        placed = [_at(b, rp.state_at(k, t)) for k, b in enumerate(bodies)]
        where_at = [(p.position, p.angle) for p in placed]
        corners: dict[int, list] = {}
        boxes: dict[int, tuple] = {}

        def pts(k: int):
            if not placed[k].polygon:
                return None
            if k not in corners:
                corners[k] = world_vertices(placed[k])
            return corners[k]

        def box(k: int):
            if k not in boxes:
                p = pts(k)
                if p is None:
                    x, y = circle_centre(placed[k])
                    r = placed[k].radius
                    boxes[k] = (x - r, y - r, x + r, y + r)
                else:
                    xs, ys = [q[0] for q in p], [q[1] for q in p]
                    boxes[k] = (min(xs), min(ys), max(xs), max(ys))
            return boxes[k]

        # pairs whose bounding circles meet (sort-and-sweep on x)
        order = sorted(range(len(placed)), key=lambda k: placed[k].position[0] - placed[k].bound)
        active: list[int] = []
        for k in order:
            bk = placed[k]
            lo = bk.position[0] - bk.bound
            active = [j for j in active if placed[j].position[0] + placed[j].bound >= lo]
            for j in active:
                bj = placed[j]
                if bj.fixed and bk.fixed:
                    continue
                reach = bj.bound + bk.bound
                if (bj.position[0] - bk.position[0]) ** 2 + (bj.position[1] - bk.position[1]) ** 2 > reach * reach:
                    continue
                now = (where_at[j], where_at[k])
                if measured.get((j, k)) == now:
                    continue
                measured[(j, k)] = now
                if deepest >= 0.0:
                    # convex bodies whose boxes are apart are apart: depth < 0 <= deepest
                    xj0, yj0, xj1, yj1 = box(j)
                    xk0, yk0, xk1, yk1 = box(k)
                    if xj0 > xk1 or xk0 > xj1 or yj0 > yk1 or yk0 > yj1:
                        continue
                d = penetration_placed(bj, pts(j), bk, pts(k), deepest)
                if d > deepest:
                    deepest, where = d, f"{bj.name} and {bk.name} at t={t!r}"
            active.append(k)
        if e0 != 0.0:
            e = energy(scene, rp, t)
            rel = abs(e - e0) / abs(e0)
            if rel > drift:
                drift, dwhere = rel, f"t={t!r}"
    return InvariantReport(len(times), deepest, where, e0, drift, dwhere)
