"""Event versus frame (issue 6, item 5): the same scenes in our discrete-event
simulator and in pymunk (Chipmunk 2D) stepped at fixed steps; collision-time
error against our exact events, collisions missed (tunnelling) or doubled,
and wall time per simulated second.  `max2code event-vs-frame` writes
docs/event-vs-frame.md, .png and .svg (the design is explained there, in
DESIGN below).

Two comparisons, because multi-body scenes are chaotic:

* replay: for each of our collisions k (the first --max-replays "real" ones
  per scene), pymunk starts from OUR exact state right after the previous
  event (nothing happens in our run between that event and k) and steps
  until a few steps past our time of k; the begin callbacks of k's pair are
  matched to k (error, missed, doubled).  No chaos can creep in: every
  collision is judged from the same start.
* free run: pymunk runs the whole scene from t = 0 (this is also what its
  wall time is taken from); its begin callbacks are matched to our events
  until the first divergence (a real collision of ours with no contact of
  that pair within the window, or a contact of pymunk's with no collision
  of ours), which is reported as a time and a count.
"""
from __future__ import annotations

import json
import math
import os
import platform
import statistics
import sys
import time
from bisect import bisect_left, bisect_right
from collections import defaultdict
from dataclasses import dataclass, field

from max2code.errors import ArgumentParser, Max2CodeError
from max2code.progress import bar
from max2code.paths import ROOT
from max2code.sim.scene import Scene, load_scene, parse_scene

STEPS = (1.0 / 60.0, 1.0 / 240.0, 1.0 / 1000.0)
STEP_NAMES = {1.0 / 60.0: "1/60", 1.0 / 240.0: "1/240", 1.0 / 1000.0: "1/1000"}
WINDOW_STEPS = 3            # matching window: this many steps either side
EXAMPLES = (("billiard break", "examples/billiard-break.json"),
            ("balls under gravity", "examples/gravity-box.json"),
            ("spinning polygons", "examples/spinning-polygons.json"))
OUR_LANGS = ("python", "c", "rust")
COMMAND = "max2code event-vs-frame"
README_BEGIN = "<!-- event-vs-frame:begin (written by max2code event-vs-frame) -->"
README_END = "<!-- event-vs-frame:end -->"


class EvfError(Max2CodeError):
    pass


def tunnel_scene() -> Scene:
    """A bullet (radius 1 cm, 30 m/s) at a 2 cm thick fixed wall.  A stepper
    sees the ball's centre only at t0 + k dt; it can find the contact only if
    one of those centres lies within 1 cm of the wall's 2 cm (a 4 cm span):
    at 1/60 s the ball moves 50 cm a step (from 0.7 m to 1.2 m: over the wall
    untouched), at 1/1000 s 3 cm."""
    return parse_scene(json.dumps({
        "name": "bullet and thin wall (tunnelling)", "end_time": 0.1,
        "bodies": [
            {"name": "bullet", "shape": "circle", "radius": 0.01, "mass": 0.01, "position": [0.2, 0.0],
             "velocity": [30.0, 0.0]},
            {"name": "wall", "shape": "polygon", "fixed": True, "position": [1.0, 0.0],
             "vertices": [[-0.01, -0.5], [0.01, -0.5], [0.01, 0.5], [-0.01, 0.5]]}]}), "<tunnelling case>")


# ------------------------------------------------------------------ states
@dataclass
class State:
    """One body's motion from its own time tb on (exact between events)."""
    tb: float
    px: float
    py: float
    vx: float
    vy: float
    ang: float
    om: float

    def at(self, t: float, ax: float, ay: float) -> tuple[float, float, float, float, float, float]:
        dt = t - self.tb
        return (self.px + (self.vx + 0.5 * ax * dt) * dt, self.py + (self.vy + 0.5 * ay * dt) * dt,
                self.vx + ax * dt, self.vy + ay * dt, self.ang + self.om * dt, self.om)


@dataclass
class Collision:
    """One of our collisions, with everything a replay needs."""
    index: int                  # among our collisions, in time order
    t: float
    a: int
    b: int
    start: float                # time of our previous state-changing event (0: the start)
    states: list                # every body's (px, py, vx, vy, ang, om) at `start`
    approach: float             # normal approach speed of the material points at the contact (m/s)
    resting: bool               # our rest_speed floor set its separation speed (e * approach < rest_speed)


def our_collisions(scene: Scene, events: list[dict]) -> list[Collision]:
    """Our collisions in time order, each with the exact state of every body
    at the previous state-changing event (replayed from the trace: bodies move
    exactly between events) and its approach speed."""
    names = {b.name: i for i, b in enumerate(scene.bodies)}
    acc = [b.acceleration for b in scene.bodies]     # in force now (a supported body's differs)
    cur = [State(0.0, b.position[0], b.position[1], b.velocity[0], b.velocity[1], b.angle, b.angular_velocity)
           for b in scene.bodies]
    last = 0.0
    out: list[Collision] = []
    for ev in events:
        kind = ev["kind"]
        if kind not in ("collision", "support", "stop", "leave", "sleep", "wake", "input"):
            continue
        t = ev["t"]
        if kind == "collision":
            a, b = names[ev["bodies"][0]], names[ev["bodies"][1]]
            snap = [s.at(last, *acc[i]) for i, s in enumerate(cur)]
            # approach speed of the material points at the contact point, just before
            cx, cy = ev["point"]
            nx, ny = ev["normal"]
            u = []
            for i in (a, b):
                px, py, vx, vy, _, om = cur[i].at(t, *acc[i])
                if scene.bodies[i].polygon or scene.bodies[i].orbit_radius > 0.0:
                    u.append((vx - om * (cy - py), vy + om * (cx - px)))
                else:
                    u.append((vx, vy))
            vn = (u[1][0] - u[0][0]) * nx + (u[1][1] - u[0][1]) * ny
            approach = -vn
            e = scene.bodies[a].restitution * scene.bodies[b].restitution
            resting = e * approach < min(approach, scene.rest_speed)
            out.append(Collision(len(out), t, min(a, b), max(a, b), last, snap, approach, resting))
        for st in ev.get("states", ()):
            i = names[st["body"]]
            cur[i] = State(t, st["position"][0], st["position"][1], st["velocity"][0], st["velocity"][1],
                           st["angle"], st["angular_velocity"])
            if "acceleration" in st:
                acc[i] = tuple(st["acceleration"])
        last = t
    return out


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


def build_space(scene: Scene, states=None, t0: float = 0.0) -> FrameWorld:
    """A faithful pymunk translation of `scene`, every body at the state
    given (px, py, vx, vy, angle, omega) or its initial one: circles (infinite
    moment: with friction 0 a contact never turns them, as in ours; an orbit
    is an offset on a kinematic body), convex polygons with their vertices
    about the centre of mass and our moment of inertia (mass * second moment
    / area), fixed bodies static (kinematic when they move or spin),
    elasticity = our restitution (Chipmunk multiplies the two, as we do),
    friction 0, the scene's gravity; collision_slop 0 and collision_bias 0."""
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
            moving = vx != 0.0 or vy != 0.0 or om != 0.0
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
        shape.friction = 0.0
        space.add(body, shape)
        index[shape] = i
        bodies.append(body)
    world = FrameWorld(space, bodies, index, t0=t0)

    def begin(arbiter, space, data):
        s1, s2 = arbiter.shapes
        i, j = index[s1], index[s2]
        world.begins.append((world.t0 + (world.steps + 1) * world.dt, min(i, j), max(i, j)))

    space.on_collision(begin=begin)
    return world


def step_until(world: FrameWorld, dt: float, t_end: float) -> None:
    """Step with dt until the world's time reaches t_end (the contact of a
    step is found at the positions at its end: Chipmunk integrates the
    positions first)."""
    world.dt = dt
    n = max(0, math.ceil((t_end - world.t0) / dt - 1e-9))
    step = world.space.step
    while world.steps < n:
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


# ------------------------------------------------------------------ matching
@dataclass
class Match:
    pairs: list             # (our index, their index)
    errors: list            # their time - our time, per matched pair
    missed: list            # our indices with no contact of their pair within the window
    doubled: list           # their indices: a further begin of a pair within the window of a matched collision
    invented: list          # their indices matching nothing of ours


def match_events(ours: list, theirs: list, window: float) -> Match:
    """Match contact starts `theirs` [(t, a, b)] to our collisions `ours`
    [(t, a, b)], pairs unordered: each of ours, in time order, takes the
    earliest unused start of the same pair within `window` of its time.
    Starts left over are doubles when within the window of a matched
    collision of their pair, else invented."""
    key = lambda e: (min(e[1], e[2]), max(e[1], e[2]))
    by_pair: dict = defaultdict(list)
    for j in sorted(range(len(theirs)), key=lambda j: theirs[j][0]):
        by_pair[key(theirs[j])].append(j)
    used: set = set()
    pairs, errors, missed = [], [], []
    matched_times: dict = defaultdict(list)
    for i in sorted(range(len(ours)), key=lambda i: ours[i][0]):
        t = ours[i][0]
        cands = by_pair.get(key(ours[i]), [])
        times = [theirs[j][0] for j in cands]
        found = None
        for k in range(bisect_left(times, t - window), bisect_right(times, t + window)):
            if cands[k] not in used:
                found = cands[k]
                break
        if found is None:
            missed.append(i)
        else:
            used.add(found)
            pairs.append((i, found))
            errors.append(theirs[found][0] - t)
            matched_times[key(ours[i])].append(t)
    doubled, invented = [], []
    for j in range(len(theirs)):
        if j in used:
            continue
        tj = theirs[j][0]
        if any(abs(tj - t) <= window for t in matched_times.get(key(theirs[j]), ())):
            doubled.append(j)
        else:
            invented.append(j)
    return Match(pairs, errors, missed, doubled, invented)


# ------------------------------------------------------------------ one scene
@dataclass
class FrameResult:
    step: float
    compared: int = 0           # replayed collisions
    errors: list = field(default_factory=list)   # |their - our| of the matched replays
    missed: int = 0
    doubled: int = 0
    early: int = 0              # contacts of the pair found before our collision, beyond the window
    free_begins: int = 0
    agree_until: float = 0.0    # free run: time of the first divergence (end time: none)
    agree_count: int = 0        # free run: our real collisions matched before it
    free_errors: list = field(default_factory=list)
    wall_per_s: float = 0.0


@dataclass
class OurResult:
    lang: str
    wall: float                 # whole run_scene: compile the scene, start the process, simulate, write and parse the trace
    wall_per_s: float
    collisions: int
    note: str = ""


@dataclass
class SceneResult:
    label: str
    path: str
    scene: Scene
    ours: list
    collisions: int
    resting: int
    replayed: int
    frames: list


def replay(scene: Scene, cols: list[Collision], k: int, dt: float) -> tuple[float, int, int]:
    """Replay our collision k in pymunk from our exact state at the previous
    event.  Returns k's error (pymunk's begin time - ours; nan: missed), the
    begins that double it, and the begins of its pair found more than the
    window before it.

    The steps end on the global grid n dt, as in a frame engine that started
    at t = 0: a first, shorter step takes the world from our previous event
    to the next grid point, and a fresh Space goes on from there with steps
    of dt (a fresh one because Chipmunk warm-starts a contact with its last
    impulse times dt / previous dt, which a short first step would blow up).
    A contact of k's pair that goes on across the two is one contact.

    A double is a further begin of k's pair within the window of the matched
    one and before our next collision involving either body: until then the
    two bodies fly freely in the exact motion, so a second begin is the
    same contact reported again, not a consequence of another collision."""
    c = cols[k]
    window = WINDOW_STEPS * dt
    g0 = (math.floor(c.start / dt) + 1) * dt
    states, t0, begins, across = c.states, c.start, [], False
    if g0 - c.start < dt * (1.0 - 1e-9):
        first = build_space(scene, c.states, c.start)
        first.dt = g0 - c.start
        first.space.step(first.dt)
        begins += first.begins
        states, t0, across = read_states(first), g0, touching(first, c.a, c.b)
    if c.t + window > t0:
        world = build_space(scene, states, t0)
        step_until(world, dt, c.t + window)
        for e in world.begins:
            if across and (e[1], e[2]) == (c.a, c.b) and e[0] == t0 + dt:
                continue
            begins.append(e)
    theirs = [e for e in begins if (e[1], e[2]) == (c.a, c.b)]
    ours = [(x.t, x.a, x.b) for x in cols[k:] if x.t <= c.t + window and (x.a, x.b) == (c.a, c.b)]
    m = match_events(ours, theirs, window)
    err = next((e for (i, _), e in zip(m.pairs, m.errors) if i == 0), math.nan)
    horizon = next((x.t for x in cols[k + 1:] if {x.a, x.b} & {c.a, c.b}), math.inf)
    doubled = sum(1 for j in m.doubled if theirs[j][0] <= horizon)
    early = sum(1 for j in m.invented if theirs[j][0] < c.t - window)
    return err, doubled, early


def free_run(scene: Scene, cols: list[Collision], dt: float, res: FrameResult) -> None:
    """The whole scene in pymunk from t = 0: wall time, and agreement with
    our events until the first divergence."""
    def one():
        w = build_space(scene)
        t0 = time.perf_counter()
        step_until(w, dt, scene.end_time)
        return w, time.perf_counter() - t0
    world, wall = one()
    for _ in range(2):
        if wall * 2 > 3.0:
            break
        wall = min(wall, one()[1])
    res.wall_per_s = wall / scene.end_time
    res.free_begins = len(world.begins)
    window = WINDOW_STEPS * dt
    m = match_events([(c.t, c.a, c.b) for c in cols], world.begins, window)
    div = [cols[i].t for i in m.missed if not cols[i].resting] + [world.begins[j][0] for j in m.invented]
    res.agree_until = min(div) if div else scene.end_time
    for (i, j), e in zip(m.pairs, m.errors):
        if cols[i].t < res.agree_until and not cols[i].resting:
            res.agree_count += 1
            res.free_errors.append(abs(e))


def best_of(fn, budget: float = 3.0, runs: int = 3):
    """(first result, smallest wall seconds) of up to `runs` calls of fn,
    fewer when they take more than `budget` seconds together."""
    result, best, spent = None, math.inf, 0.0
    for k in range(runs):
        t0 = time.perf_counter()
        r = fn()
        took = time.perf_counter() - t0
        result = r if k == 0 else result
        best, spent = min(best, took), spent + took
        if spent > budget:
            break
    return result, best


def run_ours(scene: Scene, lang: str, runs: int = 3):
    """(trace, wall seconds, best of up to `runs`) of run_scene in `lang`,
    the build done before the clock starts."""
    from max2code.sim.simulate import build_simulator, run_scene
    build_simulator(lang, scene.effects, scene.taylor_order)
    return best_of(lambda: run_scene(scene, lang), runs=runs)


def startup_seconds(lang: str) -> float:
    """Wall time of run_scene for a one-ball scene that ends at once: process
    start, reading the scene, writing and parsing the trace (best of 3)."""
    scene = parse_scene(json.dumps({"name": "start-up", "end_time": 1e-6, "bodies": [
        {"shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}]}), "<start-up>")
    return run_ours(scene, lang)[1]


def ours_available(lang: str) -> str:
    """'' when this runtime's simulator builds and runs, else why not."""
    try:
        startup = parse_scene(json.dumps({"end_time": 1e-6, "bodies": [
            {"shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}]}), "<probe>")
        run_ours(startup, lang, runs=1)
    except Exception as exc:       # not built yet, or fails: the report says so
        return f"{type(exc).__name__}: {str(exc).strip().splitlines()[0][:160] if str(exc).strip() else ''}"
    return ""


# ------------------------------------------------------------------ the sweep
def sweep(langs=OUR_LANGS, steps=STEPS, max_replays: int = 300, progress: bool = True):
    scenes = [(label, path, load_scene(str(ROOT / path))) for label, path in EXAMPLES]
    scenes.append(("tunnelling", "(built in: event_vs_frame.tunnel_scene)", tunnel_scene()))
    avail = {lang: ours_available(lang) for lang in langs}
    startup = {lang: startup_seconds(lang) for lang in langs if not avail[lang]}
    work = len(scenes) * (len(langs) + len(steps))
    done = 0
    results = []
    for label, path, scene in scenes:
        ours = []
        ref = None
        for lang in langs:
            if progress:
                bar(done, work, f"{label}: ours in {lang}", "event-vs-frame")
            done += 1
            if avail[lang]:
                ours.append(OurResult(lang, math.nan, math.nan, 0, f"not run: {avail[lang]}"))
                continue
            trace, wall = run_ours(scene, lang)
            n = sum(1 for e in trace.events if e["kind"] == "collision")
            note = ""
            if ref is None:
                ref = trace
            else:
                from max2code.sim.commands import compare
                d = compare(ref, trace)
                note = f"agrees with {ref.lang}" if d is None else f"differs from {ref.lang}: {d.what}"
            ours.append(OurResult(lang, wall, wall / scene.end_time, n, note))
        if ref is None:
            raise EvfError("no runtime of ours ran: " + "; ".join(f"{k}: {v}" for k, v in avail.items()))
        cols = our_collisions(scene, ref.events)
        real = [c for c in cols if not c.resting][:max_replays]
        frames = []
        for dt in steps:
            if progress:
                bar(done, work, f"{label}: pymunk at {STEP_NAMES.get(dt, f'{dt:g}')} s", "event-vs-frame")
            done += 1
            res = FrameResult(dt)
            free_run(scene, cols, dt, res)
            for c in real:
                err, doubled, early = replay(scene, cols, c.index, dt)
                res.compared += 1
                if math.isnan(err):
                    res.missed += 1
                else:
                    res.errors.append(abs(err))
                res.doubled += doubled
                res.early += early
            frames.append(res)
        results.append(SceneResult(label, path, scene, ours, len(cols), sum(c.resting for c in cols),
                                   len(real), frames))
    if progress:
        bar(work, work, "done", "event-vs-frame")
    return results, avail, startup


# ------------------------------------------------------------------ report
def _s(x: float) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if x == 0.0:
        return "0"
    if abs(x) >= 100:
        return f"{x:,.0f}"
    return f"{x:.3g}"


def _ms(x: float) -> str:
    return "-" if x is None or math.isnan(x) else f"{x * 1e3:.3g}"


def _less(o, startup: dict, end: float) -> str:
    """Wall time per simulated second less the start-up (measured apart, so
    under load it can exceed a short run)."""
    if o.lang not in startup:
        return "-"
    d = o.wall - startup[o.lang]
    return _s(d / end) if d > 0.0 else "within start-up"


def table(results, startup: dict) -> list[str]:
    out = ["| scene | run | collisions (ours) / contacts (pymunk) | replayed | median error ms | max error ms "
           "| missed | doubled | free run: agrees until s (collisions) | wall s per simulated s |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        for o in r.ours:
            if math.isnan(o.wall):
                out.append(f"| {r.label} | ours, {o.lang} | - | - | - | - | - | - | - | not available |")
                continue
            exact = "within the tolerance" if "orbit" in r.scene.effects else "exact"
            out.append(f"| {r.label} | ours, {o.lang} | {o.collisions} ({r.resting} rest-speed) | - | {exact} | "
                       f"{exact} | 0 | 0 | {_s(r.scene.end_time)} (all) | {_s(o.wall_per_s)} "
                       f"(less start-up: {_less(o, startup, r.scene.end_time)}) |")
        for f in r.frames:
            med = statistics.median(f.errors) if f.errors else math.nan
            mx = max(f.errors) if f.errors else math.nan
            out.append(f"| {r.label} | pymunk {STEP_NAMES.get(f.step, f'{f.step:g}')} s | {f.free_begins} | "
                       f"{f.compared} | {_ms(med)} | {_ms(mx)} | {f.missed} | {f.doubled} | "
                       f"{_s(f.agree_until)} ({f.agree_count}) | {_s(f.wall_per_s)} |")
    return out


def headline(results, startup: dict) -> list[str]:
    """One row per step: totals over the example scenes (the tunnelling case apart)."""
    out = ["| run | collisions replayed | median error ms | max error ms | missed | doubled | "
           "wall s per simulated s, billiard / gravity / polygons (ours: less start-up) |", "|---|---|---|---|---|---|---|"]
    ex = [r for r in results if r.label != "tunnelling"]
    langs = [o.lang for o in ex[0].ours if not math.isnan(o.wall)]
    for lang in langs:
        walls = " / ".join(f"{_s(o.wall_per_s)} ({_less(o, startup, r.scene.end_time)})"
                           for r in ex for o in r.ours if o.lang == lang)
        out.append(f"| ours, {lang} | all | exact (rotation: within the tolerance) | - | 0 | 0 | {walls} |")
    for k, dt in enumerate(ex[0].frames):
        errs = [e for r in ex for e in r.frames[k].errors]
        n = sum(r.frames[k].compared for r in ex)
        missed = sum(r.frames[k].missed for r in ex)
        doubled = sum(r.frames[k].doubled for r in ex)
        walls = " / ".join(_s(r.frames[k].wall_per_s) for r in ex)
        out.append(f"| pymunk {STEP_NAMES.get(dt.step, f'{dt.step:g}')} s | {n} | "
                   f"{_ms(statistics.median(errs) if errs else math.nan)} | {_ms(max(errs) if errs else math.nan)} | "
                   f"{missed} ({100.0 * missed / max(n, 1):.1f} %) | {doubled} | {walls} |")
    tun = [r for r in results if r.label == "tunnelling"]
    if tun:
        t = tun[0]
        found = {STEP_NAMES.get(f.step, f"{f.step:g}"): ("found" if f.missed == 0 else "missed") for f in t.frames}
        out.append("")
        out.append("Tunnelling case (a 1 cm bullet at 30 m/s, a 2 cm wall): ours finds the contact; pymunk "
                   + ", ".join(f"{k} s: {v}" for k, v in found.items()) + ".")
    return out


def plot(results, png: str, svg: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.6))
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    styles = {"python": ":", "c": "--", "rust": "-."}
    for r, col in zip(results, colors):
        dts = [f.step for f in r.frames]
        med = [statistics.median(f.errors) if f.errors else math.nan for f in r.frames]
        mx = [max(f.errors) if f.errors else math.nan for f in r.frames]
        axes[0].plot(dts, med, "o-", color=col, label=f"{r.label} (median)")
        axes[0].plot(dts, mx, "^--", color=col, alpha=0.5, label=f"{r.label} (max)")
        miss = [100.0 * f.missed / max(f.compared, 1) for f in r.frames]
        dbl = [100.0 * f.doubled / max(f.compared, 1) for f in r.frames]
        axes[1].plot(dts, miss, "o-", color=col, label=f"{r.label}: missed")
        axes[1].plot(dts, dbl, "s--", color=col, alpha=0.5, label=f"{r.label}: doubled")
        if r.label == "tunnelling":     # 0.1 s simulated: our figure there is start-up
            continue
        axes[2].plot(dts, [f.wall_per_s for f in r.frames], "o-", color=col, label=f"{r.label}: pymunk")
        for o in r.ours:
            if not math.isnan(o.wall_per_s):
                axes[2].axhline(o.wall_per_s, color=col, linestyle=styles.get(o.lang, "-"), linewidth=1,
                                label=f"{r.label}: ours, {o.lang}")
    grid = sorted({f.step for r in results for f in r.frames})
    axes[0].plot(grid, grid, color="grey", linewidth=1, label="one step")
    axes[0].set(xscale="log", yscale="log", xlabel="pymunk step (s)", ylabel="|contact time - exact| (s)",
                title="collision-time error (replayed from exact states)")
    axes[1].set(xscale="log", xlabel="pymunk step (s)", ylabel="% of replayed collisions",
                title="missed (tunnelling) and doubled contacts")
    axes[2].set(xscale="log", yscale="log", xlabel="pymunk step (s)", ylabel="wall s per simulated s",
                title="wall time (ours: horizontal lines)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=6)
    axes[1].legend(fontsize=6)
    axes[2].legend(fontsize=6, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.14))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    fig.savefig(svg, metadata={"Date": None})
    plt.close(fig)


DESIGN = """\
## What is compared, and how

**Scenes.** The three example scenes (`examples/billiard-break.json`,
`examples/gravity-box.json`, `examples/spinning-polygons.json`, made by
`examples/make_examples.py`) and a tunnelling case built in
(`max2code.reports.event_vs_frame.tunnel_scene`): a bullet of radius 1 cm at 30 m/s
towards a fixed wall 2 cm thick.

**Ours.** `max2code.sim.simulate.run_scene(scene, lang)` for the Python runtime
and, when they build and run on this machine (checked at run time), the C
and Rust runtimes.  Its collision events are the exact answer: exact up to
rounding for scenes without rotation; within the scene's distance tolerance
(1e-9 m) when polygons spin (Taylor windows).  The wall time is the whole
`run_scene` call, the build done beforehand (cached): compiling the JSON
scene to the flat format, starting the process (for Python, the
interpreter and its imports), the simulator reading the scene, simulating
(with the scene's 60 frame events a second) and writing the trace to a pipe,
and Python parsing the trace back.  The start-up alone (a one-ball scene
that ends at once) is listed below the table.

**pymunk.** Each scene is translated into a `pymunk.Space` by
`build_space`: circles with an infinite moment (with friction 0 no contact
turns them, as in ours), an orbiting circle as an offset on a kinematic body;
convex polygons with their vertices about the centre of mass and our moment
of inertia (mass times second moment of area over area, from
`max2code/sim/scene.py`), not pymunk's own; fixed bodies static, or kinematic
when they move or spin; elasticity = our restitution (Chipmunk multiplies
the two shapes' values, as we do); friction 0; the scene's gravity; no
damping, no sleeping, the default 10 solver iterations.  `collision_slop`
is 0 (no overlap is tolerated: a contact begins as soon as the shapes
overlap) and `collision_bias` is 0 (the smallest value: the fraction of an
overlap left after one second, so an overlap is pushed out within one step);
the defaults are 0.1 and 0.0018.  Chipmunk integrates positions first,
then finds contacts: a contact *begin* callback seen during the step from
`t` to `t + dt` is dated `t + dt`, the time of the positions it saw.

**Our rest speed.** Our model gives every contact a separation speed of at
least `min(approach, rest_speed)` (0.05 m/s, docs/simulator.md), so that under
gravity a resting body keeps hopping 0.13 mm high where Chipmunk holds one
persistent contact.  A collision of ours where this floor set the separation
speed (restitution times approach speed below `min(approach, rest_speed)`)
is a *rest-speed* collision: no frame engine has it, so it is left out of
the replays and of the free run's divergence (the table gives how many).

**Replay (error, missed, doubled).** A multi-body scene is chaotic: after a
few collisions two simulators follow different histories, and comparing
their events one to one would measure the chaos, not the stepping.  So each
of our real collisions k (the first %(max_replays)d per scene, in time order) is
replayed on its own: pymunk starts from *our* exact state of every body at
our previous event (collision or input; between it and k nothing happens in
our run: every body is in free flight), and steps until %(window)d steps
after our time of k.  Its steps end on the global grid `n dt`, as in a frame
engine started at t = 0 (otherwise a collision that follows another closely,
as in the billiard rack, would always be found a whole step late): a first,
shorter step takes it to the next grid point, and a fresh Space goes on
with steps of `dt` (fresh, because Chipmunk warm-starts a contact with its
last impulse times `dt / previous dt`, which the short step would blow up;
a contact of k's pair that goes on across the two is one contact).  Its
begin callbacks for k's pair of bodies are matched to our collisions of that pair in the same span by
`match_events` (each of ours, in time order, takes the earliest unused begin
of its pair within %(window)d steps).  Then:
* *error*: |pymunk's begin time - our time| of k, when matched; the table
  gives the median and maximum in milliseconds;
* *missed*: no begin of k's pair within %(window)d steps of our time: the
  stepper tunnelled through (or stepped around) the contact;
* *doubled*: a further begin of the same pair within %(window)d steps of the
  matched one that no collision of ours accounts for, before our next
  collision of either body (until then both fly freely in the exact motion:
  the contact was lost and found again, not changed by a third body).

The statistics are over the replays; a scene with more real collisions than
%(max_replays)d contributes its first %(max_replays)d.

The window of %(window)d steps is wide enough for a detection that is up to one
step late plus the drift of Chipmunk's semi-implicit Euler under gravity
(it lags the exact parabola by `g (t - t0) dt / 2`), and narrow enough not
to match an unrelated later contact of the same pair.

**Where our time goes.** Under gravity most of our collisions are rest-speed
hops of bodies lying on the floor or on each other (the table counts them),
and they are most of our wall time there; a frame engine pays per step
instead, whatever happens.  Our start-up (a fresh process per run) is
listed below the table and subtracted in brackets.

**Free run (divergence).** pymunk also runs each scene from t = 0 to the
end on its own; its wall time per simulated second is taken from this run
(the stepping only, the Python begin callback included: it runs once per
contact start; best of up to 3 runs, as for ours).  Its begin callbacks are matched to all our events with
the same rule; the *divergence* is the first of: a real collision of ours
with no begin of its pair within the window, or a begin with no collision
of ours.  The table gives its time and how many real collisions agreed
before it.  After it the two runs are different histories.

What is not modelled alike: our `rest_speed` floor (above); Chipmunk solves
simultaneous contacts (the billiard rack, whose balls are 5.7e-9 m apart)
together with an iterative solver where we resolve them one pair at a time
in time order; Chipmunk's restitution uses the normal velocity at the start
of the step.
"""


def write_report(results, avail, startup, out_dir: str, argv: list[str], max_replays: int,
                 load: list[float]) -> list[str]:
    import pymunk
    os.makedirs(out_dir, exist_ok=True)
    md = os.path.join(out_dir, "event-vs-frame.md")
    png = os.path.join(out_dir, "event-vs-frame.png")
    svg = os.path.join(out_dir, "event-vs-frame.svg")
    plot(results, png, svg)
    cmd = " ".join([COMMAND, *argv])
    lines = ["# Event versus frame: our simulator against pymunk (Chipmunk) at fixed steps", "",
             f"Made by `{cmd}` (this machine: {platform.machine()}, {os.cpu_count()} cores, "
             f"Python {platform.python_version()}, pymunk {pymunk.version}, Chipmunk "
             f"{pymunk.chipmunk_version.split('-')[0]}; load average {load[0]:.2f} before the sweep, {load[-1]:.2f} "
             "after: wall times are single-machine figures, best of up to 3 runs).  Nothing below is typed by "
             "hand.", "",
             "## Headline (the three example scenes together)", "", *headline(results, startup), "",
             "## Per scene", "", *table(results, startup), "",
             "Columns: *collisions (ours)*: our collision events (rest-speed collisions in brackets); *contacts (pymunk)*: "
             "begin callbacks in pymunk's free run; *replayed*: our collisions other than rest-speed ones (at most --max-replays) replayed in pymunk from our "
             "exact state; *error*, *missed*, *doubled*: of those replays; *free run*: the time of the first "
             "divergence of pymunk's free run from ours and the real collisions that agreed before it.", ""]
    lines.append("Start-up of our runs (included in their wall time above; a one-ball scene that ends at once, "
                 "best of 3): " + ", ".join(f"{lang} {startup[lang]:.3f} s" for lang in startup) + ".")
    for lang, why in avail.items():
        if why:
            lines.append("")
            lines.append(f"Our {lang} runtime was not available when this was made ({why}).")
    early = [f"{r.label} at {STEP_NAMES.get(f.step, f'{f.step:g}')} s: {f.early}" for r in results for f in r.frames
             if f.early]
    lines += ["", "Replays in which pymunk found the pair's contact more than the window *before* ours: "
              + ("; ".join(early) if early else "none") + "."]
    notes = [f"{r.label}, {o.lang}: {o.note}" for r in results for o in r.ours if o.note and not math.isnan(o.wall)]
    if notes:
        lines += ["", "Our runtimes against each other (`max2code crosscheck` rule): " + "; ".join(notes) + "."]
    lines += ["", "![error, missed and wall time against the step](event-vs-frame.png)", "",
              "([SVG](event-vs-frame.svg))", "",
              DESIGN % {"max_replays": max_replays, "window": WINDOW_STEPS}]
    with open(md, "w", encoding="utf-8") as f:
        f.write("\n".join(lines).rstrip() + "\n")
    return [md, png, svg]


def update_readme(results, startup: dict, argv: list[str]) -> bool:
    """Rewrite the block between the README markers with the headline (if
    the markers are there)."""
    path = ROOT / "README.md"
    text = path.read_text(encoding="utf-8")
    if README_BEGIN not in text or README_END not in text:
        return False
    head, rest = text.split(README_BEGIN, 1)
    _, tail = rest.split(README_END, 1)
    cmd = " ".join([COMMAND, *argv])
    block = [README_BEGIN, "", f"(`{cmd}`; full table, design and plot in "
             "[docs/event-vs-frame.md](docs/event-vs-frame.md))", "", *headline(results, startup), "", README_END]
    path.write_text(head + "\n".join(block) + tail, encoding="utf-8")
    return True


def main(argv: list[str]) -> int:
    p = ArgumentParser(prog=COMMAND,
                                description="Run the example scenes in our simulator and in pymunk at fixed steps "
                                            "(1/60, 1/240, 1/1000 s); write docs/event-vs-frame.md, .png and .svg "
                                            "and the headline in README.md.")
    p.add_argument("--langs", default=",".join(OUR_LANGS),
                   help=f"our runtimes to run and time, when available (default {','.join(OUR_LANGS)})")
    p.add_argument("--max-replays", type=int, default=300, metavar="N",
                   help="replay at most the first N real collisions per scene (default 300)")
    p.add_argument("--out-dir", default=str(ROOT / "docs"), help="where the report goes (default docs/)")
    p.add_argument("--no-readme", action="store_true", help="leave README.md alone")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    args = p.parse_args(argv)
    langs = tuple(x for x in args.langs.split(",") if x)
    for lang in langs:
        if lang not in OUR_LANGS:
            raise EvfError(f"--langs: unknown runtime '{lang}' (expected some of {', '.join(OUR_LANGS)})")
    if args.max_replays < 1:
        raise EvfError("--max-replays must be at least 1")
    _pymunk()
    load = [os.getloadavg()[0]]
    results, avail, startup = sweep(langs, STEPS, args.max_replays, not args.quiet)
    load.append(os.getloadavg()[0])
    shown = [a for a in argv if a not in ("-q", "--quiet", "--no-readme")]
    files = write_report(results, avail, startup, args.out_dir, shown, args.max_replays, load)
    if not args.no_readme and update_readme(results, startup, shown):
        files.append(str(ROOT / "README.md"))
    print("\n".join(headline(results, startup)))
    print(f"{COMMAND}: wrote {', '.join(files)}", file=sys.stderr)
    return 0
