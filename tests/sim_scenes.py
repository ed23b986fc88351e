"""Random scenes for the simulator tests and the cross-check, reproducible
from a seed: circles and convex polygons in a box, with or without gravity,
spin, restitution below 1, scripted inputs and orbiting fixed circles."""
from __future__ import annotations

import json
import math
import random


def box(w: float, h: float, thick: float = 0.2, restitution: float = 1.0) -> list[dict]:
    def wall(name, cx, cy, hw, hh):
        return {"name": name, "shape": "polygon", "fixed": True, "restitution": restitution, "position": [cx, cy],
                "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    t = thick / 2
    return [wall("floor", w / 2, -t, w / 2 + thick, t), wall("ceiling", w / 2, h + t, w / 2 + thick, t),
            wall("left", -t, h / 2, t, h / 2), wall("right", w + t, h / 2, t, h / 2)]


def random_scene(seed: int, *, bodies: int | None = None, gravity: bool | None = None, spin: bool | None = None,
                 end_time: float | None = None, restitution_one: bool | None = None) -> dict:
    rng = random.Random(seed)
    n = bodies if bodies is not None else rng.randint(3, 10)
    gravity = rng.random() < 0.5 if gravity is None else gravity
    spin = rng.random() < 0.5 if spin is None else spin
    elastic = rng.random() < 0.5 if restitution_one is None else restitution_one
    cols = max(2, math.ceil(math.sqrt(n)))
    slot = 0.5
    w = h = cols * slot
    out = box(w, h)
    slots = list(range(cols * cols))
    rng.shuffle(slots)
    for k in range(n):
        sx, sy = slots[k] % cols, slots[k] // cols
        cx, cy = (sx + 0.5) * slot + rng.uniform(-0.05, 0.05), (sy + 0.5) * slot + rng.uniform(-0.05, 0.05)
        size = rng.uniform(0.06, 0.16)
        body = {"name": f"b{k}", "mass": round(rng.uniform(0.5, 3.0), 3), "position": [round(cx, 6), round(cy, 6)],
                "velocity": [round(rng.uniform(-2, 2), 6), round(rng.uniform(-2, 2), 6)],
                "restitution": 1.0 if elastic else round(rng.choice([0.6, 0.8, 0.95]), 2)}
        if rng.random() < 0.5:
            body.update(shape="circle", radius=round(size, 6))
        else:
            m = rng.randint(3, 7)
            start = rng.uniform(0, 2 * math.pi)
            body.update(shape="polygon", vertices=[[round(size * math.cos(start + 2 * math.pi * i / m), 9),
                                                    round(size * math.sin(start + 2 * math.pi * i / m), 9)]
                                                   for i in range(m)])
            if spin:
                body["angular_velocity"] = round(rng.uniform(-6, 6), 4)
                body["angle"] = round(rng.uniform(-3, 3), 4)
        out.append(body)
    scene = {"name": f"random {seed}", "end_time": end_time if end_time is not None else round(rng.uniform(0.8, 2.0), 3),
             "frame_rate": rng.choice([0, 30]), "bodies": out}
    if gravity:
        scene["gravity"] = [0.0, -9.81]
    if rng.random() < 0.3:
        scene["inputs"] = [{"time": round(scene["end_time"] / 2, 4), "body": "b0", "add_velocity": [0.5, 1.0]}]
    if spin and rng.random() < 0.3:
        # a fixed circle orbiting the box's centre, as the paper's orbiting circles
        scene["bodies"].append({"name": "orbiter", "shape": "circle", "fixed": True, "radius": 0.05,
                                "position": [w / 2, h / 2], "orbit": {"radius": 0.1, "angle": 0.0},
                                "angular_velocity": 2.0})
    return scene


def write_random_scenes(folder, seeds) -> list[str]:
    """Write scenes seed -> folder/random-SEED.json; returns the paths.
    A scene whose bodies would overlap (an orbiting circle on a body) is
    drawn again from the next seed offset."""
    from max2code.sim.scene import SceneError, parse_scene
    paths = []
    for seed in seeds:
        for attempt in range(20):
            scene = random_scene(seed * 1000 + attempt)
            text = json.dumps(scene, indent=1)
            try:
                parse_scene(text, f"random-{seed}.json")
            except SceneError:
                continue
            break
        else:
            raise RuntimeError(f"no valid random scene for seed {seed}")
        path = f"{folder}/random-{seed}.json"
        with open(path, "w") as f:
            f.write(text + "\n")
        paths.append(path)
    return paths


def resting_scene(seed: int, *, end_time: float = 2.0, boxes: bool = True) -> dict:
    """Bodies resting on the floor of a box under gravity at t = 0 (circles
    touching it, boxes standing on a face), some set sliding, some dropped
    from a little above; random restitution below 1 and friction.  No
    inputs: the system is closed."""
    rng = random.Random(seed)
    n = rng.randint(3, 8)
    slot = 0.4
    w, h = n * slot, 1.5
    out = box(w, h)
    out[0]["friction"] = round(rng.choice([0.0, 0.5, 1.0]), 2)
    for k in range(n):
        x = (k + 0.5) * slot
        size = round(rng.uniform(0.06, 0.15), 3)
        body = {"name": f"r{k}", "mass": round(rng.uniform(0.5, 2.0), 3),
                "restitution": rng.choice([0.0, 0.3, 0.6, 0.9]), "friction": rng.choice([0.0, 0.2, 0.6])}
        y = size + (0.0 if rng.random() < 0.7 else round(rng.uniform(0.05, 0.5), 3))
        if rng.random() < 0.5 or not boxes:
            body.update(shape="circle", radius=size)
        else:
            body.update(shape="polygon", vertices=[[-size, -size], [size, -size], [size, size], [-size, size]])
        body["position"] = [round(x, 6), y]
        if rng.random() < 0.5:
            body["velocity"] = [round(rng.uniform(-1.5, 1.5), 3), 0.0]
        out.append(body)
    return {"name": f"resting {seed}", "end_time": end_time, "frame_rate": 30, "gravity": [0.0, -9.81],
            "bodies": out}


def pile_scene(seed: int, *, end_time: float = 1.5, kinds: str | None = None) -> dict:
    """A pile: 6 to 16 bodies (balls, boxes, or both: `kinds` "balls",
    "boxes" or "mixed", else drawn) dropped in rows into a narrow bin
    under gravity with random velocities, so that they pile up, pinch and
    collide again and again; restitution up to 0.9, friction on or off
    (drawn per scene).  No inputs: the system is closed."""
    rng = random.Random(seed)
    kinds = kinds or rng.choice(["balls", "boxes", "mixed"])
    friction = rng.choice([0.0, 0.3, 0.8])
    n = rng.randint(6, 16)
    cols = rng.randint(2, 4)
    slot = 0.36         # a box turned 0.3 rad reaches 0.15 m across: rows and columns never overlap
    w, h = cols * slot, 3.0
    out = box(w, h, restitution=rng.choice([0.3, 0.8, 1.0]))
    for wall in out:
        wall["friction"] = friction
    for k in range(n):
        size = round(rng.uniform(0.06, 0.12), 3)
        x = (k % cols + 0.5) * slot + round(rng.uniform(-0.02, 0.02), 3)
        y = 0.2 + (k // cols) * slot
        body = {"name": f"p{k}", "mass": round(rng.uniform(0.5, 2.0), 3),
                "restitution": rng.choice([0.0, 0.5, 0.8, 0.9]), "friction": friction,
                "position": [round(x, 6), round(y, 6)],
                "velocity": [round(rng.uniform(-2.0, 2.0), 3), round(rng.uniform(-2.0, 2.0), 3)]}
        if kinds == "balls" or (kinds == "mixed" and rng.random() < 0.5):
            body.update(shape="circle", radius=size)
        else:
            body.update(shape="polygon", vertices=[[-size, -size], [size, -size], [size, size], [-size, size]],
                        angle=round(rng.uniform(-0.3, 0.3), 3))
        out.append(body)
    return {"name": f"pile {seed} ({kinds})", "end_time": end_time, "frame_rate": 30, "gravity": [0.0, -9.81],
            "bodies": out}


def write_resting_scenes(folder, seeds) -> list[str]:
    paths = []
    for seed in seeds:
        path = f"{folder}/resting-{seed}.json"
        with open(path, "w") as f:
            f.write(json.dumps(resting_scene(seed), indent=1) + "\n")
        paths.append(path)
    return paths


def inputs_scene(end_time: float = 2.0, remove: bool = False) -> dict:
    """Three bodies in a box under gravity with every kind of input: at
    t = 0, at frame times, two at one instant, teleports into free space;
    with remove, a ledge the crate rests on and then the ledge and the
    pebble are removed."""
    bodies = box(2.0, 2.0, restitution=0.9) + [
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.5, 0.5],
         "velocity": [1.0, 0.0], "restitution": 0.9},
        {"name": "crate", "shape": "polygon", "mass": 2.0, "position": [1.4, 0.3], "friction": 0.3,
         "vertices": [[-0.15, -0.1], [0.15, -0.1], [0.15, 0.1], [-0.15, 0.1]], "angle": 0.2},
        {"name": "pebble", "shape": "circle", "radius": 0.05, "mass": 0.2, "position": [1.0, 1.5],
         "velocity": [-0.5, 0.3]}]
    inputs = [{"time": 0.0, "body": "ball", "impulse": [0.0, 3.0]},
              {"time": 0.5, "body": "crate", "set_velocity": [-1.0, 2.0]},
              {"time": 0.5, "body": "pebble", "teleport": [1.7, 1.7]},
              {"time": 0.8, "body": "ball", "add_velocity": [0.5, 1.5]},
              {"time": 1.0, "body": "pebble", "impulse": [0.1, -0.2]},
              {"time": 1.0, "body": "pebble", "teleport": [0.3, 1.6]},
              {"time": 1.25, "body": "crate", "teleport": [1.0, 1.0]},
              {"time": 1.5, "body": "ball", "set_velocity": [0.0, 0.0]}]
    if remove:
        bodies.append({"name": "ledge", "shape": "polygon", "fixed": True, "position": [1.0, 0.6], "restitution": 0.0,
                       "vertices": [[-0.3, -0.05], [0.3, -0.05], [0.3, 0.05], [-0.3, 0.05]]})
        inputs[6]["teleport"] = [1.6, 1.0]
        inputs += [{"time": 1.1, "body": "pebble", "teleport": [1.0, 0.7]},     # onto the ledge, touching
                   {"time": 1.1, "body": "pebble", "set_velocity": [0.0, 0.0]},  # at rest: it rests there
                   {"time": 1.4, "body": "ledge", "remove": True},               # the pebble leaves, falls
                   {"time": 1.75, "body": "pebble", "remove": True}]
        inputs.sort(key=lambda e: e["time"])         # in time order (stable), as a recording lists them
    return {"name": "inputs of every kind", "end_time": end_time, "frame_rate": 4, "gravity": [0.0, -9.81],
            "bodies": bodies, "inputs": inputs}


def spinning_scene(seed: int, *, end_time: float = 1.5) -> dict:
    """Spinning convex polygons in a box (a grid of slots, some placed
    against a wall so that their bounding circles overlap it from t = 0),
    fast spins of both signs, restitution 1 or below, gravity or not; one
    polygon may start without spin (it turns after its first contact).  No
    inputs: the system is closed."""
    rng = random.Random(seed)
    n = rng.randint(2, 7)
    cols = max(2, math.ceil(math.sqrt(n)))
    slot = 0.5
    w = h = cols * slot
    elastic = rng.random() < 0.5
    out = box(w, h, restitution=1.0 if elastic else 0.9)
    slots = list(range(cols * cols))
    rng.shuffle(slots)
    for k in range(n):
        sx, sy = slots[k] % cols, slots[k] // cols
        size = rng.uniform(0.06, 0.2)
        m = rng.randint(3, 7)
        start = rng.uniform(0, 2 * math.pi)
        verts = [[round(size * math.cos(start + 2 * math.pi * i / m), 9),
                  round(size * math.sin(start + 2 * math.pi * i / m), 9)] for i in range(m)]
        cx, cy = (sx + 0.5) * slot, (sy + 0.5) * slot
        if rng.random() < 0.4:
            # just clear of the nearest wall, its bounding circle across it: a graze
            near = rng.uniform(0.0005, 0.02)
            if sx == 0:
                cx = max(-x for x, _ in verts) + near
            elif sx == cols - 1:
                cx = w - max(x for x, _ in verts) - near
            if sy == 0:
                cy = max(-y for _, y in verts) + near
            elif sy == cols - 1:
                cy = h - max(y for _, y in verts) - near
        body = {"name": f"p{k}", "shape": "polygon", "mass": round(rng.uniform(0.5, 3.0), 3),
                "position": [round(cx, 6), round(cy, 6)],
                "velocity": [round(rng.uniform(-1.5, 1.5), 6), round(rng.uniform(-1.5, 1.5), 6)],
                "vertices": verts,
                "restitution": 1.0 if elastic else round(rng.choice([0.6, 0.8, 0.95]), 2)}
        if k > 0 or rng.random() < 0.7:
            body["angular_velocity"] = round(rng.choice([-1, 1]) * rng.uniform(1.0, 12.0), 4)
        out.append(body)
    scene = {"name": f"spinning {seed}", "end_time": end_time, "frame_rate": 30, "bodies": out}
    if rng.random() < 0.5:
        scene["gravity"] = [0.0, -9.81]
    return scene


def run_everywhere(scene):
    """Run a parsed scene in every runtime; the traces must be the same bytes,
    with no overlap beyond the tolerance and no energy gained (1e-12
    relative).  Returns the first runtime's trace."""
    from max2code.sim.commands import crosscheck
    from max2code.sim.invariants import check, energy_growth
    from max2code.sim.replay import read_trace
    from max2code.sim.simulate import LANGS
    tr, problems = crosscheck(scene, LANGS)
    assert problems == []
    ref = tr[LANGS[0]]
    for lang in LANGS[1:]:
        assert tr[lang].raw == ref.raw, lang
    rp = read_trace("\n".join(ref.lines()), scene, scene.name)
    assert check(scene, rp).max_overlap <= scene.tolerance
    assert energy_growth(scene, rp).max_growth <= 1e-12
    return ref


def two_circles_world():
    """A Python world of two unit-mass circles of radius 0.1, 1 m apart,
    under gravity: its predictor serves tests that hand it gaps directly."""
    from max2code.sim.live import python_world
    from max2code.sim.scene import parse_scene
    raw = {"end_time": 1.0, "gravity": [0.0, -9.81], "bodies": [
        {"name": "a", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]},
        {"name": "b", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [1.0, 0.0]}]}
    return python_world(parse_scene(json.dumps(raw), "two.json"))
