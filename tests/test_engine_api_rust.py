"""docs/engine-api.md's Rust program, built as written (rustc -D warnings
against the runtime crate and the equations generated for the scene) and
run on the Newton's cradle with a live impulse: it prints the contacts and
the striker's states the Python world gives when driven the same way, to
the last bit."""
from __future__ import annotations

import re
import shutil
import subprocess

from max2code import paths
from max2code.sim.live import python_world
from max2code.sim.scene import compile_scene, load_scene
from max2code.sim.simulate import build_simulator
from max2code.targets import target

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


def test_the_rust_example_program_runs_as_the_python_world(tmp_path):
    scene = load_scene(str(paths.ROOT / "examples" / "newtons-cradle.json"))
    build = build_simulator("rust", scene.effects, scene.taylor_order)
    shutil.copy(build.generated["circle_circle"], tmp_path / "circle_circle.rs")
    shutil.copy(build.generated["point_edge"], tmp_path / "point_edge.rs")
    (tmp_path / "scene.flat").write_text(compile_scene(scene), encoding="ascii")
    (tmp_path / "main.rs").write_text(program(), encoding="utf-8")
    rust = target("rust")
    subprocess.run(["rustc", "--edition", "2021", "-D", "warnings", *rust.runtime_flags(), "main.rs", "-o", "example"],
                   cwd=tmp_path, check=True, capture_output=True, timeout=600)
    r = subprocess.run([str(tmp_path / "example")], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    got = r.stdout.splitlines()
    assert any(line.startswith("contact ") for line in got) and any(line.startswith("striker ") for line in got)
    assert got == python_lines(scene)
