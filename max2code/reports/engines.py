"""The engines the reports compare: pymunk stepped at fixed steps (a
faithful translation of a scene, its contact starts recorded) and the CPU
time of our simulator on a scene, less its start-up."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from max2code.errors import Max2CodeError
from max2code.sim.scene import Scene, compile_scene
from max2code.sim.simulate import build_simulator, time_engine

START = 1e-9                        # s: the end time of the start-up run (the scene's start and nothing else)


class EvfError(Max2CodeError):
    pass


# ------------------------------------------------------------------ pymunk
def _pymunk():
    try:
        import pymunk
    except ImportError:
        raise EvfError("event-vs-frame needs pymunk (bash scripts/setup installs it)") from None
    return pymunk


@dataclass
class FrameWorld:
    """A pymunk Space made from a scene, and the begin callbacks it records."""
    space: object
    bodies: list                # pymunk bodies, in the scene's order
    index: dict                 # shape -> body index
    begins: list = field(default_factory=list)   # (t, a, b), a < b: contact starts, t = end of the step
    t0: float = 0.0
    steps: int = 0
    dt: float = 0.0
    inputs: list = field(default_factory=list)   # the scene's inputs still to apply (a free run from t = 0)


def build_space(scene: Scene, states=None, t0: float = 0.0, begins: bool = True) -> FrameWorld:
    """A faithful pymunk translation of `scene`, every body at the state
    given (px, py, vx, vy, angle, omega) or its initial one: circles (infinite
    moment: with friction 0 a contact never turns them, as in ours; an orbit
    is an offset on a kinematic body), convex polygons with their vertices
    about the centre of mass and our moment of inertia (mass * second moment
    / area), fixed bodies static (kinematic when they move or spin),
    elasticity = our restitution and friction = our friction coefficient
    (Chipmunk's arbiter multiplies the two shapes' values, as we do), the
    scene's gravity; collision_slop 0 and collision_bias 0.  With `begins`
    a begin callback records every contact start in world.begins."""
    pymunk = _pymunk()
    space = pymunk.Space()
    space.gravity = scene.gravity
    space.collision_slop = 0.0      # no allowed overlap: contacts as soon as shapes overlap
    space.collision_bias = 0.0      # 0 fraction of an overlap left after 1 s: removed within one step
    index = {}
    bodies = []
    for i, b in enumerate(scene.bodies):
        if states is None:
            px, py, vx, vy, ang, om = (*b.position, *b.velocity, b.angle, b.angular_velocity)
        else:
            px, py, vx, vy, ang, om = states[i]
        if b.fixed:
            if b.acceleration != (0.0, 0.0):
                raise EvfError(f"{scene.path}: {b.name}: a fixed body that accelerates has no pymunk counterpart")
            # kinematic when it moves or turns, or an input sets its velocity later
            moving = vx != 0.0 or vy != 0.0 or om != 0.0 or any(e.body == i for e in scene.inputs)
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC if moving else pymunk.Body.STATIC)
        else:
            body = pymunk.Body(b.mass, b.inertia if b.polygon else math.inf)
            if b.acceleration != tuple(scene.gravity):
                own = b.acceleration

                def velocity_func(body, gravity, damping, dt, own=own):
                    pymunk.Body.update_velocity(body, own, damping, dt)
                body.velocity_func = velocity_func
        body.position = (px, py)
        body.angle = ang
        if not (b.fixed and body.body_type == pymunk.Body.STATIC):
            body.velocity = (vx, vy)
            body.angular_velocity = om
        if b.polygon:
            shape = pymunk.Poly(body, b.vertices, radius=0.0)
        else:
            off = (b.orbit_radius * math.cos(b.orbit_angle), b.orbit_radius * math.sin(b.orbit_angle)) \
                if b.orbit_radius > 0.0 else (0.0, 0.0)
            shape = pymunk.Circle(body, b.radius, off)
        shape.elasticity = b.restitution
        shape.friction = b.friction
        space.add(body, shape)
        index[shape] = i
        bodies.append(body)
    world = FrameWorld(space, bodies, index, t0=t0)

    def begin(arbiter, space, data):
        s1, s2 = arbiter.shapes
        i, j = index[s1], index[s2]
        world.begins.append((world.t0 + (world.steps + 1) * world.dt, min(i, j), max(i, j)))

    if begins:
        space.on_collision(begin=begin)
    return world


def step_until(world: FrameWorld, dt: float, t_end: float) -> None:
    """Step with dt until the world's time reaches t_end (the contact of a
    step is found at the positions at its end: Chipmunk integrates the
    positions first).  The world's inputs are applied as a game applies
    them: before the first step that starts at or after the input's time."""
    world.dt = dt
    n = max(0, math.ceil((t_end - world.t0) / dt - 1e-9))
    step = world.space.step
    while world.steps < n:
        if world.inputs:
            now = world.t0 + world.steps * dt
            while world.inputs and world.inputs[0].time <= now + 1e-12 * dt:
                inp = world.inputs.pop(0)
                body = world.bodies[inp.body]
                vx, vy = inp.velocity
                if inp.mode == 1:
                    vx, vy = body.velocity.x + vx, body.velocity.y + vy
                body.velocity = (vx, vy)
        step(dt)
        world.steps += 1


def read_states(world: FrameWorld) -> list:
    return [(b.position.x, b.position.y, b.velocity.x, b.velocity.y, b.angle, b.angular_velocity)
            for b in world.bodies]


def touching(world: FrameWorld, a: int, b: int) -> bool:
    """Whether bodies a and b are in contact after the world's last step."""
    arbs = []
    world.bodies[a].each_arbiter(lambda arb: arbs.append(arb))
    return any({world.index[s] for s in arb.shapes} == {a, b} for arb in arbs)


@dataclass
class OurResult:
    lang: str
    cpu: float = math.nan       # CPU seconds of the simulator's process on the whole scene (best of several runs)
    start: float = math.nan     # the same for the scene ended at START: reading it, the first predictions, the final states
    counts: dict = field(default_factory=dict)   # the trace's N counters, by name, in the trace's order
    note: str = ""

    @property
    def ran(self) -> bool:
        return not math.isnan(self.cpu)

    def cpu_per_s(self, end: float) -> float:
        """CPU seconds per simulated second less the start-up (nan when the
        difference is not positive: a run within its start-up's noise)."""
        d = self.cpu - self.start
        return d / end if d > 0.0 else math.nan


def best_cpu(fn, budget: float = 2.0, runs: int = 10) -> tuple[float, dict]:
    """(smallest CPU seconds, counters) of up to `runs` calls of fn, which
    returns (wall, cpu, counters); fewer calls when they take more than
    `budget` CPU seconds together (a short run is repeated more: its
    difference from the start-up is a fraction of a millisecond)."""
    best, spent, counts = math.inf, 0.0, {}
    for _ in range(runs):
        _, cpu, counts = fn()
        best, spent = min(best, cpu), spent + cpu
        if spent > budget:
            break
    return best, counts


def start_scene(scene: Scene) -> Scene:
    """The scene ended at START (its start-up run), without the inputs
    after START (a scene refuses inputs after its end)."""
    end = min(START, scene.end_time)
    return scene.replace(end_time=end, inputs=[e for e in scene.inputs if e.time <= end])


def time_ours(scene: Scene, lang: str) -> OurResult:
    """CPU seconds of `lang`'s simulator process on the scene and on the
    same scene ended at START (its start-up: process start, reading the
    scene, every pair's first prediction, the final states), best of up to
    10 each (fewer when they take more than 2 s together); the build is
    done before (cached)."""
    build = build_simulator(lang, scene.effects, scene.taylor_order)
    flat = compile_scene(scene)
    first = compile_scene(start_scene(scene))
    cpu, counts = best_cpu(lambda: time_engine(build, flat))
    start, _ = best_cpu(lambda: time_engine(build, first))
    return OurResult(lang, cpu, start, counts)
