"""The live world of the Python runtime (docs/engine-api.md) made from a
JSON scene: the contact equations generated for the scene's effects (as
`max2code simulate --lang python` builds them), loaded as modules, and
`max2code_rt.sim.World` made from the compiled scene."""
from __future__ import annotations

import importlib.util
import json

from max2code.paths import RUNTIMES
from max2code.sim.scene import Scene, compile_scene
from max2code.sim.simulate import build_simulator


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
    """A max2code_rt.sim.World of the scene; `out` is the flat trace's sink
    (anything with write(str)), None for no trace."""
    cc, pe = equations(scene)
    return _runtime().World(compile_scene(scene), cc, pe, out)


def flat_body(scene: Scene, raw: dict, path: str = "<body>") -> str:
    """The flat lines add_body takes for a body given as in a JSON scene
    (checked as in one: the scene's gravity applies; position and velocity
    are the state at the world's time of the add)."""
    from max2code.sim.scene import body_lines, parse_scene
    one = parse_scene(json.dumps({"end_time": scene.end_time, "gravity": list(scene.gravity), "bodies": [raw]}), path)
    return "\n".join(body_lines(one.bodies[0], False)) + "\n"
