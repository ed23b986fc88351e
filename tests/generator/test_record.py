"""max2code/record.py: the plain records that replace dataclasses on the
import path of `max2code simulate` compare, print and hash by their fields."""
from __future__ import annotations

import os
from pathlib import Path
import pickle
import subprocess
import sys

import pytest

from max2code.errors import Span
from max2code.sim.scene import Body, Grid, Scene

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def body(**kw):
    args = dict(name="a", polygon=False, fixed=False, mass=1.0, inertia=0.0, restitution=1.0, position=(0.0, 0.0),
                velocity=(1.0, 0.0), acceleration=(0.0, 0.0), angle=0.0, angular_velocity=0.0, radius=0.1)
    args.update(kw)
    return Body(**args)


def test_equality_and_repr_by_fields():
    a, b = body(), body()
    assert a == b and a.vertices == [] and a.vertices is not b.vertices    # a fresh list each, as default_factory
    assert body(radius=0.2) != a and a != "a"
    assert repr(Span("f.mxm", 3, 4)) == "Span(file='f.mxm', line=3, column=4)"
    assert str(Span("f.mxm", 3, 4)) == "f.mxm:3:4"
    assert a.bound == 0.1 and a == b        # a cached property is no field
    with pytest.raises(TypeError):
        hash(a)                             # mutable: unhashable, as a dataclass with eq


def test_frozen_records_hash_and_refuse_assignment():
    s, t = Span("f", 1, 2), Span("f", 1, 2)
    assert s == t and hash(s) == hash(t) and len({s, t, Span("f", 1, 3)}) == 2
    with pytest.raises(AttributeError):
        s.line = 5
    g = Grid(0.0, 0.0, 1.0, 1.0, 2, 2, 0.25, (False,))
    with pytest.raises(AttributeError):
        del g.nx
    assert pickle.loads(pickle.dumps(g)) == g


def test_scene_replace_changes_only_what_is_named():
    sc = Scene("p", "n", 1.0, 60.0, (0.0, -9.81), 1e-9, 0.01, 4, 100, [body()], [])
    r = sc.replace(end_time=0.5)
    assert r.end_time == 0.5 and r.bodies is sc.bodies and r.max_events == sc.max_events and sc.end_time == 1.0
    assert r == Scene("p", "n", 0.5, 60.0, (0.0, -9.81), 1e-9, 0.01, 4, 100, [body()], [])


def test_the_simulate_command_imports_no_dataclasses():
    """`dataclasses` pulls in `inspect`: a tenth of the command's start on a small scene (docs/throughput.md)."""
    code = ("import sys; before = set(sys.modules); "
            "import max2code.cli, max2code.sim.commands, max2code.sim.trace_json; "
            "print(sorted(m for m in ('dataclasses', 'inspect') if m in sys.modules and m not in before))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert r.stdout == "[]\n", r.stdout
