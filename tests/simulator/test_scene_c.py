"""The C scene reader (max2code/sim/scene_c.py, runtimes/c/tools/m2c_scene_flat.c)
against the Python one (max2code/sim/scene.py), its specification: a scene
the C reader takes gives compile_scene's flat text byte for byte and the same
facts (effects, end time, Taylor order, event limit, names as JSON, largest
index); a scene Python refuses is never taken (the command then reads it in
Python and reports the fault as before).  Checked on the examples, on gases
like the benchmark's, on hypothesis-made scenes whose numbers are spelt in
every way JSON allows (integers, exponents, minus zero, 17 digits, subnormal)
with defaults left out, comments, gravity, fixed circles and walls, and on
each kind of fault."""
import ctypes
import json
import math
import os
import random
import struct
import sys
import tempfile

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from max2code.paths import ROOT
from max2code.sim import scene_c
from max2code.sim.scene import SceneError, compile_scene, load_scene
from max2code.sim.simulate import trace_names
from max2code.textio import InputError

sys.path.insert(0, str(ROOT / "bench"))
from sim import gas  # noqa: E402  (bench/sim.py's gas of disks in a box)

EXAMPLES = sorted((ROOT / "examples").glob("*.json"))

pytestmark = pytest.mark.skipif(scene_c.library() is None, reason="the C scene reader cannot be built")


def both(text):
    """(the C reader's FlatScene or None, Python's Scene or the SceneError's text) of a scene's JSON text
    (str, or bytes as they are)."""
    fd, path = tempfile.mkstemp(suffix=".json")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(text if isinstance(text, bytes) else text.encode("utf-8"))
        fast = scene_c.read_scene(path)
        try:
            scene = load_scene(path)
        except (SceneError, InputError) as exc:
            return fast, str(exc).replace(path, "SCENE")
        return fast, scene
    finally:
        os.unlink(path)


def agree(fast, scene) -> None:
    """A scene the C reader took is Python's, byte for byte."""
    assert not isinstance(scene, str), f"the C reader took a scene Python refuses: {scene}"
    assert fast.flat == compile_scene(scene).encode("ascii")
    assert (fast.effects, fast.end_time, fast.taylor_order, fast.max_events) == \
           (scene.effects, scene.end_time, scene.taylor_order, scene.max_events)
    assert (fast.json_names, fast.most) == trace_names(scene)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples(path):
    fast, scene = both(path.read_text(encoding="utf-8"))
    if fast is not None:
        agree(fast, scene)


def test_the_common_scenes_are_taken():
    """The gases and the examples without polygons that move or turn and without inputs are the C reader's."""
    for n, seed in ((3, 1), (200, 2), (2000, 3)):
        fast, scene = both(json.dumps(gas(n, 0.3, 0.5, seed)))
        assert fast is not None, n
        agree(fast, scene)
    for name in ("gravity-box", "resting-ball"):
        fast, scene = both((ROOT / "examples" / f"{name}.json").read_text(encoding="utf-8"))
        assert fast is not None, name


# ------------------------------------------------------------ numbers
def some_doubles(rng, n):
    """Doubles of every kind: uniform, any bits, spread over the decades, short decimals, powers of two
    and their neighbours, the ends of the C code's quick ranges."""
    edges = [0.0, -0.0, 1e-4, 1e15, 9.999999999999999e14, 1e-4 * (1 - 1e-16), 5e-324, 2.2250738585072014e-308,
             1.7976931348623157e308, 0.1, 0.3, 2.0 / 3.0, 123456789012345.67, 1e23, 8.41e21, 9007199254740993.0]
    yield from edges
    for _ in range(n):
        r = rng.random()
        if r < 0.3:
            yield rng.uniform(-100.0, 100.0)
        elif r < 0.5:
            x = struct.unpack("d", struct.pack("Q", rng.getrandbits(64)))[0]
            if math.isfinite(x):
                yield x
        elif r < 0.7:
            yield rng.uniform(0.0, 1.0) * 10.0 ** rng.randint(-8, 18)
        elif r < 0.8:
            yield float(f"{rng.uniform(-1e3, 1e3):.{rng.randint(1, 17)}g}")
        elif r < 0.9:
            yield 2.0 ** rng.randint(-30, 60) * rng.choice([1.0, -1.0, 3.0, 0.75])
        else:
            x = rng.uniform(1e-4, 1e15)
            yield math.nextafter(x, math.inf) if rng.random() < 0.5 else x


def test_numbers_read_and_written_as_python_does():
    """The C reader's numbers are float()'s of their text (every spelling: repr, 17 digits, exponents, 19
    and 20 digits, few digits) and its written numbers repr()'s, on 20000 doubles of every kind."""
    lib = scene_c.library()
    buf = ctypes.create_string_buffer(64)
    out = ctypes.c_double()
    read = 0
    for x in some_doubles(random.Random(3), 20000):
        assert lib.sf_repr(x, buf, 64) > 0 and buf.value.decode() == repr(x), x
        for text in (repr(x), f"{x:.17g}", f"{x:.17e}", f"{x:.15e}", f"{x:.3f}", f"{x:.19e}", f"{x:.20f}"):
            if "." not in text and "e" not in text:
                text += ".0"
            data = text.encode()
            if lib.sf_number(data, len(data), ctypes.byref(out)):
                read += 1
                assert (out.value, math.copysign(1.0, out.value)) == (float(text), math.copysign(1.0, float(text)))
    assert read > 100000


# ------------------------------------------------------------ made scenes
def spell(x: float, how: int) -> str:
    """x as JSON text, one of several spellings that read back as x."""
    if how == 1 and x == int(x) and abs(x) < 1e15:
        return str(int(x)) if x != 0.0 or math.copysign(1.0, x) > 0 else "-0"
    if how == 2:
        return f"{x:.17g}" if "e" in f"{x:.17g}" or "." in f"{x:.17g}" else f"{x:.17g}.0"
    if how == 3:
        return f"{x:.17E}"
    if how == 4:
        return f"{x:.6e}" if float(f"{x:.6e}") == x else repr(x)
    return repr(x)


def numbers(lo: float, hi: float):
    nice = st.sampled_from([v for v in (0.0, -0.0, 0.5, 1.0, 2.0, 0.1, 1e-5, 3.0, 1e16, 123456789.0)
                            if lo <= v <= hi])
    return st.one_of(nice, st.floats(lo, hi, allow_nan=False, allow_infinity=False))


@st.composite
def scenes(draw):
    ways = st.integers(0, 4)
    out = {"end_time": 1.0}
    put = []                # [(key, text)] of the scene, in order

    def num(lo, hi):
        return spell(draw(numbers(lo, hi)), draw(ways))

    put.append(("end_time", spell(draw(st.floats(0.01, 100.0)), draw(ways))))
    if draw(st.booleans()):
        put.append(("gravity", f"[{num(-20.0, 20.0)}, {num(-20.0, 20.0)}]"))
    for key, lo, hi in (("tolerance", 1e-12, 1e-3), ("rest_speed", 0.0, 1.0), ("frame_rate", 0.0, 100.0)):
        if draw(st.booleans()):
            put.append((key, num(lo, hi)))
    if draw(st.booleans()):
        put.append(("taylor_order", str(draw(st.integers(1, 7)))))
    if draw(st.booleans()):
        put.append(("comment", json.dumps(draw(st.recursive(
            st.none() | st.booleans() | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=5),
            lambda c: st.lists(c, max_size=3) | st.dictionaries(st.text(max_size=3), c, max_size=3),
            max_leaves=6)))))
    bodies = []
    n = draw(st.integers(1, 25))
    side = draw(st.floats(3.0, 50.0))
    for k in range(n):
        f = []
        if draw(st.integers(0, 4)) == 0:
            w, h = draw(st.floats(0.05, 5.0)), draw(st.floats(0.05, 5.0))
            f.append(('"shape"', '"polygon"'))
            f.append(('"fixed"', "true"))
            f.append(('"position"', f"[{num(-side, side)}, {num(-side, side)}]"))
            f.append(('"vertices"', json.dumps([[-w, -h], [w, -h], [w, h], [-w, h]])))
            if draw(st.booleans()):
                f.append(('"angle"', num(-3.0, 3.0)))
        else:
            fixed = draw(st.integers(0, 3)) == 0
            f.append(('"shape"', '"circle"'))
            f.append(('"radius"', num(1e-3, 0.5 if draw(st.integers(0, 5)) else 5.0)))
            f.append(('"position"', f"[{num(-side, side)}, {num(-side, side)}]"))
            if fixed:
                f.append(('"fixed"', "true"))
            else:
                if draw(st.booleans()):
                    f.append(('"fixed"', "false"))
                f.append(('"mass"', num(1e-3, 10.0)))
            for key in ("velocity", "acceleration"):
                if draw(st.booleans()):
                    f.append((f'"{key}"', f"[{num(-10.0, 10.0)}, {num(-10.0, 10.0)}]"))
            for key, lo, hi in (("restitution", 0.0, 1.0), ("friction", 0.0, 2.0), ("angle", -7.0, 7.0)):
                if draw(st.booleans()):
                    f.append((f'"{key}"', num(lo, hi)))
            if draw(st.integers(0, 40)) == 0:
                f.append(('"angular_velocity"', draw(st.sampled_from(["0", "0.0", "-0.0", "0.5"]))))
        if draw(st.booleans()):
            name = draw(st.sampled_from([f"b{k}"] * 300 + [f"body{k}"] * 100 + [f"body{k + 1}", "x"]))
            f.append(('"name"', json.dumps(name)))
        if draw(st.integers(0, 5)) == 0:
            f.append(('"comment"', '"a \\"quoted\\" word"'))
        f = draw(st.permutations(f))
        bodies.append("{" + ", ".join(f"{a}: {b}" for a, b in f) + "}")
    put.append(("bodies", "[" + ", ".join(bodies) + "]"))
    put = draw(st.permutations(put))
    return "{" + ", ".join(f'"{k}": {v}' for k, v in put) + "}"


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_made_scenes(text):
    """Whatever the C reader takes, Python takes too, with the same flat text (overlapping bodies, duplicate
    names, spinning circles and the like among them: those Python refuses)."""
    fast, scene = both(text)
    if fast is not None:
        agree(fast, scene)


def test_made_scenes_are_mostly_taken():
    """The property above is not vacuous: of 200 made scenes that Python takes, the C reader takes most."""
    rng = random.Random(5)
    taken = valid = 0
    for k in range(200):
        n = rng.randint(1, 30)
        disks = [{"shape": "circle", "name": f"d{i}", "radius": 0.01, "mass": 1.0 + i,
                  "position": [0.05 * i, rng.uniform(-1.0, 1.0) if i % 2 else 0.0],
                  "velocity": [rng.uniform(-1, 1), rng.gauss(0, 1)]} for i in range(n)]
        text = json.dumps({"end_time": rng.uniform(0.1, 2.0), "gravity": [0, -9.81] if k % 2 else [0.0, 0.0],
                           "bodies": disks})
        fast, scene = both(text)
        if not isinstance(scene, str):
            valid += 1
            taken += fast is not None
            if fast is not None:
                agree(fast, scene)
    assert valid > 150 and taken == valid


# ------------------------------------------------------------ faults: never taken
GOOD = {"end_time": 1.0, "bodies": [
    {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -0.5],
     "vertices": [[-2, -0.5], [2, -0.5], [2, 0.5], [-2, 0.5]]},
    {"name": "a", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.5], "velocity": [1, 0]},
    {"name": "b", "shape": "circle", "radius": 0.1, "mass": 2.0, "position": [0.5, 0.5]}]}


def edit(path, value):
    scene = json.loads(json.dumps(GOOD))
    *head, last = path
    obj = scene
    for k in head:
        obj = obj[k]
    if value is KeyError:
        del obj[last]
    else:
        obj[last] = value
    return json.dumps(scene)


FAULTS = {
    "overlap": edit(("bodies", 2, "position"), [0.15, 0.5]),
    "overlap with the floor": edit(("bodies", 1, "position"), [0.0, 0.05]),
    "touching the floor within the margin": edit(("bodies", 1, "position"), [0.0, 0.1]),
    "duplicate name": edit(("bodies", 2, "name"), "a"),
    "no mass": edit(("bodies", 1, "mass"), KeyError),
    "zero mass": edit(("bodies", 1, "mass"), 0),
    "mass of a fixed circle": edit(("bodies", 1, "fixed"), True),
    "negative radius": edit(("bodies", 1, "radius"), -0.1),
    "restitution above 1": edit(("bodies", 1, "restitution"), 1.5),
    "spinning circle": edit(("bodies", 1, "angular_velocity"), 1.0),
    "string number": edit(("bodies", 1, "radius"), "0.1"),
    "boolean number": edit(("bodies", 1, "radius"), True),
    "unknown body key": edit(("bodies", 1, "colour"), "red"),
    "unknown scene key": edit(("speed",), 2),
    "unknown shape": edit(("bodies", 1, "shape"), "square"),
    "no end time": edit(("end_time",), KeyError),
    "taylor order 8": edit(("taylor_order",), 8),
    "taylor order 2.5": edit(("taylor_order",), 2.5),
    "no bodies": edit(("bodies",), []),
    "far away": edit(("bodies", 2, "position"), [1e151, 0.5]),
    "too fast": edit(("bodies", 2, "velocity"), [2e150, 0.0]),
    "at the speed limit": edit(("bodies", 2, "velocity"), [1e150, 0.0]),
    "tiny radius": edit(("bodies", 1, "radius"), 1e-151),
    "frame rate above the limit": edit(("frame_rate",), 5000),
    "frames beyond max_events": json.dumps({**GOOD, "frame_rate": 100, "max_events": 50}),
    "a polygon's bad vertices": edit(("bodies", 0, "vertices"), [[0, 0], [1, 0]]),
}
MOVING = json.loads(json.dumps(GOOD))
MOVING["bodies"][0].update(fixed=False, mass=5.0)
FAULTS["a moving polygon"] = json.dumps(MOVING)
UNNAMED = json.loads(json.dumps(GOOD))
del UNNAMED["bodies"][1]["name"]
UNNAMED["bodies"][2]["name"] = "body1"
FAULTS["a default name taken"] = json.dumps(UNNAMED)
TEXT_FAULTS = {
    "NaN": json.dumps(GOOD).replace('"radius": 0.1', '"radius": NaN', 1),
    "1e400": json.dumps(GOOD).replace('"radius": 0.1', '"radius": 1e400', 1),
    "trailing comma": json.dumps(GOOD)[:-2] + "],}",
    "extra data": json.dumps(GOOD) + " 1",
    "repeated key": json.dumps(GOOD).replace('"mass": 1.0', '"mass": 1.0, "mass": 0.5', 1),
    "leading zero": json.dumps(GOOD).replace('"mass": 2.0', '"mass": 02.0', 1),
    "control character": json.dumps(GOOD).replace('"name": "a"', '"name": "a\tb"', 1),
    "19-digit integer": json.dumps(GOOD).replace('"mass": 2.0', '"mass": 1000000000000000000', 1),
    "non-ASCII name": json.dumps(GOOD, ensure_ascii=False).replace('"a"', '"\xe9"', 1),
    "escaped name": json.dumps(GOOD).replace('"a"', '"\\u0061x"', 1),
    "not UTF-8": json.dumps(GOOD).encode().replace(b'"a"', b'"\xe9"', 1),
    "inputs": json.dumps({**GOOD, "inputs": [{"time": 0.1, "body": "a", "impulse": [1, 0]}]}),
}


@pytest.mark.parametrize("case", sorted({**FAULTS, **TEXT_FAULTS}))
def test_faults_are_not_taken(case):
    text = {**FAULTS, **TEXT_FAULTS}[case]
    fast, scene = both(text)
    assert fast is None
    if case in ("inputs", "a moving polygon", "19-digit integer", "touching the floor within the margin",
                "non-ASCII name", "escaped name", "repeated key", "at the speed limit"):
        assert not isinstance(scene, str), scene        # good scenes the C reader leaves to Python
    else:
        assert isinstance(scene, str), f"{case}: Python takes it"


def test_the_good_scene_is_taken():
    fast, scene = both(json.dumps(GOOD))
    assert fast is not None
    agree(fast, scene)


@pytest.mark.slow
def test_command_with_and_without_the_c_reader(tmp_path, monkeypatch):
    """`max2code simulate` writes the same trace whichever reader took the scene, and the same error."""
    from max2code.sim import commands

    good = tmp_path / "good.json"
    good.write_text(json.dumps(gas(300, 0.3, 0.2, 7)), encoding="utf-8")
    bad = tmp_path / "bad.json"
    bad.write_text(FAULTS["overlap"], encoding="utf-8")
    outs, errors = [], []
    for reader in (scene_c.read_scene, lambda path: None):
        monkeypatch.setattr(commands, "read_scene", reader)
        out = tmp_path / f"trace{len(outs)}.jsonl"
        assert commands.simulate_main([str(good), "-o", str(out), "-q"]) == 0
        outs.append(out.read_bytes())
        with pytest.raises(commands.SimCliError) as exc:
            commands.simulate_main([str(bad), "-o", str(tmp_path / "x.jsonl"), "-q"])
        errors.append(str(exc.value))
    assert outs[0] == outs[1] and len(outs[0]) > 1000
    assert errors[0] == errors[1] and "overlap at t = 0" in errors[0]


MUTANT_BASE = json.dumps({**GOOD, "gravity": [0, -9.81], "comment": {"why": ["a", 1, 2.5e-3, None, True]}},
                         indent=1)
SPARE = ' \n\t{}[],:"-+.0123456789eEtruefalsnl\\u'


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(0, len(MUTANT_BASE) - 1), st.integers(0, 2), st.sampled_from(SPARE)),
                min_size=1, max_size=4))
def test_mutated_texts(edits):
    """A good scene's text with a few characters deleted, inserted or replaced (broken JSON, changed numbers
    and names, keys and literals cut short): whatever the C reader takes, Python takes with the same flat
    bytes, and it never reads past the text (the C code sees only the text's own bytes)."""
    text = list(MUTANT_BASE)
    for at, how, c in edits:
        at = min(at, len(text) - 1)
        if how == 0:
            del text[at]
        elif how == 1:
            text.insert(at, c)
        else:
            text[at] = c
    fast, scene = both("".join(text))
    if fast is not None:
        agree(fast, scene)
