"""Live worlds (docs/engine-api.md) made from a JSON scene, for programs
that drive the engine themselves (a game loop, a test bed).

`open_world(scene, engine)` checks and compiles the scene
(max2code/sim/scene.py), builds the contact equations for exactly its
effects (cached, as `max2code simulate` builds them) and returns a world:

* engine="c": the compiled C world through ctypes (max2code/sim/cworld.py,
  libm2c_world.so of the scene's build), at C speed;
* engine="python": the pure-Python reference, `max2code_rt.sim.World`
  (`python_world`, with the input checks the C binding makes:
  `checked_world`): the contact equations generated for the scene's
  effects, loaded as modules, and the world made from the compiled scene.

Both take the same calls and give the same contacts, states and trace bytes
(tests/runtimes/test_live.py)."""
from __future__ import annotations

import functools
import importlib.util
import json
import os

from max2code.paths import RUNTIMES
from max2code.sim.scene import (Scene, SceneError, body_lines, body_window, circle_lever, compile_scene, load_scene,
                                parse_scene)
from max2code.sim.simulate import build_simulator, world_library

ENGINES = ("c", "python")


def _runtime():
    """max2code_rt.sim, from the runtime folder when it is not on the path."""
    try:
        from max2code_rt import sim
    except ImportError:
        import sys
        sys.path.insert(0, str(RUNTIMES / "python"))
        from max2code_rt import sim
    return sim


def _module(path: str, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def equations(scene: Scene):
    """The generated (circle_circle, point_edge) modules for the scene's
    effects and Taylor order (built once, cached under build/sim/python/)."""
    build = build_simulator("python", scene.effects, scene.taylor_order)
    return (_module(build.generated["circle_circle"], "m2c_gen_circle_circle"),
            _module(build.generated["point_edge"], "m2c_gen_point_edge"))


def python_world(scene: Scene, out=None):
    """A max2code_rt.sim.World of the scene, with the checks of the C
    binding (checked_world); `out` is the flat trace's sink (anything with
    write(str)), None for no trace."""
    cc, pe = equations(scene)
    return checked_world()(compile_scene(scene), cc, pe, out)


@functools.cache
def checked_world():
    """max2code_rt.sim.World that, as the C binding (max2code/sim/cworld.py),
    also refuses a second finish(); the engine itself refuses inputs after
    finish() and inputs whose result would not be finite."""
    sim = _runtime()
    from max2code.sim.cworld import FINISHED

    class CheckedWorld(sim.World):
        def finish(self):
            if self.finished:
                raise sim.SimError(FINISHED)
            return super().finish()

    return CheckedWorld


def flat_body(scene: Scene, raw: dict, path: str = "<body>") -> str:
    """The flat lines add_body takes for a body given as in a JSON scene
    (checked as in one: the scene's gravity applies; position and velocity
    are the state at the world's time of the add)."""
    one = parse_scene(json.dumps({"end_time": scene.end_time, "gravity": list(scene.gravity), "bodies": [raw]}), path)
    b = one.bodies[0]
    return "\n".join(body_lines(b, False, body_window(b, scene, circle_lever(scene)))) + "\n"


def as_scene(scene) -> Scene:
    """A checked Scene from a path to a JSON scene, a dict (a JSON scene
    already read) or a Scene."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        name = scene.get("name")
        return parse_scene(json.dumps(scene), name if isinstance(name, str) else "<scene>")
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(os.fspath(scene))
    raise SceneError(f"<scene>: error: expected a path, a dict or a Scene, got {type(scene).__name__}")


def open_world(scene, engine: str = "c", *, out=None):
    """A world at t = 0 of the scene (a path, a dict or a Scene: as_scene) in
    `engine` ("c" or "python"); `out`: None or an object with write(str) that
    receives the flat trace as events happen."""
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, not {engine!r}")
    sc = as_scene(scene)
    if engine == "python":
        return python_world(sc, out)
    from max2code.sim.cworld import CWorld   # here: it imports max2code_rt, which need not be on the path (_runtime)
    return CWorld(str(world_library(sc, "c")), compile_scene(sc), out)


def body_index(scene: Scene, name: str) -> int:
    """The index of the body called name (the worlds' calls take indices)."""
    for k, b in enumerate(scene.bodies):
        if b.name == name:
            return k
    raise KeyError(f"{scene.path}: no body named {name!r}")
