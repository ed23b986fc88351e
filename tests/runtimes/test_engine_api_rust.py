"""docs/engine-api.md's Rust program, built as written (rustc -D warnings
against the runtime crate and the equations generated for the scene) and
run on the Newton's cradle with a live impulse: it prints the contacts and
the striker's states the Python world gives when driven the same way, to
the last bit."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from max2code import paths
from max2code.sim.live import python_world
from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator
from max2code.toolchain import toolchain

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)

DOC = paths.ROOT / "docs" / "engine-api.md"


def program() -> str:
    found = re.findall(r"<!-- engine-api example: rust -->\n```rust\n(.*?)\n```", DOC.read_text(encoding="utf-8"),
                       re.S)
    assert len(found) == 1
    return found[0] + "\n"


def python_lines(scene) -> list[str]:
    """What the doc's program prints, from the Python reference world."""
    g = lambda x: "%.17g" % x  # noqa: E731
    w = python_world(scene)
    frame = 1.0 / 60.0
    lines = []
    k = 1
    while k * frame < w.s.end:
        t = k * frame
        for c in w.advance(t):
            lines.append(f"contact {g(c.t)} {c.a} {c.b} {g(c.impulse)}")
        px, py, *_ = w.state(4, t)
        if k % 60 == 0:
            lines.append(f"striker at {g(t)}: {g(px)} {g(py)}")
        if k == 90:
            w.apply_impulse(4, 0.0, 0.05)
        k += 1
    w.finish()
    return lines


def _build_and_run(tmp_path, scene, source: str, exe: str):
    """The Rust program source (main.rs) built against the runtime with the
    generated equations of the scene's effects beside it, the compiled
    scene in scene.flat, and run in tmp_path: the finished process."""
    build = build_simulator("rust", scene.effects, scene.taylor_order)
    shutil.copy(build.generated["circle_circle"], tmp_path / "circle_circle.rs")
    shutil.copy(build.generated["point_edge"], tmp_path / "point_edge.rs")
    (tmp_path / "scene.flat").write_text(compile_scene(scene), encoding="ascii")
    (tmp_path / "main.rs").write_text(source, encoding="utf-8")
    rust = toolchain("rust")
    subprocess.run(["rustc", "--edition", "2021", "-D", "warnings", *rust.runtime_flags(), "main.rs", "-o", exe],
                   cwd=tmp_path, check=True, capture_output=True, timeout=600)
    return subprocess.run([str(tmp_path / exe)], cwd=tmp_path, capture_output=True, text=True, timeout=60)


def test_the_rust_example_program_runs_as_the_python_world(tmp_path):
    scene = load_scene(str(paths.ROOT / "examples" / "newtons-cradle.json"))
    r = _build_and_run(tmp_path, scene, program(), "example")
    assert r.returncode == 0, r.stderr
    got = r.stdout.splitlines()
    assert any(line.startswith("contact ") for line in got) and any(line.startswith("striker ") for line in got)
    assert got == python_lines(scene)


ADD_PROGRAM = r"""
#[path = "circle_circle.rs"]
#[allow(dead_code)]
mod circle_circle;
#[path = "point_edge.rs"]
#[allow(dead_code)]
mod point_edge;

use max2code_rt::sim::{g17, SimError, World};

max2code_rt::sim_equations!(circle_circle, point_edge);

fn main() -> Result<(), SimError> {
    let text = std::fs::read_to_string("scene.flat").map_err(SimError::Io)?;
    let mut world = World::<GeneratedEquations>::from_scene(&text, Some(Box::new(std::io::stdout())))?;
    world.advance(0.5)?;
    let inside = std::fs::read_to_string("inside.flat").map_err(SimError::Io)?;
    let free = std::fs::read_to_string("free.flat").map_err(SimError::Io)?;
    let n = world.bodies();
    eprintln!("refused {:?}", world.add_body(&inside)?);
    let k = world.add_body(&free)?.expect("room for it");
    let s = world.state(k, 0.5)?;
    eprintln!("added {k} of {n} at {} {} {} {}", g17(s.px), g17(s.py), g17(s.vx), g17(s.vy));
    world.advance(1.0)?;
    world.remove_body(k)?;
    world.advance(1.5)?;
    world.finish()?;
    Ok(())
}
"""


def test_add_and_remove_body_in_rust_write_the_python_world_bytes(tmp_path):
    """add_body (refused where it overlaps, then accepted) and remove_body
    through Rust's World: the trace of the Python world driven the same way."""
    import io
    import json
    from max2code.sim.live import flat_body
    from max2code.sim.scene import parse_scene
    import sys
    sys.path.insert(0, str(paths.ROOT / "tests"))
    from sim_scenes import inputs_scene
    raw = inputs_scene(1.5)
    raw["inputs"] = []
    scene = parse_scene(json.dumps(raw))
    drop = {"name": "drop", "shape": "circle", "radius": 0.08, "mass": 0.5, "position": [0.3, 1.5],
            "velocity": [0.0, -1.0]}
    inside, free = flat_body(scene, drop | {"position": [1.0, 0.0]}), flat_body(scene, drop)
    out = io.StringIO()
    w = python_world(scene, out)
    w.advance(0.5)
    assert w.add_body(inside) == -1
    k = w.add_body(free)
    w.advance(1.0)
    w.remove_body(k)
    w.advance(1.5)
    w.finish()
    assert f"E add 0.5 {k} " in out.getvalue() and f"E input 1 {k} " in out.getvalue()

    (tmp_path / "inside.flat").write_text(inside, encoding="ascii")
    (tmp_path / "free.flat").write_text(free, encoding="ascii")
    r = _build_and_run(tmp_path, scene, ADD_PROGRAM, "add")
    assert r.returncode == 0, r.stderr
    n = len(scene.bodies)
    assert r.stderr.splitlines() == ["refused None", f"added {k} of {n} at 0.29999999999999999 1.5 0 -1"]
    assert r.stdout == out.getvalue()


SESSION_PROGRAM = r"""
#[path = "circle_circle.rs"]
#[allow(dead_code)]
mod circle_circle;
#[path = "point_edge.rs"]
#[allow(dead_code)]
mod point_edge;

use max2code_rt::sim::{g17, SimError, World};

max2code_rt::sim_equations!(circle_circle, point_edge);

fn main() -> Result<(), SimError> {
    let text = std::fs::read_to_string("scene.flat").map_err(SimError::Io)?;
    let mut world = World::<GeneratedEquations>::from_scene(&text, Some(Box::new(std::io::stdout())))?;
    let (ball, crate_, pebble) = (4, 5, 6);
    world.advance(0.3)?;
    world.apply_impulse(ball, 0.5, 2.0)?;
    world.set_velocity(crate_, 0.0, 1.0)?;
    let hit = world.next_event_time();
    world.advance(hit)?; // at an event's exact time: the input comes first
    world.add_velocity(pebble, 0.1, 0.1)?;
    world.advance(0.5)?;
    assert!(world.teleport(ball, 1.0, 1.2)?);
    assert!(!world.teleport(crate_, 1.0, -0.05)?); // into the floor: refused, not recorded
    world.advance(1.4)?;
    world.remove_body(pebble)?;
    world.finish()?;
    for inp in world.input_log() {
        eprintln!("{} {} {} {} {}", g17(inp.t), inp.body, inp.mode, g17(inp.vx), g17(inp.vy));
    }
    Ok(())
}
"""


def test_a_rust_session_recorded_gives_its_trace_in_rust_and_python(tmp_path):
    """A live session in Rust (inputs of every kind, one at an event's exact
    time, a refused teleport, a removal): its input log made into a
    recording (max2code.sim.recording) and run by the batch simulators of
    Rust and Python writes the session's trace byte for byte."""
    import json
    import sys
    from max2code.sim.recording import recording
    from max2code.sim.simulate import run_scene
    sys.path.insert(0, str(paths.ROOT / "tests"))
    from sim_scenes import inputs_scene
    raw = inputs_scene(2.0)
    raw["inputs"] = []
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(raw), encoding="utf-8")
    scene = load_scene(str(path))
    assert [b.name for b in scene.bodies[4:7]] == ["ball", "crate", "pebble"]
    r = _build_and_run(tmp_path, scene, SESSION_PROGRAM, "session")
    assert r.returncode == 0, r.stderr
    log = [(float(t), int(b), int(m), float(x), float(y)) for t, b, m, x, y in (ln.split() for ln in r.stderr.splitlines())]
    assert [m for _, _, m, _, _ in log] == [2, 0, 1, 3, 4]
    rec = tmp_path / "recording.json"
    rec.write_text(json.dumps(recording(str(path), log)), encoding="utf-8")
    for lang in ("rust", "python"):
        assert run_scene(load_scene(str(rec)), lang).raw == r.stdout, lang
