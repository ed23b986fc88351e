"""Tipping (docs/contact-model.md, "Tipping off a support"): a box whose
centre of mass lies past the end of its support segment does not fall
asleep there; it keeps its free motion, pivots on the ledge's corner and
falls to the floor, while a box whose centre lies over the ledge stays
exactly where it is.  Each proof runs in every runtime, and all four write
the same bytes for the example scene examples/piles/overhang.json."""
from __future__ import annotations

from pathlib import Path

import pytest

from max2code.sim.commands import crosscheck
from max2code.sim.scene import parse_scene
from max2code.sim.simulate import LANGS

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
SCENE = ROOT / "examples" / "piles" / "overhang.json"


def overhang():
    return parse_scene(SCENE.read_text(), str(SCENE))


def final(tr, name):
    return next(b for b in tr.final["bodies"] if b["body"] == name)


def start(scene, name):
    return next(b for b in scene.bodies if b.name == name)


@pytest.fixture(scope="module")
def traces():
    scene = overhang()
    tr, problems = crosscheck(scene, LANGS)
    return scene, tr, problems


@pytest.mark.slow
def test_all_four_runtimes_write_the_same_bytes_for_the_overhang(traces):
    _, tr, problems = traces
    assert problems == []
    ref = tr[LANGS[0]]
    for lang in LANGS[1:]:
        assert tr[lang].raw == ref.raw, lang


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_an_overhanging_box_tips_off_the_ledge_onto_the_floor(traces, lang):
    scene, tr, _ = traces
    t = tr[lang]
    ledge_top = 0.5                      # the ledge's top face (position 0.45, half height 0.05)
    size = 0.2                           # the tipper's side
    tip = final(t, "tipper")
    assert tip["position"][1] < ledge_top - size, tip
    assert tip["position"][0] > 1.0, tip            # past the ledge's end
    # it never sleeps on the ledge: its first sleep is on the floor
    sleeps = [e for e in t.events if e["kind"] == "sleep" and e["bodies"][0] == "tipper"]
    assert sleeps and all(e["bodies"][1] == "floor" for e in sleeps), sleeps
    assert any(e["kind"] == "collision" and set(e["bodies"]) == {"tipper", "ledge"} for e in t.events)


@pytest.mark.slow
@pytest.mark.parametrize("lang", LANGS)
def test_a_box_whose_centre_is_over_the_ledge_stays_exactly(traces, lang):
    scene, tr, _ = traces
    t = tr[lang]
    b0 = start(scene, "holder")
    hold = final(t, "holder")
    assert hold["position"] == [b0.position[0], b0.position[1]], hold
    assert hold["velocity"] == [0.0, 0.0] and hold["angle"] == 0.0, hold
    sleeps = [e for e in t.events if e["kind"] == "sleep" and e["bodies"] == ["holder", "ledge"]]
    assert len(sleeps) == 1 and sleeps[0]["t"] == 0.0, sleeps
