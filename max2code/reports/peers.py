"""Side by side: our event-driven simulator against three frame engines on
the same scenes, pymunk 7 (Chipmunk; 1/60 s steps, 10 iterations), rapier2d
(f64, from crates.io; 1/60 s steps, its default parameters) and Box2D v3
(built from a source folder given with --box2d-src; 1/60 s steps of 4
sub-steps).

Every engine reads the same scene description: our JSON scene, parsed by
max2code/sim/scene.py and written for the compiled peers in the *peer
format* (`peer_text`: a few words per body: circles, convex polygons about
their centre of mass, fixed bodies (kinematic when they move, turn or are
driven by an input), mass and moment of inertia, start velocities,
restitution and friction (both engines' contacts multiply the two bodies'
values, as ours), gravity, the scripted inputs).  The peers are small
drivers: bench/peers/rapier (a Rust crate, built here with cargo into
build/peers/rapier-target/) and bench/peers/box2d/driver.c (compiled here with gcc
against the given Box2D source into build/peers/box2d-HASH/); pymunk runs
in this process through engines.build_space.

Figures per scene and engine:
* CPU seconds per simulated second: ours is the simulator's process less
  its start-up (engines.time_ours); a peer's is the sum of its step
  calls alone (CLOCK_PROCESS_CPUTIME_ID around each call), best of up to 3
  runs;
* status: "ok", or how the run ended early (ours: "stuck at t = ..." and
  the CPU per simulated second up to there; a peer that cannot be built or
  cannot take the scene: why);
* outcomes, judged alike for every engine from its states at every 1/60 s
  frame (`judge`): the largest overlap of two bodies (penetration depth of
  circles and convex polygons), the time from which every movable body
  stays below REST_SPEED, and the final position and angle of the scene's
  watched bodies (WATCH).
"""
from __future__ import annotations

import hashlib
import math
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from max2code.errors import Max2CodeError
from max2code.paths import ROOT
from max2code.sim.scene import REMOVE, Scene, compile_scene
from max2code.sim.simulate import build_simulator, parse_trace, start_simulator, time_engine

STEP = 1.0 / 60.0
SUBSTEPS = 4                    # Box2D's sub-steps per step
OURS_BUDGET = 120.0             # CPU s: our run on one scene is stopped after this (its status says so)
PYMUNK_SLOP = 0.005             # m: pymunk's allowed overlap, Box2D's linear slop
REST_SPEED = 0.01               # m/s: a body moves slower than this (its fastest point) to count as at rest
PEERS = ("pymunk", "rapier", "box2d")
PEER_TITLES = {"pymunk": "pymunk 1/60 s", "rapier": "rapier2d 1/60 s", "box2d": "Box2D v3 1/60 s x 4"}
RAPIER_DIR = ROOT / "bench" / "peers" / "rapier"
BOX2D_DRIVER = ROOT / "bench" / "peers" / "box2d" / "driver.c"
# bodies whose final position and angle the table gives, by scene file stem
WATCH = {"box-on-box": ("top",), "overhang": ("tipper", "holder"), "stack-hit": ("box9",),
         "pyramid-hit": ("box5_0",), "dominoes": ("domino19",)}


class PeerError(Max2CodeError):
    pass


# ------------------------------------------------------------------ the peer format
def _role(scene: Scene, i: int) -> int:
    """0 movable, 1 fixed and still, 2 fixed and moving (kinematic): it moves
    or turns at the start, or an input drives it later."""
    b = scene.bodies[i]
    if not b.fixed:
        return 0
    moving = b.velocity != (0.0, 0.0) or b.angular_velocity != 0.0 or any(e.body == i for e in scene.inputs)
    return 2 if moving else 1


def peer_text(scene: Scene, dt: float = STEP, substeps: int = SUBSTEPS) -> str:
    """The scene in the peer format the compiled drivers read: whitespace
    separated words, numbers as Python's repr (they read back exactly)."""
    r = repr
    out = [f"peer-scene end {r(scene.end_time)} dt {r(dt)} substeps {substeps} "
           f"gravity {r(scene.gravity[0])} {r(scene.gravity[1])}", f"bodies {len(scene.bodies)}"]
    for i, b in enumerate(scene.bodies):
        mass = 0.0 if b.fixed else b.mass
        inertia = 0.0 if b.fixed or not b.polygon else b.inertia
        head = (f"{'p' if b.polygon else 'c'} {_role(scene, i)} {r(mass)} {r(inertia)} "
                f"{r(b.position[0])} {r(b.position[1])} {r(b.velocity[0])} {r(b.velocity[1])} "
                f"{r(b.angle)} {r(b.angular_velocity)} {r(b.restitution)} {r(b.friction)} "
                f"{r(b.acceleration[0])} {r(b.acceleration[1])}")
        if b.polygon:
            shape = f"{len(b.vertices)} " + " ".join(f"{r(x)} {r(y)}" for x, y in b.vertices)
        else:
            shape = f"{r(b.radius)} {r(b.orbit_radius)} {r(b.orbit_angle)}"
        out.append(head + " " + shape)
    out.append(f"inputs {len(scene.inputs)}")
    for e in scene.inputs:
        out.append(f"{r(e.time)} {e.body} {e.mode} {r(e.velocity[0])} {r(e.velocity[1])}")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ one run's result
@dataclass
class Run:
    """One engine on one scene: CPU, status, and its states every frame."""
    engine: str
    cpu: float = math.nan               # CPU seconds (best run)
    simulated: float = 0.0              # seconds simulated (less than the end time when it stopped early)
    status: str = "ok"
    step_cpu: list = field(default_factory=list)    # CPU seconds of each step (peers), best run
    samples: list = field(default_factory=list)     # (t, [(x, y, angle, vx, vy, omega) or None per body])

    @property
    def cpu_per_s(self) -> float:
        return self.cpu / self.simulated if self.simulated > 0.0 and self.cpu >= 0.0 else math.nan


def parse_driver_output(text: str, n: int) -> tuple[list, list]:
    """(step CPU seconds, samples) from a driver's output: per step a line
    's T CPU' and n body lines ('- - - - - -' for a removed body)."""
    lines = text.split("\n")
    step_cpu, samples = [], []
    k = 0
    while k < len(lines) and lines[k].startswith("s "):
        _, t, c = lines[k].split()
        states = []
        for line in lines[k + 1:k + 1 + n]:
            w = line.split()
            states.append(None if w[0] == "-" else tuple(map(float, w)))
        if len(states) != n:
            raise PeerError(f"driver output cut short at t = {t}")
        step_cpu.append(float(c))
        samples.append((float(t), states))
        k += n + 1
    return step_cpu, samples


def _best(fn, runs: int = 3, budget: float = 2.0):
    """The run of least CPU among up to `runs` calls of fn (fewer once they
    took `budget` CPU seconds together)."""
    best, spent = None, 0.0
    for _ in range(runs):
        r = fn()
        if best is None or r.cpu < best.cpu:
            best = r
        spent += r.cpu
        if spent > budget or r.status != "ok":
            break
    return best


def run_driver(engine: str, binary: str, scene: Scene, dt: float = STEP) -> Run:
    """A compiled peer on the scene, best of up to 3 runs."""
    text = peer_text(scene, dt)

    def once() -> Run:
        proc = subprocess.run([binary], input=text, capture_output=True, text=True, timeout=3600)
        if proc.returncode != 0:
            last = proc.stdout.strip().splitlines()[-1:] or proc.stderr.strip().splitlines()[-1:] or [""]
            why = last[0][2:] if last[0].startswith("X ") else f"failed (exit {proc.returncode}): {last[0][:200]}"
            return Run(engine, status=why)
        step_cpu, samples = parse_driver_output(proc.stdout, len(scene.bodies))
        return Run(engine, sum(step_cpu), samples[-1][0] if samples else 0.0, "ok", step_cpu, samples)
    return _best(once)


def run_pymunk(scene: Scene, dt: float = STEP) -> Run:
    """pymunk stepping the scene as a game would: the bodies of
    engines.build_space with pymunk's default solver (10 iterations,
    its default collision bias) and a collision slop of PYMUNK_SLOP
    (build_space's zero slop and bias, chosen there to date contact starts,
    let resting stacks jitter and sink; pymunk's default slop, 0.1, is made
    for pixels: 10 cm of allowed overlap in a scene in metres);
    the scene's inputs applied before the first step that starts at or after
    their time; best of up to 3 runs."""
    import pymunk

    from max2code.reports.engines import build_space
    default = pymunk.Space()

    def once() -> Run:
        world = build_space(scene, begins=False)
        space, bodies = world.space, world.bodies
        space.collision_slop, space.collision_bias = PYMUNK_SLOP, default.collision_bias
        space.iterations = default.iterations
        inputs = sorted(scene.inputs, key=lambda e: e.time)
        removed = [False] * len(bodies)
        steps = max(0, math.ceil(scene.end_time / dt - 1e-9))
        clock = time.process_time
        step_cpu, samples = [], []
        nxt = 0
        for k in range(steps):
            now = k * dt
            while nxt < len(inputs) and inputs[nxt].time <= now + 1e-12 * dt:
                e = inputs[nxt]
                nxt += 1
                if removed[e.body]:
                    continue
                b = bodies[e.body]
                x, y = e.velocity
                if e.mode == 0:
                    b.velocity = (x, y)
                elif e.mode == 1:
                    b.velocity = (b.velocity.x + x, b.velocity.y + y)
                elif e.mode == 2:
                    b.apply_impulse_at_local_point((x, y))
                elif e.mode == 3:
                    b.position = (x, y)
                    space.reindex_shapes_for_body(b)
                else:
                    removed[e.body] = True
                    space.remove(b, *b.shapes)
            c0 = clock()
            space.step(dt)
            step_cpu.append(clock() - c0)
            samples.append(((k + 1) * dt, [None if removed[i] else
                                           (b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y,
                                            b.angular_velocity) for i, b in enumerate(bodies)]))
        return Run("pymunk", sum(step_cpu), steps * dt, "ok", step_cpu, samples)
    return _best(once)


# ------------------------------------------------------------------ ours
_STOP_AT = re.compile(r"at t = ([-+0-9.eE]+)")


def _proc_cpu(pid: int) -> float:
    """CPU seconds (user + system) a running process has used so far (Linux /proc)."""
    with open(f"/proc/{pid}/stat", encoding="ascii") as fh:
        fields = fh.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _run_budget(build, flat: str, budget: float) -> tuple[str, float, int, bool]:
    """Run the simulator on a flat scene, killed once it has used `budget`
    CPU seconds: (its whole output, its CPU seconds, exit code, killed)."""
    proc = start_simulator(build)
    done = threading.Event()
    killed = []

    def feed():
        try:
            proc.stdin.write(flat.encode("ascii"))
            proc.stdin.close()
        except (BrokenPipeError, OSError):
            pass

    def watch():
        while not done.wait(0.5):      # the child is not reaped before done is set: its pid stays its own
            try:
                if _proc_cpu(proc.pid) > budget:
                    killed.append(True)
                    proc.kill()
                    return
            except (OSError, ValueError, IndexError):
                return
    threads = [threading.Thread(target=feed, daemon=True), threading.Thread(target=watch, daemon=True),
               threading.Thread(target=proc.stderr.read, daemon=True)]
    for th in threads:
        th.start()
    chunks = []
    while True:
        chunk = proc.stdout.read(1 << 20)
        if not chunk:
            break
        chunks.append(chunk)
    done.set()
    _, code, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(code)
    for th in threads:
        th.join(timeout=5)
    proc.stdout.close()
    return b"".join(chunks).decode("ascii", "replace"), usage.ru_utime + usage.ru_stime, proc.returncode, bool(killed)


def _last_time(text: str) -> float:
    """The time of the last event line ('E KIND T ...') of a flat trace (0: none)."""
    k = text.rfind("\nE ")
    while k >= 0:
        w = text[k + 1:k + 200].split()
        try:
            return float(w[2])
        except (IndexError, ValueError):
            k = text.rfind("\nE ", 0, k)
    return 0.0


def run_ours(scene: Scene, lang: str = "c", budget: float = OURS_BUDGET) -> Run:
    """Our simulator on the scene: the exact states at every frame (the
    scene's frame_rate; STEP when it has none) replayed from the trace, and
    the CPU per simulated second less the start-up (engines.time_ours;
    a run of more than 2 CPU seconds is not repeated: its own CPU less the
    start-up).  A run that stops early (stuck, any failure), or is stopped
    here after `budget` CPU seconds, is timed up to where it stopped: its
    status names the instant, its CPU is that run's (start-up included) over
    the time reached."""
    from max2code.reports.engines import best_cpu, start_scene, time_ours
    if scene.frame_rate == 0:
        scene = scene.replace(frame_rate=1.0 / STEP)
    build = build_simulator(lang, scene.effects, scene.taylor_order)
    text, cpu, code, killed = _run_budget(build, compile_scene(scene), budget)
    name = f"ours {lang}"
    if killed:
        reached = _last_time(text)
        return Run(name, cpu, reached, f"unfinished: stopped after {budget:g} CPU s at t = {reached:.4g} s")
    if code != 0:
        last = text.rstrip().splitlines()[-1] if text.strip() else ""
        msg = last[2:] if last.startswith("X ") else f"exit {code}"
        m = _STOP_AT.search(msg)
        try:
            reached = float(m.group(1).rstrip(".")) if m else _last_time(text)
        except ValueError:
            reached = _last_time(text)
        what = "stuck" if "stuck" in msg else "failed"
        return Run(name, cpu, reached, f"{what} at t = {reached:.4g} s" if m else f"{what}: {msg[-160:]}")
    samples = frame_states(scene, parse_trace(text, scene, build).events)
    if cpu > 2.0:
        first = compile_scene(start_scene(scene))
        start, _ = best_cpu(lambda: time_engine(build, first))
        run_cpu = cpu - start
    else:
        res = time_ours(scene, lang)
        run_cpu = res.cpu - res.start
    return Run(name, max(run_cpu, 0.0), scene.end_time, "ok", [], samples)


def frame_states(scene: Scene, events: list[dict]) -> list:
    """Every body's exact state at each frame event of our trace, replayed
    from the states the events carry (bodies move exactly between events:
    p + v dt + a dt^2 / 2, angle + omega dt)."""
    names = {b.name: i for i, b in enumerate(scene.bodies)}
    acc = [b.acceleration for b in scene.bodies]
    cur = [(0.0, *b.position, *b.velocity, b.angle, b.angular_velocity) for b in scene.bodies]
    gone = [math.inf] * len(scene.bodies)
    for e in scene.inputs:
        if e.mode == REMOVE:
            gone[e.body] = min(gone[e.body], e.time)
    out = []
    for ev in events:
        t = ev["t"]
        if ev["kind"] == "frame":
            states = []
            for i, (tb, px, py, vx, vy, ang, om) in enumerate(cur):
                if t >= gone[i]:
                    states.append(None)
                    continue
                d = t - tb
                ax, ay = acc[i]
                states.append((px + (vx + 0.5 * ax * d) * d, py + (vy + 0.5 * ay * d) * d, ang + om * d,
                               vx + ax * d, vy + ay * d, om))
            out.append((t, states))
        for st in ev.get("states", ()):
            i = names[st["body"]]
            cur[i] = (t, *st["position"], *st["velocity"], st["angle"], st["angular_velocity"])
            if "acceleration" in st:
                acc[i] = tuple(st["acceleration"])
    return out


# ------------------------------------------------------------------ judging the states
def _world_shape(b, state):
    """('c', cx, cy, r) or ('p', [(x, y) ...] counter-clockwise) at a state."""
    x, y, ang = state[0], state[1], state[2]
    if not b.polygon:
        if b.orbit_radius > 0.0:
            a = ang + b.orbit_angle
            return ("c", x + b.orbit_radius * math.cos(a), y + b.orbit_radius * math.sin(a), b.radius)
        return ("c", x, y, b.radius)
    c, s = math.cos(ang), math.sin(ang)
    return ("p", [(x + c * vx - s * vy, y + s * vx + c * vy) for vx, vy in b.vertices])


def _box(sh):
    if sh[0] == "c":
        return sh[1] - sh[3], sh[1] + sh[3], sh[2] - sh[3], sh[2] + sh[3]
    xs = [p[0] for p in sh[1]]
    ys = [p[1] for p in sh[1]]
    return min(xs), max(xs), min(ys), max(ys)


def _circle_polygon(cx, cy, r, pts) -> float:
    n = len(pts)
    inside_by = math.inf        # distance to the boundary when inside
    outside = False
    best = math.inf
    for k in range(n):
        ax, ay = pts[k]
        bx, by = pts[(k + 1) % n]
        ex, ey = bx - ax, by - ay
        ln = math.hypot(ex, ey)
        s = (ex * (cy - ay) - ey * (cx - ax)) / ln      # > 0: inside of this edge (counter-clockwise)
        if s < 0.0:
            outside = True
        inside_by = min(inside_by, s)
        u = max(0.0, min(1.0, ((cx - ax) * ex + (cy - ay) * ey) / (ln * ln)))
        best = min(best, math.hypot(cx - ax - u * ex, cy - ay - u * ey))
    return r - best if outside else r + inside_by


def _axis_depth(pa, pb) -> float:
    depth = math.inf
    for pts in (pa, pb):
        n = len(pts)
        for k in range(n):
            ax, ay = pts[k]
            bx, by = pts[(k + 1) % n]
            nx, ny = by - ay, ax - bx
            ln = math.hypot(nx, ny)
            nx, ny = nx / ln, ny / ln
            a = [x * nx + y * ny for x, y in pa]
            b = [x * nx + y * ny for x, y in pb]
            d = min(max(a), max(b)) - max(min(a), min(b))
            if d <= 0.0:
                return 0.0
            depth = min(depth, d)
    return depth


def overlap(sa, sb) -> float:
    """Penetration depth of two shapes (0 when apart)."""
    if sa[0] == "c" and sb[0] == "c":
        return max(0.0, sa[3] + sb[3] - math.hypot(sa[1] - sb[1], sa[2] - sb[2]))
    if sa[0] == "p" and sb[0] == "p":
        return _axis_depth(sa[1], sb[1])
    c, p = (sa, sb) if sa[0] == "c" else (sb, sa)
    return max(0.0, _circle_polygon(c[1], c[2], c[3], p[1]))


def max_overlap(scene: Scene, states: list) -> float:
    """The largest penetration depth of two bodies, not both fixed, at one
    instant (sweep and prune on x)."""
    shapes = []
    for i, (b, st) in enumerate(zip(scene.bodies, states)):
        if st is None:
            continue
        sh = _world_shape(b, st)
        shapes.append((_box(sh), i, sh))
    shapes.sort(key=lambda s: s[0][0])
    worst = 0.0
    for k, (ba, i, sa) in enumerate(shapes):
        for bb, j, sb in shapes[k + 1:]:
            if bb[0] > ba[1]:
                break
            if bb[2] > ba[3] or bb[3] < ba[2] or (scene.bodies[i].fixed and scene.bodies[j].fixed):
                continue
            worst = max(worst, overlap(sa, sb))
    return worst


@dataclass
class Outcome:
    overlap: float = math.nan           # m: the largest overlap at any frame
    rest_from: float = math.nan         # s: every movable body slower than REST_SPEED from then on (nan: never)
    watched: dict = field(default_factory=dict)     # name -> (x, y, angle) at the end


def judge(scene: Scene, samples: list, stem: str = "") -> Outcome:
    """The outcome figures of one run from its states every frame."""
    out = Outcome()
    if not samples:
        return out
    out.overlap = max(max_overlap(scene, st) for _, st in samples)
    movable = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    rest = math.nan
    for t, st in samples:
        fast = max((math.hypot(st[i][3], st[i][4]) + abs(st[i][5]) * scene.bodies[i].bound
                    for i in movable if st[i] is not None), default=0.0)
        if fast >= REST_SPEED:
            rest = math.nan
        elif math.isnan(rest):
            rest = t
    out.rest_from = rest
    names = {b.name: i for i, b in enumerate(scene.bodies)}
    final = samples[-1][1]
    for name in WATCH.get(stem, ()):
        st = final[names[name]]
        if st is not None:
            a = math.remainder(st[2], 2.0 * math.pi)
            out.watched[name] = (st[0], st[1], a)
    return out


# ------------------------------------------------------------------ building the peers
def _digest(paths) -> str:
    h = hashlib.sha256()
    for p in paths:
        h.update(str(p).encode())
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


def build_rapier(progress: bool = True) -> str:
    """The rapier driver built with cargo (release) into build/peers/rapier-target/;
    cargo rebuilds only what changed.  PeerError when it cannot be built."""
    cargo = shutil.which("cargo")
    if cargo is None:
        raise PeerError("cargo not found")
    target = ROOT / "build" / "peers" / "rapier-target"
    if progress:
        print("peers: building the rapier2d driver (cargo build --release)", file=sys.stderr, flush=True)
    proc = subprocess.run([cargo, "build", "--release", "--quiet", "--manifest-path", str(RAPIER_DIR / "Cargo.toml")],
                          capture_output=True, text=True, env={**os.environ, "CARGO_TARGET_DIR": str(target)})
    if proc.returncode != 0:
        raise PeerError("cargo build of bench/peers/rapier failed: " + proc.stderr.strip()[-400:])
    return str(target / "release" / "rapier-peer")


def build_box2d(src: str, progress: bool = True) -> str:
    """bench/peers/box2d/driver.c compiled with Box2D's src/*.c from `src`
    (a Box2D v3 source folder: include/box2d/box2d.h, src/*.c) into
    build/peers/box2d-HASH/ (HASH of the driver and every source file)."""
    src_dir = Path(src)
    header = src_dir / "include" / "box2d" / "box2d.h"
    if not header.exists():
        raise PeerError(f"--box2d-src {src}: no include/box2d/box2d.h (expected a Box2D v3 source folder)")
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise PeerError("no C compiler (gcc or cc) found")
    sources = sorted((src_dir / "src").glob("*.c"))
    deps = [BOX2D_DRIVER, *sources, *sorted((src_dir / "src").glob("*.h")),
            *sorted((src_dir / "include" / "box2d").glob("*.h"))]
    out_dir = ROOT / "build" / "peers" / f"box2d-{_digest(deps)}"
    exe = out_dir / "box2d-peer"
    if exe.exists():
        return str(exe)
    out_dir.mkdir(parents=True, exist_ok=True)
    if progress:
        print(f"peers: compiling Box2D ({len(sources)} files) and its driver into {out_dir}", file=sys.stderr,
              flush=True)
    tmp = out_dir / f"box2d-peer.{os.getpid()}.tmp"     # two runs building at once do not clash
    proc = subprocess.run([cc, "-O2", "-std=c17", "-DNDEBUG", "-I", str(src_dir / "include"), "-I",
                           str(src_dir / "src"), *map(str, sources), str(BOX2D_DRIVER), "-lm", "-lpthread",
                           "-o", str(tmp)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise PeerError("compiling Box2D failed: " + proc.stderr.strip()[-400:])
    tmp.replace(exe)
    return str(exe)


def prepare(box2d_src: str | None, progress: bool = True) -> dict:
    """{engine: binary path, or PeerError text} for the peers to run: pymunk
    (this process), rapier, and box2d when its source is given."""
    out: dict = {}
    try:
        import pymunk  # noqa: F401
        out["pymunk"] = ""
    except ImportError:
        out["pymunk"] = PeerError("pymunk is not installed")
    try:
        out["rapier"] = build_rapier(progress)
    except PeerError as exc:
        out["rapier"] = exc
    if box2d_src:
        try:
            out["box2d"] = build_box2d(box2d_src, progress)
        except PeerError as exc:
            out["box2d"] = exc
    return out


# ------------------------------------------------------------------ the sweep and the table
@dataclass
class Row:
    label: str
    scene: Scene
    runs: dict                  # engine -> Run (ours first)
    outcomes: dict              # engine -> Outcome


def run_peer(engine: str, how, scene: Scene) -> Run:
    if isinstance(how, Exception):
        return Run(engine, status=f"not available: {how}")
    if engine == "pymunk":
        return run_pymunk(scene)
    return run_driver(engine, how, scene)


def sweep(scenes, box2d_src: str | None = None, lang: str = "c", progress: bool = True, built=None,
          budget: float = OURS_BUDGET) -> list[Row]:
    """Every scene (label, scene) in ours (stopped after `budget` CPU
    seconds) and in each peer."""
    built = prepare(box2d_src, progress) if built is None else built
    rows = []
    for n, (label, scene) in enumerate(scenes, 1):
        runs, outcomes = {}, {}
        for engine in ["ours", *built]:
            if progress:
                print(f"peers: [{n}/{len(scenes)}] {label}: {engine} ...", file=sys.stderr, flush=True)
            try:
                r = run_ours(scene, lang, budget) if engine == "ours" else run_peer(engine, built[engine], scene)
            except Exception as exc:        # any failure is a status in the table, not the end of the sweep
                r = Run(engine, status=f"failed: {type(exc).__name__}: {str(exc).strip().splitlines()[0][-160:]}"
                        if str(exc).strip() else f"failed: {type(exc).__name__}")
            runs[engine] = r
            outcomes[engine] = judge(scene, r.samples, label)
            r.samples = []          # judged: the states are not kept
            if progress:
                print(f"peers: [{n}/{len(scenes)}] {label}: {engine}: {_cpu(r.cpu_per_s)} CPU s per simulated s, "
                      f"{r.status}", file=sys.stderr, flush=True)
        rows.append(Row(label, scene, runs, outcomes))
    return rows


def _cpu(x: float) -> str:
    if x is None or math.isnan(x):
        return "-"
    if x == 0.0:
        return "within start-up"
    return f"{x:.3g}" if x < 100 else f"{x:,.0f}"


def _ratio(a: float, b: float) -> str:
    if math.isnan(a) or math.isnan(b) or b <= 0.0:
        return "-"
    if a == 0.0:
        return "~0"
    return f"{a / b:.3g}x" if a / b < 1000 else f"{a / b:,.0f}x"


def _status(r: Run) -> str:
    return "" if r.status == "ok" else r.status


def cpu_table(rows: list[Row], lang: str = "c") -> list[str]:
    """The side-by-side table: CPU per simulated second per engine, ours
    over each peer, and how each run ended."""
    peers = [e for e in PEERS if any(e in r.runs for r in rows)]
    head = ["scene (bodies, s)", f"ours ({lang})"] + [PEER_TITLES[e] for e in peers] \
        + [f"ours / {e}" for e in peers] + ["status"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        ours = r.runs["ours"]
        cells = [f"{r.label} ({len(r.scene.bodies)}, {r.scene.end_time:g})", _cpu(ours.cpu_per_s)]
        cells += [_cpu(r.runs[e].cpu_per_s) if e in r.runs else "-" for e in peers]
        cells += [_ratio(ours.cpu_per_s, r.runs[e].cpu_per_s) if e in r.runs else "-" for e in peers]
        notes = [f"{'ours' if e == 'ours' else e}: {_status(x)}" for e, x in r.runs.items() if _status(x)]
        cells.append("; ".join(notes) if notes else "all ran to the end")
        out.append("| " + " | ".join(cells) + " |")
    return out


def outcome_table(rows: list[Row]) -> list[str]:
    """Per scene and engine: the largest overlap, when it came to rest, the
    watched bodies at the end."""
    out = ["| scene | engine | max overlap mm | at rest from s | watched bodies at the end: x, y m, angle rad |",
           "|---|---|---|---|---|"]
    for r in rows:
        for e, o in r.outcomes.items():
            run = r.runs[e]
            if run.status != "ok":
                out.append(f"| {r.label} | {e} | - | - | ({run.status}) |")
                continue
            rest = "moving at the end" if math.isnan(o.rest_from) else f"{o.rest_from:.3g}"
            w = "; ".join(f"{k} {x:.4g}, {y:.4g}, {a:.3g}" for k, (x, y, a) in o.watched.items()) or "-"
            out.append(f"| {r.label} | {e} | {o.overlap * 1e3:.3g} | {rest} | {w} |")
    return out


def plot(rows: list[Row], stem: str) -> list[str]:
    """CPU seconds per simulated second per scene and engine (log scale),
    STEM.png and STEM.svg; a run that ended early is hatched."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    engines = ["ours", *[e for e in PEERS if any(e in r.runs for r in rows)]]
    fig, ax = plt.subplots(figsize=(max(8, 0.9 * len(rows) + 3), 5))
    width = 0.8 / len(engines)
    cmap = plt.get_cmap("tab10")
    for k, e in enumerate(engines):
        xs = [i + (k - (len(engines) - 1) / 2) * width for i in range(len(rows))]
        ys = [r.runs[e].cpu_per_s if e in r.runs else math.nan for r in rows]
        bars = ax.bar(xs, [y if y > 0 else math.nan for y in ys], width, color=cmap(k),
                      label="ours (C)" if e == "ours" else PEER_TITLES[e])
        for bar, r in zip(bars, rows):
            if e in r.runs and r.runs[e].status != "ok":
                bar.set_hatch("//")
    ax.set_yscale("log")
    ax.set_xticks(range(len(rows)), [r.label for r in rows], rotation=35, ha="right", fontsize=8)
    ax.set_ylabel("CPU s per simulated s (log)")
    ax.set_title("Side by side: our event engine and three frame engines (hatched: the run stopped early)")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(stem + ".png", dpi=110)
    fig.savefig(stem + ".svg", metadata={"Date": None})
    plt.close(fig)
    return [stem + ".png", stem + ".svg"]
