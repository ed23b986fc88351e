"""A run that stops keeps its trace: every runtime writes and flushes the
events before the stop, and `max2code simulate -o FILE` keeps them in FILE,
closed by a `stopped` line that names the instant and the reason."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from max2code.cli import main
from max2code.sim.simulate import LANGS

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def _simulate(capsys, *args) -> tuple[int, str]:
    code = main(["simulate", *map(str, args)])
    return code, capsys.readouterr().err


@pytest.mark.slow
def test_a_stuck_run_keeps_its_trace_in_every_runtime(tmp_path, capsys):
    """Newton's cradle with at most one event at one instant: the first blow
    passed along the row at t = 0.2 s trips the guard.  Each runtime's trace
    holds the same events up to that instant, then the stop."""
    scene = json.loads((ROOT / "examples" / "newtons-cradle.json").read_text())
    scene["max_events_at_one_time"] = 1
    path = tmp_path / "cradle.json"
    path.write_text(json.dumps(scene))
    kept = {}
    for lang in LANGS:
        out = tmp_path / f"{lang}.jsonl"
        code, err = _simulate(capsys, "--lang", lang, path, "-o", out, "-q")
        msg = f"{path}: {lang} simulator: more than 1 events at t = 0.20000000000000001: the scene is stuck"
        assert (code, err) == (1, f"{msg}; the trace up to then is in {out}\n")
        lines = out.read_text().splitlines()
        last = json.loads(lines[-1])
        assert last == {"kind": "stopped", "t": 0.2, "error": msg[len(f"{path}: "):]}
        events = [json.loads(x) for x in lines[:-1]]
        assert events and all(e["t"] <= 0.2 for e in events)
        assert any(e["kind"] == "collision" and e["t"] == 0.2 for e in events), "the instant's first event is kept"
        kept[lang] = lines[:-1]
    for lang in LANGS:
        assert kept[lang] == kept[LANGS[0]], f"{lang}'s kept trace differs from {LANGS[0]}'s"


def test_a_run_over_the_event_limit_keeps_its_trace_on_standard_output(capsys):
    """Without -o the trace goes to standard output as it is made: the
    events up to the limit, then the stopped line; the error names the
    instant of the event past the limit."""
    code = main(["simulate", "--lang", "c", str(ROOT / "examples" / "ball-pit.json"), "--max-events", "50", "-q"])
    out, err = capsys.readouterr()
    lines = [json.loads(x) for x in out.splitlines()]
    assert code == 1 and len(lines) == 51 and lines[-1]["kind"] == "stopped"
    t = lines[-1]["t"]
    assert all(e["t"] <= t for e in lines[:-1]) and lines[-2]["t"] <= t
    head, _, tail = err.strip().partition(" at t = ")
    assert head.endswith(": error: more than 50 events (collisions, inputs, frames)"), err
    number, _, why = tail.partition(": ")
    assert float(number) == t and why == ("the run was stopped; raise max_events in the scene or --max-events, "
                                          "or shorten end_time"), err
