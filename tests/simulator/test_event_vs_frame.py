"""Event versus frame (max2code event-vs-frame): the tunnelling case, the
pymunk translation (friction, inputs), the matcher, our timing less the
start-up and the events by kind.  pymunk is a test requirement
(scripts/setup installs it): a missing pymunk fails here, it is not skipped."""
import json
import math

import pymunk
import pytest

from max2code.reports.engines import OurResult, build_space, step_until, time_ours
from max2code.reports.event_vs_frame import (example_scenes, free_run, FrameResult, is_resting, kinds_table,
                                             match_events, our_collisions, replay, SceneResult, tunnel_scene)
from max2code.sim.scene import load_scene, parse_scene
from max2code.paths import ROOT
from max2code.sim.simulate import run_scene

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def test_tunnelling_case():
    scene = tunnel_scene()
    trace = run_scene(scene, "python")
    cols = our_collisions(scene, trace.events)
    # ours: exactly one contact, the bullet's surface reaching the wall's face: (1.0 - 0.01 - 0.01 - 0.2) / 30
    assert [(c.a, c.b) for c in cols] == [(0, 1)]
    assert math.isclose(cols[0].t, 0.78 / 30.0, rel_tol=1e-12)
    assert math.isclose(cols[0].approach, 30.0, rel_tol=1e-12) and not cols[0].resting
    final = {b["body"]: b for b in trace.final["bodies"]}
    assert final["bullet"]["velocity"][0] < 0.0          # bounced back
    # pymunk at 1/60 s: the centre goes from 0.7 m to 1.2 m in one step, over the wall untouched
    err, doubled, early = replay(scene, cols, 0, 1.0 / 60.0)
    assert math.isnan(err) and doubled == 0 and early == 0
    res = FrameResult(1.0 / 60.0)
    free_run(scene, cols, 1.0 / 60.0, res)
    assert res.free_begins == 0 and res.agree_count == 0 and math.isclose(res.agree_until, cols[0].t)
    # at 1/1000 s (3 cm a step against a 4 cm span) it is found, at most a step late
    err, doubled, early = replay(scene, cols, 0, 1.0 / 1000.0)
    assert 0.0 <= err <= 1.0 / 1000.0 + 1e-12 and doubled == 0


def test_pymunk_translation_is_faithful():
    scene = load_scene(str(ROOT / "examples" / "spinning-polygons.json"))
    world = build_space(scene)
    assert world.space.collision_slop == 0.0 and world.space.collision_bias == 0.0
    assert tuple(world.space.gravity) == scene.gravity
    shapes = {i: s for s, i in world.index.items()}
    for i, (b, body) in enumerate(zip(scene.bodies, world.bodies)):
        shape = shapes[i]
        assert shape.elasticity == b.restitution and shape.friction == b.friction
        assert body.angle == b.angle
        if b.fixed:
            assert body.body_type == pymunk.Body.STATIC
            continue
        assert body.mass == b.mass
        assert math.isclose(body.moment, b.inertia, rel_tol=1e-12)      # ours, not pymunk's own
        assert tuple(body.position) == b.position and tuple(body.velocity) == b.velocity
        assert body.angular_velocity == b.angular_velocity
        assert body.center_of_gravity == (0, 0)
        verts = shape.get_vertices()
        assert len(verts) == len(b.vertices)
        for v in b.vertices:      # about the centre of mass (pymunk may start the loop elsewhere)
            assert min(math.hypot(v[0] - w.x, v[1] - w.y) for w in verts) < 1e-15
    balls = load_scene(str(ROOT / "examples" / "billiard-break.json"))
    world = build_space(balls)
    for b, body in zip(balls.bodies, world.bodies):
        if not b.fixed:
            assert body.moment == math.inf      # frictionless circles never turn, as in ours


def test_matcher_counts_missed_doubled_invented():
    ours = [(1.0, 0, 1), (2.0, 0, 2), (3.0, 1, 2), (3.02, 1, 2)]
    theirs = [(1.01, 1, 0),      # ours 0, pair given the other way round
              (1.03, 0, 1),      # a second begin within the window of ours 0: doubled
              (2.5, 0, 2),       # too late for ours 1 (missed) and near nothing: invented
              (3.01, 1, 2),      # ours 2
              (3.04, 1, 2),      # ours 3 (takes the earliest unused of its pair in its window)
              (5.0, 0, 1)]       # invented
    m = match_events(ours, theirs, 0.05)
    assert m.pairs == [(0, 0), (2, 3), (3, 4)]
    assert [round(e, 12) for e in m.errors] == [0.01, 0.01, 0.02]
    assert m.missed == [1]
    assert m.doubled == [1]
    assert m.invented == [2, 5]
    # nothing of theirs: all missed; nothing of ours: all invented
    assert match_events(ours, [], 0.05).missed == [0, 1, 2, 3]
    assert match_events([], theirs, 0.05).invented == list(range(len(theirs)))


def test_friction_and_restitution_combine_as_ours():
    """Chipmunk's arbiter multiplies the two shapes' friction and elasticity:
    the product rule of our model."""
    scene = parse_scene(json.dumps({"end_time": 1.0, "gravity": [0.0, -10.0], "bodies": [
        {"name": "box", "shape": "polygon", "mass": 1.0, "position": [0.0, 0.1], "velocity": [1.0, 0.0],
         "restitution": 0.5, "friction": 0.4, "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]},
        {"name": "floor", "shape": "polygon", "fixed": True, "position": [0.0, -0.5], "restitution": 0.8,
         "friction": 0.25, "vertices": [[-5, -0.5], [5, -0.5], [5, 0.5], [-5, 0.5]]}]}), "<friction>")
    world = build_space(scene)
    assert [s.friction for s in world.index] == [0.4, 0.25]
    seen = []
    world.space.on_collision(post_solve=lambda arb, space, data: seen.append((arb.friction, arb.restitution)))
    step_until(world, 1.0 / 240.0, 0.1)
    assert seen and all(math.isclose(f, 0.1) and math.isclose(e, 0.4) for f, e in seen)
    # sliding at mu g = 1 m/s^2 from 1 m/s: slower after 0.1 s, as ours
    assert 0.8 < world.bodies[0].velocity.x < 0.95


def test_free_run_applies_the_inputs():
    scene = parse_scene(json.dumps({"end_time": 0.5, "bodies": [
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0]}],
        "inputs": [{"time": 0.25, "body": "ball", "set_velocity": [2.0, 0.0]},
                   {"time": 0.3, "body": "ball", "add_velocity": [0.0, 1.0]}]}), "<inputs>")
    world = build_space(scene)
    world.inputs = list(scene.inputs)
    dt = 1.0 / 100.0
    step_until(world, dt, 0.5)
    x, y = world.bodies[0].position
    assert math.isclose(x, 2.0 * 0.25, rel_tol=1e-9) and math.isclose(y, 1.0 * 0.2, rel_tol=1e-9)


def test_rest_speed_contacts():
    # a hop of a body lying on another (the floor set its separation speed, slow approach)
    assert is_resting("collision", 0.05, 0.81, 0.05)
    # a real bounce; a fast landing that ends in support or with restitution 0
    assert not is_resting("collision", 2.0, 0.81, 0.05)
    assert not is_resting("support", 3.0, 0.0, 0.05) and not is_resting("collision", 3.0, 0.0, 0.05)
    assert is_resting("support", 0.04, 0.0, 0.05)


def test_ours_timed_less_start_up_and_events_by_name():
    scene = load_scene(str(ROOT / "examples" / "newtons-cradle.json"))
    ours = time_ours(scene, "c")
    # both runs were timed; which is larger is the machine's noise on a scene
    # this small (CI once measured the start-up above the whole run), so only
    # the arithmetic is asserted, on fixed figures
    assert ours.start > 0.0 and ours.cpu > 0.0
    assert ours.counts["collisions"] > 0 and ours.counts["frames"] == 180
    assert OurResult("c", 0.5, 0.25, {}).cpu_per_s(2.0) == 0.125
    assert math.isnan(OurResult("c", 0.001117, 0.001202, {}).cpu_per_s(2.0))
    # every N counter is a column by name, a new kind too; work counters last
    extra = dict(ours.counts, sleeps=3)
    rows = kinds_table([SceneResult("cradle", "", scene, [OurResult("c", 1.0, 0.5, extra)], 0, 0, 0, [])])
    head = [h.strip() for h in rows[0].strip("|").split("|")]
    assert head[:4] == ["scene", "simulated s", "events", "per collision"] and "sleeps" in head
    assert head[-3:] == ["stale", "pairs", "features"]
    cells = [c.strip() for c in rows[2].strip("|").split("|")]
    assert cells[head.index("sleeps")] == "3"
    events = sum(v for k, v in extra.items() if k not in ("stale", "pairs", "features"))
    assert cells[2] == f"{events:,}"


def test_every_example_scene_is_found():
    found = [path for _, path, _ in example_scenes()]
    assert found == (sorted(f"examples/{p.name}" for p in (ROOT / "examples").glob("*.json"))
                     + sorted(f"examples/piles/{p.name}" for p in (ROOT / "examples" / "piles").glob("*.json")))
    assert len(found) >= 14 and "examples/piles/pit-200.json" in found
