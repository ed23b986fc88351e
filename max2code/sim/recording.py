"""Recordings (docs/engine-api.md, "Recordings"): a live session written as
a JSON scene whose inputs are the scene's own followed by every live input
at the time it was made, so that any runtime's batch simulator writes the
session's trace again, byte for byte."""
from __future__ import annotations

import json
import math

from max2code.errors import Max2CodeError
from max2code.sim.scene import INPUT_KINDS, REMOVE, parse_scene
from max2code.textio import InputError, read_text


class RecordingError(Max2CodeError):
    """A session that cannot be written as a scene."""


def recording(scene_path: str, inputs, added: int = 0) -> dict:
    """The JSON scene of a session on the scene at scene_path: `inputs` is
    the world's input log, (t, body, mode, x, y) per input, the scene's own
    first (World.input_log()); `added` how many bodies add_body added (a
    recording cannot hold them)."""
    if added:
        raise RecordingError(f"{scene_path}: error: the session added {added} bodies with add_body; a recording "
                             "holds inputs only (add the bodies to the scene, then remove them)")
    try:
        text = read_text(scene_path)
    except InputError as exc:
        raise RecordingError(str(exc)) from None
    raw = json.loads(text)
    scene = parse_scene(text, scene_path)
    own = [(e.time, e.body, e.mode, e.velocity[0], e.velocity[1]) for e in scene.inputs]
    log = [tuple(x) for x in inputs]
    if log[:len(own)] != own:
        raise RecordingError(f"{scene_path}: error: the session's input log does not start with this scene's "
                             f"{len(own)} inputs: it was recorded on another scene")
    out = list(raw.get("inputs", []))
    for t, body, mode, x, y in log[len(own):]:
        if not (0 <= body < len(scene.bodies)) or not (0 <= mode < len(INPUT_KINDS)):
            raise RecordingError(f"{scene_path}: error: input (t={t!r}, body={body}, mode={mode}) names no body "
                                 "or kind of this scene")
        if not all(math.isfinite(v) for v in (t, x, y)):
            raise RecordingError(f"{scene_path}: error: input at t={t!r} on body {body} is not finite")
        e = {"time": float(t), "body": scene.bodies[body].name}
        e[INPUT_KINDS[mode]] = True if mode == REMOVE else [float(x), float(y)]
        out.append(e)
    raw["inputs"] = out
    return raw


def write_recording(scene_path: str, world, path: str) -> dict:
    """Write the recording of a live world (anything with input_log() and
    `added`) on the scene at scene_path to path; returns it.  The file is
    checked as any scene is, so a bad recording fails here, not later."""
    rec = recording(scene_path, world.input_log(), world.added)
    text = json.dumps(rec, indent=1) + "\n"
    parse_scene(text, path)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return rec
