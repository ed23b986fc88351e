"""Run a scene in one runtime's simulator: generate the two contact
equations for the effects the scene uses, build that language's simulator
with them (cached under build/sim/), feed it the compiled scene and read its
flat trace back into JSON events (docs/simulator.md)."""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
from dataclasses import dataclass, field

from max2code.generate.pipeline import GenerateRequest, build_selection, derive, generate
from max2code.generate.mxm import read_mxm
from max2code.harness.runtimes import BUILD, ROOT
from max2code.sim.scene import Scene, compile_scene
from max2code.targets import target as get_target

EQUATIONS = {"circle_circle": ROOT / "equations" / "circle-circle.mxm",
             "point_edge": ROOT / "equations" / "point-edge.mxm"}
LANGS = ("python", "c", "rust", "m2")
FEATURES = {(0, False): "circle-circle", (0, True): "circle-vertex", (1, False): "circle-edge", (1, True): "vertex-edge"}


class SimulateError(RuntimeError):
    """The simulator did not build, failed, or reported a stuck scene."""


@dataclass
class SimBuild:
    lang: str
    workdir: str
    run_cmd: list[str]
    variant_names: dict[str, list[str]]     # equation -> variant names in the index order of NAME_variant


@dataclass
class Trace:
    lang: str
    events: list[dict]
    final: dict
    stats: dict
    raw: str = field(repr=False, default="")

    def lines(self) -> list[str]:
        out = [json.dumps(e, separators=(",", ":")) for e in self.events]
        out.append(json.dumps(self.final, separators=(",", ":")))
        out.append(json.dumps(self.stats, separators=(",", ":")))
        return out


def _hash_tree(path, h) -> None:
    for base, dirs, files in sorted(os.walk(path)):
        dirs.sort()
        dirs[:] = [d for d in dirs if d not in ("target", "__pycache__")]
        for f in sorted(files):
            p = os.path.join(base, f)
            h.update(p.encode())
            with open(p, "rb") as fh:
                h.update(fh.read())


def build_simulator(lang: str, effects: tuple[str, ...], order: int, *, progress: bool = False) -> SimBuild:
    """Generate the equations for exactly these effects and build the
    simulator of `lang` with them (rebuilt only when something changed)."""
    tgt = get_target(lang)
    tag = ("-".join(effects) or "none") + f"-o{order}"
    workdir = BUILD / "sim" / lang / tag
    workdir.mkdir(parents=True, exist_ok=True)
    generated: dict[str, str] = {}
    names: dict[str, list[str]] = {}
    h = hashlib.sha256()
    for eq, path in EQUATIONS.items():
        fname = eq + tgt.extension
        req = GenerateRequest(str(path.relative_to(ROOT)), lang, options={"order": str(order)}, effects=effects,
                              out_name=fname, progress=progress)
        cwd = os.getcwd()
        os.chdir(ROOT)      # generated headers name the .mxm relative to the project
        try:
            mod = read_mxm(req.path)
            d = derive(mod, req.options, use_cache=True)
            out = generate(d, req)
        finally:
            os.chdir(cwd)
        from max2code.generate.variants import switches_of
        sel = build_selection(f"{eq}_coefficients", out.variants, switches_of(d), "")
        names[eq] = [c.name for c in sel.cases]
        target_file = workdir / fname
        if not target_file.exists() or target_file.read_text(encoding="utf-8") != out.text:
            target_file.write_text(out.text, encoding="utf-8")
        generated[eq] = str(target_file)
        h.update(out.text.encode())
    _hash_tree(ROOT / "runtimes" / lang, h)
    stamp = workdir / "build.stamp"
    digest = h.hexdigest()
    if not stamp.exists() or stamp.read_text() != digest:
        for cmd in tgt.sim_build(str(workdir), generated):
            proc = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=1800)
            if proc.returncode != 0:
                raise SimulateError(f"{lang} simulator did not build: {' '.join(map(str, cmd))}\n"
                                    f"{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
        stamp.write_text(digest)
    return SimBuild(lang, str(workdir), tgt.sim_run(str(workdir), generated), names)


def _f(w: str) -> float:
    return float(w)


def parse_trace(text: str, scene: Scene, build: SimBuild) -> Trace:
    names = [b.name for b in scene.bodies]
    events: list[dict] = []
    final = {"kind": "final", "t": scene.end_time, "bodies": []}
    counts: dict[str, int] = {}
    predictions: dict[str, int] = {}
    for ln, line in enumerate(text.splitlines(), 1):
        w = line.split()
        if not w:
            continue
        try:
            tag = w[0]
            if tag == "E":
                kind, t = w[1], _f(w[2])
                ev: dict = {"t": t, "kind": kind}
                if kind in ("collision", "support"):
                    a, b, feat, i, j = int(w[3]), int(w[4]), int(w[5]), int(w[6]), int(w[7])
                    ev["bodies"] = [names[a], names[b]]
                    ev["feature"] = FEATURES[(feat, (j >= 0) if feat == 0 else (i >= 0))]
                    ev["features"] = [i, j]
                    ev["point"] = [_f(w[8]), _f(w[9])]
                    ev["normal"] = [_f(w[10]), _f(w[11])]
                    ev["impulse"] = _f(w[12])
                elif kind in ("stop", "leave"):
                    ev["bodies"] = [names[int(w[3])], names[int(w[4])]]
                    ev["edge"] = int(w[7])
                elif kind == "input":
                    ev["bodies"] = [names[int(w[3])]]
                    ev["input"] = int(w[6])
                events.append(ev)
            elif tag == "S":
                st = {"body": names[int(w[1])], "position": [_f(w[3]), _f(w[4])], "velocity": [_f(w[5]), _f(w[6])],
                      "angle": _f(w[7]), "angular_velocity": _f(w[8]), "acceleration": [_f(w[9]), _f(w[10])]}
                events[-1].setdefault("states", []).append(st)
            elif tag == "F":
                final["bodies"].append({"body": names[int(w[1])], "position": [_f(w[2]), _f(w[3])],
                                        "velocity": [_f(w[4]), _f(w[5])], "angle": _f(w[6]),
                                        "angular_velocity": _f(w[7])})
            elif tag == "N":
                counts[w[1]] = int(w[2])
            elif tag == "V":
                eq, k, n = w[1], int(w[2]), int(w[3])
                if n:
                    predictions[build.variant_names[eq][k]] = n
            elif tag == "X":
                raise SimulateError(f"{scene.path}: {build.lang} simulator: {line[2:]}")
            else:
                raise ValueError(f"unknown line tag {tag!r}")
        except (IndexError, ValueError, KeyError) as exc:
            raise SimulateError(f"{build.lang} simulator wrote a bad trace line {ln}: {line[:120]!r} ({exc})") from None
    stats = {"kind": "stats", "lang": build.lang, "events": counts, "predictions": dict(sorted(predictions.items()))}
    return Trace(build.lang, events, final, stats, text)


def run_scene(scene: Scene, lang: str, *, progress: bool = False, timeout: float = 3600) -> Trace:
    build = build_simulator(lang, scene.effects, scene.taylor_order, progress=progress)
    flat = compile_scene(scene)
    proc = subprocess.run(build.run_cmd, input=flat, capture_output=True, text=True, cwd=build.workdir,
                          timeout=timeout)
    if proc.returncode != 0:
        last = proc.stdout.rstrip().splitlines()[-1] if proc.stdout.strip() else ""
        if last.startswith("X "):
            raise SimulateError(f"{scene.path}: {lang} simulator: {last[2:]}")
        raise SimulateError(f"{scene.path}: {lang} simulator failed (exit {proc.returncode}): {proc.stderr[-2000:]}")
    return parse_trace(proc.stdout, scene, build)
