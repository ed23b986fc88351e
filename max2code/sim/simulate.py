"""Run a scene in one runtime's simulator: generate the two contact
equations for the effects the scene uses, build that language's simulator
with them (cached under build/sim/), feed it the compiled scene and read its
flat trace back into JSON events (docs/simulator.md)."""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
import threading
from dataclasses import dataclass, field
from pathlib import Path

from max2code import __version__
from max2code.errors import Max2CodeError
from max2code.paths import BUILD, RUNTIMES, TEMPLATES, equation
from max2code.sim.scene import Scene, compile_scene
from max2code.targets import simulator_languages

PKG = Path(__file__).resolve().parent.parent     # the max2code package
EQUATIONS = {"circle_circle": equation("circle-circle"), "point_edge": equation("point-edge")}
LANGS = simulator_languages()
FEATURES = {(0, False): "circle-circle", (0, True): "circle-vertex", (1, False): "circle-edge", (1, True): "vertex-edge"}


class SimulateError(Max2CodeError):
    """The simulator did not build, failed, or reported a stuck scene."""


@dataclass
class SimBuild:
    lang: str
    workdir: str
    run_cmd: list[str]
    variant_names: dict[str, list[str]]     # equation -> variant names in the index order of NAME_variant
    generated: dict[str, str] = field(default_factory=dict)     # equation -> the generated source file


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
    tag = ("-".join(effects) or "none") + f"-o{order}"
    workdir = BUILD / "sim" / lang / tag
    workdir.mkdir(parents=True, exist_ok=True)
    # everything the build depends on but Maxima's version (its results are
    # cached by version anyway): when unchanged, neither generate nor build
    key = hashlib.sha256(json.dumps([lang, list(effects), order, __version__]).encode())
    for path in EQUATIONS.values():
        key.update(path.read_bytes())
    for tree in (PKG / "generate", PKG / "targets", TEMPLATES / lang, RUNTIMES / lang):
        _hash_tree(tree, key)
    inputs_stamp, names_file, stamp = workdir / "inputs.stamp", workdir / "variant-names.json", workdir / "build.stamp"
    try:
        if inputs_stamp.read_text() == key.hexdigest() and stamp.exists():
            saved = json.loads(names_file.read_text(encoding="utf-8"))
            if all(os.path.exists(g) for g in saved["generated"].values()):
                return SimBuild(lang, str(workdir), saved["run"], saved["names"], saved["generated"])
    except (OSError, ValueError, KeyError, TypeError):
        pass
    # the generator is imported only when something must be generated (it is most of the start-up)
    from max2code.generate.mxm import read_mxm
    from max2code.generate.pipeline import GenerateRequest, derive, generate
    from max2code.targets import target as get_target

    tgt = get_target(lang)
    generated = {}
    names: dict[str, list[str]] = {}
    h = hashlib.sha256()
    for eq, path in EQUATIONS.items():
        fname = eq + tgt.extension
        req = GenerateRequest(str(path), lang, options={"order": str(order)}, effects=effects,
                              out_name=fname, progress=progress)
        # generated headers name the .mxm as the bundle does, wherever it is installed
        mod = read_mxm(req.path, name=f"{path.parent.name}/{path.name}")
        d = derive(mod, req.options, use_cache=True)
        out = generate(d, req)
        names[eq] = [c.name for c in out.selection.cases]
        target_file = workdir / fname
        if not target_file.exists() or target_file.read_text(encoding="utf-8") != out.text:
            target_file.write_text(out.text, encoding="utf-8")
        generated[eq] = str(target_file)
        h.update(out.text.encode())
    _hash_tree(RUNTIMES / lang, h)
    digest = h.hexdigest()
    if not stamp.exists() or stamp.read_text() != digest:
        for cmd in tgt.sim_build(str(workdir), generated, {eq: len(n) for eq, n in names.items()}):
            proc = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=1800)
            if proc.returncode != 0:
                raise SimulateError(f"{lang} simulator did not build: {' '.join(map(str, cmd))}\n"
                                    f"{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
        stamp.write_text(digest)
    run = tgt.sim_run(str(workdir), generated)
    names_file.write_text(json.dumps({"names": names, "generated": generated, "run": run}), encoding="utf-8")
    inputs_stamp.write_text(key.hexdigest())
    return SimBuild(lang, str(workdir), run, names, generated)


def _num(w: str) -> str:
    """A trace number as JSON: the runtime's `%.17g` text, which reads back as
    the same double (a whole number gets '.0' so that it stays a float);
    never NaN or infinite.  (Re-printing each number in its shortest form
    would cost more than the simulation.)"""
    if "." in w or "e" in w:
        if "n" in w:
            raise ValueError(f"non-finite number {w}")
        return w
    if "n" in w or "i" in w:
        raise ValueError(f"non-finite number {w}")
    return w + ".0"


class TraceConverter:
    """Turns the runtime's flat trace (docs/simulator.md), line by line, into
    the JSON lines of `max2code simulate`: each event is written when the
    next record starts, so memory does not grow with the number of events
    (the final states and statistics are per body and per variant)."""

    def __init__(self, scene: Scene, build: SimBuild, write, *, frames: bool = True,
                 max_events: int | None = None):
        self.scene, self.build, self.write = scene, build, write
        self.names = [json.dumps(b.name) for b in scene.bodies]
        self.frames = frames
        self.max_events = max_events
        self.events = 0            # E records seen
        self.line = 0
        self.pending: list[str] | None = None     # the event being read: its JSON text in pieces
        self.final: list[str] = []
        self.counts: dict[str, int] = {}
        self.predictions: dict[str, int] = {}

    def _flush(self) -> None:
        if self.pending is not None:
            if len(self.pending) > 1:
                self.pending.insert(1, ',"states":[')
                self.pending.append("]")
            self.pending.append("}\n")
            self.write("".join(self.pending))
            self.pending = None

    def feed(self, line: str) -> None:
        self.line += 1
        w = line.split()
        if not w:
            return
        try:
            tag = w[0]
            if tag == "S":
                if self.pending is None:
                    raise ValueError("a state without its event")
                sep = "," if len(self.pending) > 1 else ""
                self.pending.append(f'{sep}{{"body":{self.names[int(w[1])]},"position":[{_num(w[3])},{_num(w[4])}],'
                                    f'"velocity":[{_num(w[5])},{_num(w[6])}],"angle":{_num(w[7])},'
                                    f'"angular_velocity":{_num(w[8])},"acceleration":[{_num(w[9])},{_num(w[10])}]}}')
                return
            self._flush()
            if tag == "E":
                self.events += 1
                if self.max_events is not None and self.events > self.max_events:
                    raise TraceLimit(self.max_events)
                kind, t = w[1], _num(w[2])
                if kind in ("collision", "support"):
                    a, b, feat, i, j = int(w[3]), int(w[4]), int(w[5]), int(w[6]), int(w[7])
                    feature = FEATURES[(feat, (j >= 0) if feat == 0 else (i >= 0))]
                    head = (f'{{"t":{t},"kind":"{kind}","bodies":[{self.names[a]},{self.names[b]}],'
                            f'"feature":"{feature}","features":[{i},{j}],"point":[{_num(w[8])},{_num(w[9])}],'
                            f'"normal":[{_num(w[10])},{_num(w[11])}],"impulse":{_num(w[12])}')
                elif kind in ("stop", "leave"):
                    head = (f'{{"t":{t},"kind":"{kind}","bodies":[{self.names[int(w[3])]},{self.names[int(w[4])]}],'
                            f'"edge":{int(w[7])}')
                elif kind == "sleep":
                    head = (f'{{"t":{t},"kind":"sleep","bodies":[{self.names[int(w[3])]},{self.names[int(w[4])]}],'
                            f'"island":{int(w[7])}')
                elif kind == "wake":
                    head = f'{{"t":{t},"kind":"wake","bodies":[{self.names[int(w[3])]}],"island":{int(w[7])}'
                elif kind == "input":
                    head = f'{{"t":{t},"kind":"input","bodies":[{self.names[int(w[3])]}],"input":{int(w[6])}'
                elif kind == "frame":
                    if not self.frames:
                        return
                    head = f'{{"t":{t},"kind":"frame"'
                else:
                    raise ValueError(f"unknown event kind {kind!r}")
                self.pending = [head]
            elif tag == "F":
                self.final.append(f'{{"body":{self.names[int(w[1])]},"position":[{_num(w[2])},{_num(w[3])}],'
                                  f'"velocity":[{_num(w[4])},{_num(w[5])}],"angle":{_num(w[6])},'
                                  f'"angular_velocity":{_num(w[7])}}}')
            elif tag == "N":
                self.counts[w[1]] = int(w[2])
            elif tag == "V":
                eq, k, n = w[1], int(w[2]), int(w[3])
                if n:
                    self.predictions[self.build.variant_names[eq][k]] = n
            elif tag == "X":
                raise SimulateError(f"{self.scene.path}: {self.build.lang} simulator: {line.strip()[2:]}")
            else:
                raise ValueError(f"unknown line tag {tag!r}")
        except (IndexError, ValueError, KeyError) as exc:
            raise SimulateError(f"{self.build.lang} simulator wrote a bad trace line {self.line}: {line[:120]!r} "
                                f"({exc})") from None

    def finish(self) -> tuple[dict, dict]:
        """Write the last event, the final states and the statistics; return (final, stats)."""
        self._flush()
        final_text = f'{{"kind":"final","t":{repr(float(self.scene.end_time))},"bodies":[{",".join(self.final)}]}}'
        stats = {"kind": "stats", "lang": self.build.lang, "events": self.counts,
                 "predictions": dict(sorted(self.predictions.items()))}
        self.write(final_text + "\n")
        self.write(json.dumps(stats, separators=(",", ":")) + "\n")
        return json.loads(final_text), stats


class TraceLimit(Exception):
    """More events than the limit: the run is stopped."""

    def __init__(self, limit: int):
        super().__init__(limit)
        self.limit = limit


def parse_trace(text: str, scene: Scene, build: SimBuild) -> Trace:
    """A whole flat trace into a Trace (the JSON events as dicts)."""
    lines: list[str] = []
    conv = TraceConverter(scene, build, lines.append)
    for line in text.splitlines():
        conv.feed(line)
    final, stats = conv.finish()
    return Trace(build.lang, [json.loads(x) for x in lines[:-2]], final, stats, text)


def stream_scene(scene: Scene, lang: str, write, *, frames: bool = True, max_events: int | None = None,
                 progress: bool = False, timeout: float = 3600) -> tuple[dict, dict]:
    """Run the scene in `lang` and pass each JSON line of its trace to
    `write` as the simulator writes it; returns (final, stats).  More than
    `max_events` events (collisions, inputs, frames) stops the simulator
    and raises SimulateError."""
    build = build_simulator(lang, scene.effects, scene.taylor_order, progress=progress)
    flat = compile_scene(scene)
    conv = TraceConverter(scene, build, write, frames=frames, max_events=max_events)
    proc = subprocess.Popen(build.run_cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            cwd=build.workdir, text=True, encoding="ascii", errors="replace", bufsize=1 << 16)
    err: list[str] = []

    def feed_input():
        try:
            proc.stdin.write(flat)
            proc.stdin.close()
        except (BrokenPipeError, OSError):
            pass

    def drain_errors():
        err.append(proc.stderr.read()[-4000:])

    threads = [threading.Thread(target=feed_input, daemon=True), threading.Thread(target=drain_errors, daemon=True)]
    for th in threads:
        th.start()
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    last = ""
    try:
        for line in proc.stdout:
            last = line
            conv.feed(line)
    except TraceLimit as exc:
        raise SimulateError(f"{scene.path}: error: more than {exc.limit} events (collisions, inputs, frames): "
                            f"the run was stopped; raise max_events in the scene or --max-events, or shorten "
                            f"end_time") from None
    finally:
        timer.cancel()
        if proc.poll() is None:
            proc.kill()
        proc.wait()
        for th in threads:
            th.join(timeout=5)
        proc.stdout.close()
    if proc.returncode != 0:
        if last.startswith("X "):
            raise SimulateError(f"{scene.path}: {lang} simulator: {last[2:].strip()}")
        why = "timed out" if proc.returncode < 0 else f"exit {proc.returncode}"
        raise SimulateError(f"{scene.path}: {lang} simulator failed ({why}): {''.join(err)[-2000:]}")
    return conv.finish()


def run_scene(scene: Scene, lang: str, *, progress: bool = False, timeout: float = 3600) -> Trace:
    """Run the scene in `lang` and return its whole trace (events in memory:
    for tests and comparisons; `max2code simulate` streams with stream_scene)."""
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
