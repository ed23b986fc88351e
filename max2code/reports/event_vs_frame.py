"""Event versus frame: every example scene in our discrete-event simulator
and in pymunk (Chipmunk 2D) stepped at fixed steps; collision-time error
against our exact events, collisions missed (tunnelling) or doubled, CPU
time per simulated second (ours less the start-up), and our events by kind.
`max2code event-vs-frame` writes docs/event-vs-frame.md, .png and .svg (the
design is explained there, in DESIGN below).

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

from max2code.errors import ArgumentParser
from max2code.progress import bar
from max2code.paths import ROOT
from max2code.sim.scene import Scene, load_scene, parse_scene
from max2code.sim.commands import compare
from max2code.reports.engines import EvfError, OurResult, _pymunk, build_space, read_states, step_until, time_ours, touching
from max2code.sim.simulate import LANGS, WORK_COUNTERS, SimulateError, handled_events, run_scene

STEPS = (1.0 / 60.0, 1.0 / 240.0, 1.0 / 1000.0)
STEP_NAMES = {1.0 / 60.0: "1/60", 1.0 / 240.0: "1/240", 1.0 / 1000.0: "1/1000"}
WINDOW_STEPS = 3            # matching window: this many steps either side
OUR_LANGS = ("c", "rust")          # the default runtimes timed (any simulator language may be asked for)
REST_FACTOR = 2.0                   # a rest-speed contact approaches at less than this times the rest speed
COMMAND = "max2code event-vs-frame"
README_BEGIN = "<!-- event-vs-frame:begin (written by max2code event-vs-frame) -->"
README_END = "<!-- event-vs-frame:end -->"


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
    """One of our contacts (a collision, or a contact that ends in support),
    with everything a replay needs."""
    index: int                  # among our contacts, in time order
    t: float
    a: int
    b: int
    start: float                # time of our previous state-changing event (0: the start)
    states: list                # every body's (px, py, vx, vy, ang, om) at `start`
    approach: float             # normal approach speed of the material points at the contact (m/s)
    resting: bool               # a rest-speed contact (see is_resting)
    kind: str = "collision"     # or "support"


def is_resting(kind: str, approach: float, e: float, rest_speed: float) -> bool:
    """A rest-speed contact, which no frame engine has: our rest_speed floor
    set its separation speed (e * approach below min(approach, rest_speed)),
    or it ends in support, and it approaches at less than REST_FACTOR times
    the rest speed: the hop of a body lying on another, which comes back at
    about the rest speed it left with.  A fast landing that the floor or the
    support ends (restitution 0) is a real contact."""
    floored = kind == "support" or e * approach < min(approach, rest_speed)
    return floored and approach < REST_FACTOR * rest_speed


def our_collisions(scene: Scene, events: list[dict]) -> list[Collision]:
    """Our contacts (collisions and supports) in time order, each with the
    exact state of every body at the previous state-changing event (replayed
    from the trace: bodies move exactly between events) and its approach
    speed."""
    names = {b.name: i for i, b in enumerate(scene.bodies)}
    acc = [b.acceleration for b in scene.bodies]     # in force now (a supported body's differs)
    cur = [State(0.0, b.position[0], b.position[1], b.velocity[0], b.velocity[1], b.angle, b.angular_velocity)
           for b in scene.bodies]
    last = 0.0
    out: list[Collision] = []
    for ev in events:
        kind = ev["kind"]
        if kind in ("frame", "cell", "horizon"):
            continue
        t = ev["t"]
        if kind in ("collision", "support"):
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
            out.append(Collision(len(out), t, min(a, b), max(a, b), last, snap, approach,
                                 is_resting(kind, approach, e, scene.rest_speed), kind))
        for st in ev.get("states", ()):
            i = names[st["body"]]
            cur[i] = State(t, st["position"][0], st["position"][1], st["velocity"][0], st["velocity"][1],
                           st["angle"], st["angular_velocity"])
            if "acceleration" in st:
                acc[i] = tuple(st["acceleration"])
        last = t
    return out


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
    cpu_per_s: float = 0.0      # CPU seconds of the free run's stepping per simulated second


@dataclass
class SceneResult:
    label: str
    path: str
    scene: Scene
    ours: list
    collisions: int             # our contacts: collisions and supports
    resting: int                # of which rest-speed ones
    replayed: int
    frames: list

    def counts(self) -> dict:
        """The N counters of the first of our runs that ran."""
        return next((o.counts for o in self.ours if o.ran), {})


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
    """The whole scene in pymunk from t = 0, the scene's inputs applied: CPU
    time of the stepping, and agreement with our events until the first
    divergence."""
    def one():
        w = build_space(scene)
        w.inputs = sorted(scene.inputs, key=lambda x: x.time)
        t0 = time.process_time()
        step_until(w, dt, scene.end_time)
        return w, time.process_time() - t0
    world, cpu = one()
    for _ in range(2):
        if cpu * 2 > 3.0:
            break
        cpu = min(cpu, one()[1])
    res.cpu_per_s = cpu / scene.end_time
    res.free_begins = len(world.begins)
    window = WINDOW_STEPS * dt
    m = match_events([(c.t, c.a, c.b) for c in cols], world.begins, window)
    div = [cols[i].t for i in m.missed if not cols[i].resting] + [world.begins[j][0] for j in m.invented]
    res.agree_until = min(div) if div else scene.end_time
    for (i, j), e in zip(m.pairs, m.errors):
        if cols[i].t < res.agree_until and not cols[i].resting:
            res.agree_count += 1
            res.free_errors.append(abs(e))


def ours_available(lang: str) -> str:
    """'' when this runtime's simulator builds and runs, else why not."""
    try:
        probe = parse_scene(json.dumps({"end_time": 1e-6, "bodies": [
            {"shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}]}), "<probe>")
        run_scene(probe, lang)
    except Exception as exc:       # not built yet, or fails: the report says so
        return f"{type(exc).__name__}: {str(exc).strip().splitlines()[0][:160] if str(exc).strip() else ''}"
    return ""


def example_scenes() -> list[tuple[str, str, Scene]]:
    """Every examples/*.json, then every examples/piles/*.json (bodies in
    lasting contact: piles, stacks, dominoes), by file name: (label, path,
    scene)."""
    out = []
    for folder in ("examples", "examples/piles"):
        for path in sorted((ROOT / folder).glob("*.json")):
            out.append((path.stem, f"{folder}/{path.name}", load_scene(str(path))))
    return out


# ------------------------------------------------------------------ the sweep
def sweep(langs=OUR_LANGS, steps=STEPS, max_replays: int = 300, progress: bool = True, scenes=None):
    scenes = list(example_scenes() if scenes is None else scenes)
    scenes.append(("tunnelling", "(built in: event_vs_frame.tunnel_scene)", tunnel_scene()))
    avail = {lang: ours_available(lang) for lang in langs}
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
                ours.append(OurResult(lang, note=f"not run: {avail[lang]}"))
                continue
            try:
                trace = run_scene(scene, lang)
            except SimulateError as exc:      # stuck, or any failure: the report says where it stopped
                ours.append(OurResult(lang, note=f"stopped: {str(exc).splitlines()[0][-200:]}"))
                continue
            res = time_ours(scene, lang)
            if ref is None:
                ref = trace
            else:
                d = compare(ref, trace)
                res.note = f"agrees with {ref.lang}" if d is None else f"differs from {ref.lang}: {d.what}"
            ours.append(res)
        if ref is None and not any(o.note.startswith("stopped: ") for o in ours):
            raise EvfError("no runtime of ours ran: " + "; ".join(f"{k}: {v}" for k, v in avail.items()))
        # a scene none of ours finished has no contacts to replay; pymunk's free run is still timed
        cols = our_collisions(scene, ref.events) if ref is not None else []
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
    return results, avail


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


def _per_s(o: OurResult, end: float) -> str:
    x = o.cpu_per_s(end)
    return "within start-up" if math.isnan(x) else _s(x)


def _step(dt: float) -> str:
    return STEP_NAMES.get(dt, f"{dt:g}")


def _examples(results) -> list:
    return [r for r in results if r.label != "tunnelling"]


def table(results) -> list[str]:
    """Exactness per scene and step (the replays and the free run)."""
    out = ["| scene | run | contacts (ours) / begins (pymunk) | replayed | median error ms | max error ms "
           "| missed | doubled | free run: agrees until s (contacts) | CPU s per simulated s |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        for o in r.ours:
            if not o.ran:
                out.append(f"| {r.label} | ours, {o.lang} | - | - | - | - | - | - | - | {o.note or 'not available'} |")
                continue
            exact = "within the tolerance" if "orbit" in r.scene.effects else "exact"
            out.append(f"| {r.label} | ours, {o.lang} | {r.collisions} ({r.resting} rest-speed) | - | {exact} | "
                       f"{exact} | 0 | 0 | {_s(r.scene.end_time)} (all) | {_per_s(o, r.scene.end_time)} "
                       f"(less start-up) |")
        for f in r.frames:
            med = statistics.median(f.errors) if f.errors else math.nan
            mx = max(f.errors) if f.errors else math.nan
            out.append(f"| {r.label} | pymunk {_step(f.step)} s | {f.free_begins} | "
                       f"{f.compared} | {_ms(med)} | {_ms(mx)} | {f.missed} | {f.doubled} | "
                       f"{_s(f.agree_until)} ({f.agree_count}) | {_s(f.cpu_per_s)} |")
    return out


def kinds_table(results) -> list[str]:
    """Our events by kind per scene: every counter of the trace's N lines, by
    name, in the trace's order (a kind a runtime adds shows up as a column)."""
    ex = _examples(results)
    names = list(dict.fromkeys(k for r in ex for k in r.counts()))
    events = [k for k in names if k not in WORK_COUNTERS]
    work = [k for k in names if k in WORK_COUNTERS]
    out = ["| scene | simulated s | events | per collision | " + " | ".join(events + work) + " |",
           "|---|" + "---|" * (3 + len(events) + len(work))]
    for r in ex:
        c = r.counts()
        n = handled_events(c)
        per = _s(n / c["collisions"]) if c.get("collisions") else "-"
        out.append(f"| {r.label} | {_s(r.scene.end_time)} | {n:,} | {per} | "
                   + " | ".join(f"{c[k]:,}" if k in c else "-" for k in events + work) + " |")
    return out


def cpu_table(results, langs: list[str]) -> list[str]:
    """CPU seconds per simulated second, per scene: ours less the start-up, pymunk at each step."""
    ex = _examples(results)
    steps = [f.step for f in ex[0].frames] if ex else []
    head = [f"ours, {lang} (start-up s)" for lang in langs] + [f"pymunk {_step(dt)} s" for dt in steps]
    ratio = f"ours, {langs[0]} / pymunk {_step(steps[-1])} s" if langs and steps else None
    out = ["| scene | simulated s | our events (collisions) | " + " | ".join(head) + (f" | {ratio} |" if ratio else " |"),
           "|---|---|---|" + "---|" * (len(head) + (1 if ratio else 0))]
    for r in ex:
        c = r.counts()
        row = [f"{r.label}", _s(r.scene.end_time), f"{handled_events(c):,} ({c.get('collisions', 0):,})"]
        by = {o.lang: o for o in r.ours}
        for lang in langs:
            o = by.get(lang)
            row.append("not available" if o is None else o.note if not o.ran and o.note else
                       "not available" if not o.ran else
                       f"{_per_s(o, r.scene.end_time)} ({_s(o.start)})")
        row += [_s(f.cpu_per_s) for f in r.frames]
        if ratio:
            o = by.get(langs[0])
            ours = o.cpu_per_s(r.scene.end_time) if o is not None and o.ran else math.nan
            theirs = r.frames[-1].cpu_per_s
            row.append(_s(ours / theirs) if theirs > 0.0 and not math.isnan(ours) else "-")
        out.append("| " + " | ".join(row) + " |")
    return out


def headline(results, langs: list[str]) -> list[str]:
    """CPU per simulated second per scene, then the exactness over all the
    example scenes per step (the tunnelling case apart)."""
    ex = _examples(results)
    out = [*cpu_table(results, langs), "",
           "| run | contacts replayed | median error ms | max error ms | missed | doubled |",
           "|---|---|---|---|---|---|",
           "| ours | all | exact (rotation: within the tolerance) | - | 0 | 0 |"]
    for k, dt in enumerate(ex[0].frames if ex else []):
        errs = [e for r in ex for e in r.frames[k].errors]
        n = sum(r.frames[k].compared for r in ex)
        missed = sum(r.frames[k].missed for r in ex)
        doubled = sum(r.frames[k].doubled for r in ex)
        out.append(f"| pymunk {_step(dt.step)} s | {n} | "
                   f"{_ms(statistics.median(errs) if errs else math.nan)} | {_ms(max(errs) if errs else math.nan)} | "
                   f"{missed} ({100.0 * missed / max(n, 1):.1f} %) | {doubled} |")
    tun = [r for r in results if r.label == "tunnelling"]
    if tun:
        t = tun[0]
        found = {_step(f.step): ("found" if f.missed == 0 else "missed") for f in t.frames}
        out.append("")
        out.append("Tunnelling case (a 1 cm bullet at 30 m/s, a 2 cm wall): ours finds the contact; pymunk "
                   + ", ".join(f"{k} s: {v}" for k, v in found.items()) + ".")
    return out


def plot(results, langs: list[str], png: str, svg: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ex = _examples(results)
    fig, axes = plt.subplots(1, 3, figsize=(16, 6))
    cmap = plt.get_cmap("tab10")
    for n, r in enumerate(ex):
        col = cmap(n % 10)
        dts = [f.step for f in r.frames]
        med = [statistics.median(f.errors) if f.errors else math.nan for f in r.frames]
        mx = [max(f.errors) if f.errors else math.nan for f in r.frames]
        axes[0].plot(dts, med, "o-", color=col, label=f"{r.label} (median)")
        axes[0].plot(dts, mx, "^--", color=col, alpha=0.5, label=f"{r.label} (max)")
        miss = [100.0 * f.missed / max(f.compared, 1) for f in r.frames]
        dbl = [100.0 * f.doubled / max(f.compared, 1) for f in r.frames]
        axes[1].plot(dts, miss, "o-", color=col, label=f"{r.label}: missed")
        axes[1].plot(dts, dbl, "s--", color=col, alpha=0.5, label=f"{r.label}: doubled")
    grid = sorted({f.step for r in ex for f in r.frames})
    axes[0].plot(grid, grid, color="grey", linewidth=1, label="one step")
    axes[0].set(xscale="log", yscale="log", xlabel="pymunk step (s)", ylabel="|contact time - exact| (s)",
                title="contact-time error (replayed from exact states)")
    axes[1].set(xscale="log", xlabel="pymunk step (s)", ylabel="% of replayed contacts",
                title="missed (tunnelling) and doubled contacts")
    # CPU per simulated second, per scene: ours (less start-up) and pymunk at each step
    runs = [(f"ours, {lang}", lambda r, lang=lang: next((o.cpu_per_s(r.scene.end_time) for o in r.ours
                                                          if o.lang == lang and o.ran), math.nan))
            for lang in langs]
    for dt in sorted(grid, reverse=True):      # coarse steps first, as in the tables
        runs.append((f"pymunk {_step(dt)} s", lambda r, dt=dt: next((f.cpu_per_s for f in r.frames if f.step == dt),
                                                                    math.nan)))
    width = 0.8 / max(len(runs), 1)
    for m, (name, get) in enumerate(runs):
        xs = [n + (m - (len(runs) - 1) / 2) * width for n in range(len(ex))]
        ys = [get(r) for r in ex]
        axes[2].bar(xs, [y if y > 0 else math.nan for y in ys], width, label=name,
                    color=cmap(m) if m < len(langs) else plt.get_cmap("Greys")(0.35 + 0.2 * (m - len(langs))))
    axes[2].set_xticks(range(len(ex)), [r.label for r in ex], rotation=35, ha="right", fontsize=8)
    axes[2].set(yscale="log", ylabel="CPU s per simulated s", title="CPU time (ours: less start-up)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=5, ncol=2)
    axes[1].legend(fontsize=5, ncol=2)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    fig.savefig(svg, metadata={"Date": None})
    plt.close(fig)


DESIGN = """\
## What is compared, and how

**Scenes.** Every example scene, `examples/*.json` and
`examples/piles/*.json` (made by `examples/make_examples.py`), found when
the command runs, and a tunnelling
case built in (`max2code.reports.event_vs_frame.tunnel_scene`): a bullet of
radius 1 cm at 30 m/s towards a fixed wall 2 cm thick.

**Ours.** Each runtime asked for (`--langs`, C and Rust by default) runs
each scene through `max2code.sim.simulate.run_scene` once for its events
(the exact answer: exact up to rounding for scenes without rotation; within
the scene's distance tolerance, 1e-9 m, when polygons spin), and the
runtimes' traces are compared with the `max2code crosscheck` rule.  The
time is the CPU time (user + system) of the simulator's process alone
(`simulate.time_engine`: the flat scene piped in, the trace drained), best
of up to 10 runs (fewer when they take more than 2 s), less its *start-up*: the same scene with its end time set
to 1 ns, run the same way, which is the process start, reading the scene,
every pair's first prediction and writing the final states.  What is left
is the simulation of the scene's seconds, frames (60 a second) included,
and writing their trace.  No runtime change is needed: both runs are
ordinary runs.

**Our events by kind.** The trace's N lines name every counter of the
simulator (collisions, inputs, frames, cell crossings, horizons, supports,
stops, leaves, and whatever kinds a runtime adds; `stale`, `pairs` and
`features` count work: queue entries dropped, pair and feature
predictions).  They are read by name and tabled as they come, so a new kind
shows up without a change here.

**pymunk.** Each scene is translated into a `pymunk.Space` by
`build_space`: circles with an infinite moment (contacts never turn them,
as in ours; with friction they slide and stop as ours do, they do not
roll), an orbiting circle as an offset on a kinematic body; convex polygons
with their vertices about the centre of mass and our moment of inertia
(mass times second moment of area over area, from `max2code/sim/scene.py`),
not pymunk's own; fixed bodies static, or kinematic when they move or
spin; elasticity = our restitution and friction = our friction coefficient
(Chipmunk's arbiter multiplies the two shapes' elasticities and the two
frictions, the product rule we use for both: pymunk's `Arbiter.restitution`
and `Arbiter.friction` documentation); the scene's gravity; the scene's
inputs applied before the first step that starts at or after their time;
no damping, no sleeping, the default 10 solver iterations.
`collision_slop` is 0 (no overlap is tolerated: a contact begins as soon as
the shapes overlap) and `collision_bias` is 0 (the smallest value: the
fraction of an overlap left after one second, so an overlap is pushed out
within one step); the defaults are 0.1 and 0.0018.  Chipmunk integrates
positions first, then finds contacts: a contact *begin* callback seen
during the step from `t` to `t + dt` is dated `t + dt`, the time of the
positions it saw.

**Our contacts, and rest-speed ones.** Our contacts are our collisions and
our *support* events (a contact that ends with a body resting or sliding
on a fixed edge, or carried on a movable box's face: a frame engine sees
its begin too).  Our model gives every
bouncing contact a separation speed of at least `min(approach, rest_speed)`
(0.05 m/s, docs/simulator.md), so that a body lying on another movable body
that cannot carry it (a ball, a turning body, a box that slides without
friction under it) keeps hopping a fraction of a millimetre where Chipmunk holds one
persistent contact.  A *rest-speed* contact is one where this floor set the
separation speed (restitution times approach speed below
`min(approach, rest_speed)`) or that ends in support, *and* that approaches
at less than %(rest)g times the rest speed (the hop comes back at about the
speed it left with): no frame engine has it, so it is left out of the
replays and of the free run's divergence (the table gives how many).  A
fast landing with restitution 0 (the platformer's box) is a real contact.

**Replay (error, missed, doubled).** A multi-body scene is chaotic: after a
few collisions two simulators follow different histories, and comparing
their events one to one would measure the chaos, not the stepping.  So each
of our real contacts k (the first %(max_replays)d per scene, in time order) is
replayed on its own: pymunk starts from *our* exact state of every body at
our previous state-changing event (between it and k nothing happens in our
run: every body is in free flight or slides on its support), and steps
until %(window)d steps after our time of k.  Its steps end on the global grid `n dt`, as in a frame
engine started at t = 0 (otherwise a collision that follows another closely,
as in the billiard rack, would always be found a whole step late): a first,
shorter step takes it to the next grid point, and a fresh Space goes on
with steps of `dt` (fresh, because Chipmunk warm-starts a contact with its
last impulse times `dt / previous dt`, which the short step would blow up;
a contact of k's pair that goes on across the two is one contact).  Its
begin callbacks for k's pair of bodies are matched to our contacts of that pair in the same span by
`match_events` (each of ours, in time order, takes the earliest unused begin
of its pair within %(window)d steps).  Then:
* *error*: |pymunk's begin time - our time| of k, when matched; the table
  gives the median and maximum in milliseconds;
* *missed*: no begin of k's pair within %(window)d steps of our time: the
  stepper tunnelled through (or stepped around) the contact;
* *doubled*: a further begin of the same pair within %(window)d steps of the
  matched one that no contact of ours accounts for, before our next
  contact of either body (until then both move in the exact motion: the
  contact was lost and found again, not changed by a third body).

The statistics are over the replays; a scene with more real contacts than
%(max_replays)d contributes its first %(max_replays)d.

The window of %(window)d steps is wide enough for a detection that is up to one
step late plus the drift of Chipmunk's semi-implicit Euler under gravity
(it lags the exact parabola by `g (t - t0) dt / 2`), and narrow enough not
to match an unrelated later contact of the same pair.

**Free run (divergence, CPU time).** pymunk also runs each scene from t = 0
to the end on its own, with the scene's inputs; its CPU time per simulated
second is taken from this run (the stepping only, the Python begin callback
included: it runs once per contact start; best of up to 3 runs).  Its begin callbacks are matched to all our contacts with the same
rule; the *divergence* is the first of: a real contact of ours with no
begin of its pair within the window, or a begin with no contact of ours.
The table gives its time and how many real contacts agreed before it.
After it the two runs are different histories.

What is not modelled alike: our `rest_speed` floor (above) and our
contact model (a body rests or slides on fixed edges and is carried on
movable boxes that do not turn, with the exact
Coulomb rule, docs/simulator.md; Chipmunk solves every contact, movable
ones too, with an iterative impulse solver and static friction); Chipmunk
solves simultaneous contacts (the billiard rack, whose balls are 5.7e-9 m
apart) together where we resolve them one pair at a time in time order;
Chipmunk's restitution uses the normal velocity at the start of the step.
"""


def _peers_only(args, lang: str, shown: list[str]) -> int:
    """--peers-only: the side-by-side table of every example scene, printed,
    and its plot."""
    from max2code.reports import peers
    import pymunk
    load = [os.getloadavg()[0]]
    rows = peers.sweep([(label, scene) for label, _, scene in example_scenes()], args.box2d_src, lang,
                       not args.quiet, budget=args.ours_budget)
    load.append(os.getloadavg()[0])
    os.makedirs(args.out_dir, exist_ok=True)
    files = peers.plot(rows, os.path.join(args.out_dir, "peers"))
    print(f"`{' '.join([COMMAND, *shown])}` ({platform.machine()}, {os.cpu_count()} cores; "
          f"Python {platform.python_version()}, pymunk {pymunk.version}; {_load_words(load)}); CPU seconds per "
          "simulated second:\n")
    print("\n".join(peers.cpu_table(rows, lang)))
    print()
    print("\n".join(peers.outcome_table(rows)))
    print(f"{COMMAND}: wrote {', '.join(files)}", file=sys.stderr)
    return 0


def write_report(results, avail, langs, out_dir: str, argv: list[str], max_replays: int,
                 load: list[float], side=None) -> list[str]:
    import pymunk
    os.makedirs(out_dir, exist_ok=True)
    md = os.path.join(out_dir, "event-vs-frame.md")
    png = os.path.join(out_dir, "event-vs-frame.png")
    svg = os.path.join(out_dir, "event-vs-frame.svg")
    ran = [lang for lang in langs if not avail[lang]]
    out: list[str] = []
    plot(results, ran, png, svg)
    cmd = " ".join([COMMAND, *argv])
    lines = ["# Event versus frame: our simulator against pymunk (Chipmunk) at fixed steps", "",
             f"Made by `{cmd}` (this machine: {platform.machine()}, {os.cpu_count()} cores, "
             f"Python {platform.python_version()}, pymunk {pymunk.version}, Chipmunk "
             f"{pymunk.chipmunk_version.split('-')[0]}; {_load_words(load)}: CPU times are single-machine figures, "
             "best of several runs).  Nothing below is typed by hand.", "",
             "## Headline (every example scene)", "", *headline(results, ran), "",
             "CPU seconds per simulated second: ours is the simulator's process (user + system) on the whole "
             "scene less the same scene ended at 1 ns (its start-up, in brackets: the process, reading the scene, "
             "every pair's first prediction, the final states); pymunk's is the stepping of its free run. "
             "*our events*: every event handled (all the trace's N counters but stale entries and predictions), "
             "the collisions in brackets.", "",
             "## Our events by kind", "", *kinds_table(results), "",
             "Every counter of the trace's N lines, by name (docs/simulator.md): the event kinds, then "
             f"{', '.join(WORK_COUNTERS)} (queue entries dropped as stale, pair and feature predictions: work, not "
             "events); *events*: all the event kinds; *per collision*: events over collisions.", "",
             "## Per scene", "", *table(results), "",
             "Columns: *contacts (ours)*: our collisions and supports (rest-speed ones in brackets); *begins (pymunk)*: "
             "begin callbacks in pymunk's free run; *replayed*: our contacts other than rest-speed ones (at most "
             "--max-replays) replayed in pymunk from our exact state; *error*, *missed*, *doubled*: of those "
             "replays; *free run*: the time of the first divergence of pymunk's free run from ours and the real "
             "contacts that agreed before it.", ""]
    for lang, why in avail.items():
        if why:
            lines.append(f"Our {lang} runtime was not available when this was made ({why}).")
            lines.append("")
    early = [f"{r.label} at {_step(f.step)} s: {f.early}" for r in results for f in r.frames if f.early]
    lines += ["Replays in which pymunk found the pair's contact more than the window *before* ours: "
              + ("; ".join(early) if early else "none") + "."]
    notes = [f"{r.label}, {o.lang}: {o.note}" for r in results for o in r.ours if o.note and o.ran]
    if notes:
        lines += ["", "Our runtimes against each other (`max2code crosscheck` rule): " + "; ".join(notes) + "."]
    lines += ["", "![error, missed and CPU time](event-vs-frame.png)", "",
              "([SVG](event-vs-frame.svg))", ""]
    if side:
        from max2code.reports import peers
        ours_lang = next((lang for lang in langs if not avail[lang]), langs[0])
        out.extend(peers.plot(side, os.path.join(out_dir, "peers")))
        lines += ["## Side by side: pymunk, rapier2d and Box2D v3", "",
                  "CPU seconds per simulated second on every example scene (ours: less the start-up; a peer: its "
                  "steps alone), ours over each, and how each run ended (max2code/reports/peers.py; Box2D only "
                  "with --box2d-src).", "", *peers.cpu_table(side, ours_lang), "",
                  "Outcomes, judged alike from each engine's states every 1/60 s: the largest overlap of two "
                  f"bodies, the time from which every movable body moves slower than {peers.REST_SPEED:g} m/s (its "
                  "fastest point), the watched bodies' final position and angle.", "",
                  *peers.outcome_table(side), "", "![CPU per simulated second, side by side](peers.png)", "",
                  "([SVG](peers.svg))", ""]
    lines += [DESIGN % {"max_replays": max_replays, "window": WINDOW_STEPS, "rest": REST_FACTOR}]
    with open(md, "w", encoding="utf-8") as f:
        f.write("\n".join(lines).rstrip() + "\n")
    return [md, png, svg, *out]


def _load_words(load: list[float]) -> str:
    return f"load average {load[0]:.2f} before the sweep, {load[-1]:.2f} after"


def update_readme(results, langs, argv: list[str], load: list[float]) -> bool:
    """Rewrite the block between the README markers with the headline (if
    the markers are there)."""
    path = ROOT / "README.md"
    text = path.read_text(encoding="utf-8")
    if README_BEGIN not in text or README_END not in text:
        return False
    head, rest = text.split(README_BEGIN, 1)
    _, tail = rest.split(README_END, 1)
    cmd = " ".join([COMMAND, *argv])
    block = [README_BEGIN, "", f"(`{cmd}`, {_load_words(load)}; CPU seconds per simulated second, ours less "
             "the start-up in brackets; full tables, design and plot in "
             "[docs/event-vs-frame.md](docs/event-vs-frame.md))", "", *headline(results, langs), "", README_END]
    path.write_text(head + "\n".join(block) + tail, encoding="utf-8")
    return True


def main(argv: list[str]) -> int:
    p = ArgumentParser(prog=COMMAND,
                       description="Run every example scene (examples/*.json) in our simulators and in pymunk at "
                                   "fixed steps (1/60, 1/240, 1/1000 s); write docs/event-vs-frame.md, .png and "
                                   ".svg and the headline in README.md.")
    p.add_argument("--langs", default=",".join(OUR_LANGS),
                   help=f"our runtimes to run and time, when available (default {','.join(OUR_LANGS)}; "
                        f"any of {','.join(LANGS)})")
    p.add_argument("--max-replays", type=int, default=300, metavar="N",
                   help="replay at most the first N real contacts per scene (default 300)")
    p.add_argument("--out-dir", default=str(ROOT / "docs"), help="where the report goes (default docs/)")
    p.add_argument("--no-readme", action="store_true", help="leave README.md alone")
    p.add_argument("--box2d-src", metavar="DIR",
                   help="a Box2D v3 source folder: its src/*.c are compiled with bench/peers/box2d/driver.c and "
                        "Box2D joins the side-by-side table")
    p.add_argument("--ours-budget", type=float, default=120.0, metavar="SECONDS",
                   help="side-by-side table: stop our run on a scene after this many CPU seconds and report the "
                        "time it reached (default 120)")
    p.add_argument("--no-peers", action="store_true",
                   help="leave out the side-by-side table (pymunk, rapier2d, Box2D: max2code/reports/peers.py)")
    p.add_argument("--peers-only", action="store_true",
                   help="only the side-by-side table: print it and write OUT-DIR/peers.png and .svg (no replays, "
                        "no report, README.md left alone)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    args = p.parse_args(argv)
    if args.peers_only and args.no_peers:
        raise EvfError("--peers-only and --no-peers exclude each other")
    langs = list(dict.fromkeys(x for x in args.langs.split(",") if x))
    if not langs:
        raise EvfError("--langs: expected at least one runtime")
    for lang in langs:
        if lang not in LANGS:
            raise EvfError(f"--langs: unknown runtime '{lang}' (expected some of {', '.join(LANGS)})")
    if args.max_replays < 1:
        raise EvfError("--max-replays must be at least 1")
    _pymunk()
    shown = [a for a in argv if a not in ("-q", "--quiet", "--no-readme")]
    if args.peers_only:
        return _peers_only(args, langs[0], shown)
    load = [os.getloadavg()[0]]
    results, avail = sweep(langs, STEPS, args.max_replays, not args.quiet)
    side = None
    if not args.no_peers:
        from max2code.reports import peers
        side = peers.sweep([(r.label, r.scene) for r in _examples(results)], args.box2d_src,
                           next((lang for lang in langs if not avail[lang]), langs[0]), not args.quiet,
                           budget=args.ours_budget)
    load.append(os.getloadavg()[0])
    files = write_report(results, avail, langs, args.out_dir, shown, args.max_replays, load, side)
    ran = [lang for lang in langs if not avail[lang]]
    if not args.no_readme and update_readme(results, ran, shown, load):
        files.append(str(ROOT / "README.md"))
    print("\n".join(headline(results, ran)))
    print(f"{COMMAND}: wrote {', '.join(files)}", file=sys.stderr)
    return 0
