"""Run a scene in one runtime's simulator: generate the two contact
equations for the effects the scene uses, build that language's simulator
with them (cached under build/sim/), feed it the compiled scene and read its
flat trace back into JSON events (docs/simulator.md)."""
from __future__ import annotations

import functools
import json
import operator
import os
import re
import shutil
import subprocess
import threading
import time
from itertools import compress, repeat
from pathlib import Path

try:
    import fcntl
except ImportError:         # not on Windows
    fcntl = None

from max2code import __version__, filestate
from max2code.errors import Max2CodeError
from max2code.record import Record
from max2code.paths import BUILD, RUNTIMES, TEMPLATES, equation
from max2code.sim.scene import Scene, compile_parts, compile_scene
from max2code.sim import trace_json
from max2code.sim.scene_c import FlatScene
from max2code.targets import LANGUAGES, simulator_languages
from max2code.toolchain import toolchain

PKG = Path(__file__).resolve().parent.parent     # the max2code package
EQUATIONS = {"circle_circle": equation("circle-circle"), "point_edge": equation("point-edge")}
LANGS = simulator_languages()
FEATURES = {(0, False): "circle-circle", (0, True): "circle-vertex", (1, False): "circle-edge", (1, True): "vertex-edge"}


# the trace's N counters that count work, not handled events: stale queue
# entries dropped, pair and feature predictions; every other counter (the
# event kinds: collisions, inputs, frames, cells, horizons, supports, ...,
# and whatever kinds a runtime adds) is an event
WORK_COUNTERS = ("stale", "pairs", "features")


def handled_events(counts: dict[str, int]) -> int:
    """Events handled, from the trace's N counters read by name: all but the
    work counters, so that a new event kind counts without a change here."""
    return sum(v for k, v in counts.items() if k not in WORK_COUNTERS)


class SimulateError(Max2CodeError):
    """The simulator did not build, failed, or reported a stuck scene."""


class RunStopped(SimulateError):
    """The simulator stopped after it had started its trace (an X line, the
    event limit, a crash): the events before the stop were written.  `t` is
    the instant of the stop as the trace's text (the last event's time; None
    when no event was written), `message` the error without that instant."""

    def __init__(self, text: str, t: str | None, message: str):
        super().__init__(text)
        self.t = t
        self.message = message


def stop_line(exc: RunStopped) -> str:
    """The last line of a trace whose run stopped: `{"kind": "stopped", "t", "error"}`."""
    try:
        t = _num(exc.t)
    except ValueError:
        t = "null"          # a bad trace line's time
    return f'{{"kind":"stopped","t":{t},"error":{json.dumps(exc.message)}}}\n'


def _last_time(data: bytes) -> str | None:
    """The time of the last event line (`E KIND T ...`) of flat trace text, as written."""
    p = len(data)
    while True:
        p = data.rfind(b"E ", 0, p)
        if p < 0:
            return None
        if p == 0 or data[p - 1] == 10:
            w = data[p:data.find(b"\n", p) if data.find(b"\n", p) >= 0 else len(data)].split()
            return w[2].decode("ascii", "replace") if len(w) > 2 else None


def start_simulator(build: "SimBuild", **kw) -> subprocess.Popen:
    """The built simulator started with pipes to and from it; a program that
    cannot be run (gone, not executable: e.g. rebuilt by another run at that
    moment) is a SimulateError that names it, not an OSError that a caller
    could take for a fault of its output file."""
    try:
        return subprocess.Popen(build.run_cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                cwd=build.workdir, **kw)
    except OSError as exc:
        raise SimulateError(f"cannot start the {build.lang} simulator {build.run_cmd[0]}: "
                            f"{exc.strerror or exc}; another max2code run may be rebuilding it: run the command again") from None


class SimBuild(Record):
    _fields = ("lang", "workdir", "run_cmd", "variant_names", "generated")

    def __init__(self, lang: str, workdir: str, run_cmd: list[str], variant_names: dict[str, list[str]],
                 generated: dict[str, str] | None = None):
        self.lang, self.workdir, self.run_cmd = lang, workdir, run_cmd
        self.variant_names = variant_names      # equation -> variant names in the index order of NAME_variant
        self.generated = {} if generated is None else generated     # equation -> the generated source file


class Trace(Record):
    _fields = ("lang", "events", "final", "stats", "raw")
    _repr_fields = _fields[:-1]

    def __init__(self, lang: str, events: list[dict], final: dict, stats: dict, raw: str = ""):
        self.lang, self.events, self.final, self.stats, self.raw = lang, events, final, stats, raw

    def lines(self) -> list[str]:
        out = [json.dumps(e, separators=(",", ":")) for e in self.events]
        out.append(json.dumps(self.final, separators=(",", ":")))
        out.append(json.dumps(self.stats, separators=(",", ":")))
        return out


# C tools of the command itself, compiled on their own (max2code/sim/trace_json.py, scene_c.py): no part of
# any simulator, so an edit of them rebuilds no simulator
COMMAND_TOOLS = frozenset({"m2c_trace_json.c", "m2c_scene_flat.c"})


def _tree_files(path) -> list[str]:
    """The files under `path` a simulator depends on, in a fixed order (no
    build products, caches nor the command's own tools)."""
    out = []
    for base, dirs, files in os.walk(path):     # top-down: the folders left out of dirs are not entered
        dirs[:] = sorted(d for d in dirs if d not in ("target", "__pycache__"))
        out += [os.path.join(base, f) for f in sorted(files) if f not in COMMAND_TOOLS]
    return out


def _hash_tree(path, h) -> None:
    for p in _tree_files(path):
        h.update(p.encode())
        with open(p, "rb") as fh:
            h.update(fh.read())


# the form of build.stamp's digest (_build_simulator): part of every build's
# key, so that a folder stamped in another form is built again
STAMP_FORM = "paths-relative-to-the-folder"


def _build_key(lang: str, effects: tuple[str, ...], order: int) -> tuple[Path, str]:
    """The build's folder and the hash (hex) of everything it depends on but
    Maxima's version (its results are cached by version anyway): the hash
    remembered for the files' stat when none changed (max2code/filestate.py),
    else computed from their bytes."""
    workdir = BUILD / "sim" / lang / (("-".join(effects) or "none") + f"-o{order}")
    head = json.dumps([lang, list(effects), order, __version__, STAMP_FORM])
    trees = [_tree_files(tree) for tree in (PKG / "generate", PKG / "targets", PKG / "toolchain", TEMPLATES / lang,
                                            RUNTIMES / lang)]
    now = filestate.state([*map(str, EQUATIONS.values()), *(p for tree in trees for p in tree)], head)
    memo = workdir / "inputs.state"
    digest = filestate.recall(memo, now)
    if digest is not None:
        return workdir, digest
    import hashlib      # only here: importing it (OpenSSL) costs more than a run of a small scene
    key = hashlib.sha256(head.encode())
    for path in EQUATIONS.values():
        key.update(path.read_bytes())
    for tree in trees:
        for p in tree:
            key.update(p.encode())
            with open(p, "rb") as fh:
                key.update(fh.read())
    digest = key.hexdigest()
    if workdir.is_dir():
        filestate.remember(memo, now, digest)
    return workdir, digest


def built_simulator(lang: str, effects: tuple[str, ...], order: int) -> SimBuild | None:
    """build_simulator's result when nothing changed since it last ran (no
    generating, no building: a few milliseconds), else None."""
    workdir, key = _build_key(lang, effects, order)
    try:
        if (workdir / "inputs.stamp").read_text() == key and (workdir / "build.stamp").exists():
            saved = json.loads((workdir / "variant-names.json").read_text(encoding="utf-8"))
            # the command is made again, not read back: it names this process's interpreter
            # (sys.executable), and another environment may have built the folder
            run = toolchain(lang).sim_run(str(workdir), saved["generated"])
            if all(os.path.exists(g) for g in saved["generated"].values()) and _runnable(run):
                return SimBuild(lang, str(workdir), run, saved["names"], saved["generated"])
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return None


def _runnable(run_cmd: list[str]) -> bool:
    """The simulator's program is there (a path, or a command on PATH such as python3)."""
    return os.path.exists(run_cmd[0]) or shutil.which(run_cmd[0]) is not None


def build_simulator(lang: str, effects: tuple[str, ...], order: int, *, progress: bool = False) -> SimBuild:
    """Generate the equations for exactly these effects and build the
    simulator of `lang` with them (rebuilt only when something changed)."""
    done = built_simulator(lang, effects, order)
    if done is not None:
        return done
    workdir, _ = _build_key(lang, effects, order)
    from max2code.toolchain.tools import build_lock
    with build_lock(workdir):
        # another process may have built it while this one waited for the lock
        return built_simulator(lang, effects, order) or _build_simulator(lang, effects, order, progress)


def _build_simulator(lang: str, effects: tuple[str, ...], order: int, progress: bool) -> SimBuild:
    """build_simulator's work, under the lock of its folder."""
    workdir, key = _build_key(lang, effects, order)
    inputs_stamp, names_file, stamp = workdir / "inputs.stamp", workdir / "variant-names.json", workdir / "build.stamp"
    # the generator is imported only when something must be generated (it is most of the start-up)
    from max2code.generate.mxm import read_mxm
    from max2code.generate.pipeline import GenerateRequest, derive, generate

    extension = LANGUAGES[lang].extension
    tc = toolchain(lang)
    generated = {}
    names: dict[str, list[str]] = {}
    import hashlib
    h = hashlib.sha256()
    for eq, path in EQUATIONS.items():
        fname = eq + extension
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
    cmds = tc.sim_build(str(workdir), generated, {eq: len(n) for eq, n in names.items()})
    # new flags rebuild too; the folder's own path is left out, so a build
    # folder copied elsewhere whole keeps its stamp
    h.update(json.dumps(cmds).replace(json.dumps(str(workdir))[1:-1], "WORKDIR").encode())
    digest = h.hexdigest()
    run = tc.sim_run(str(workdir), generated)
    if not stamp.exists() or stamp.read_text() != digest or not _runnable(run):     # a deleted program too
        _run_build(lang, workdir, cmds)
        stamp.write_text(digest)
    names_file.write_text(json.dumps({"names": names, "generated": generated, "run": run}), encoding="utf-8")
    inputs_stamp.write_text(key)
    return SimBuild(lang, str(workdir), run, names, generated)


def _run_build(lang: str, workdir: Path, cmds: list[list[str]]) -> None:
    """Run a build's commands in workdir, in order; SimulateError with the failing command's output."""
    for cmd in cmds:
        proc = subprocess.run(cmd, cwd=workdir, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                              timeout=1800)
        if proc.returncode != 0:
            raise SimulateError(f"{lang} simulator did not build: {' '.join(map(str, cmd))}\n"
                                f"{proc.stdout[-3000:]}{proc.stderr[-3000:]}")


def world_library(scene: Scene, lang: str = "c", *, progress: bool = False) -> Path:
    """The shared library of `lang`'s live world API (docs/engine-api.md),
    built with the equations of the scene's effects (beside its simulator,
    built when needed): for ctypes and other programs.  SimulateError when
    `lang` makes none."""
    return effects_world_library(lang, scene.effects, scene.taylor_order, progress=progress)


def effects_world_library(lang: str, effects: tuple[str, ...], order: int, *, progress: bool = False) -> Path:
    """world_library for these effects and Taylor order: built on demand
    (the simulator's build makes only its program), once per simulator build
    (its stamp world.stamp names the build.stamp it was made from), under the
    lock of the simulator's folder."""
    name = toolchain(lang).world_library
    if name is None:
        raise SimulateError(f"the {lang} simulator has no shared library of the world API")
    build = built_simulator(lang, effects, order)
    if build is not None and _world_fresh(Path(build.workdir), name):
        return Path(build.workdir) / name
    workdir, _ = _build_key(lang, effects, order)
    from max2code.toolchain.tools import build_lock
    with build_lock(workdir):
        build = built_simulator(lang, effects, order) or _build_simulator(lang, effects, order, progress)
        if not _world_fresh(workdir, name):
            tc = toolchain(lang)
            cmds = tc.world_build(build.workdir, build.generated,
                                  {eq: len(n) for eq, n in build.variant_names.items()})
            _run_build(lang, workdir, cmds)
            (workdir / "world.stamp").write_text((workdir / "build.stamp").read_text())
    return workdir / name


def _world_fresh(workdir: Path, name: str) -> bool:
    """The world library in workdir was made from the simulator build there now."""
    try:
        return ((workdir / name).exists()
                and (workdir / "world.stamp").read_text() == (workdir / "build.stamp").read_text())
    except OSError:
        return False


def _num(w: str) -> str:
    """A trace number as JSON: the runtime's `%.17g` text, which reads back as
    the same double (a whole number gets '.0' so that it stays a float);
    never NaN or infinite.  (Re-printing each number in its shortest form
    would cost more than the simulation.)"""
    if "." in w or "e" in w:
        if "n" in w or "N" in w:
            raise ValueError(f"non-finite number {w}")
        return w
    if not w.lstrip("-").isdigit():
        raise ValueError(f"not a finite number: {w}")
    return w + ".0"


def _state(body, px, py, vx, vy, angle, omega, ax, ay) -> str:
    """A state's JSON from the trace's fields (an f-string: faster than % formatting)."""
    return (f'{{"body":{body},"position":[{px},{py}],"velocity":[{vx},{vy}],"angle":{angle},'
            f'"angular_velocity":{omega},"acceleration":[{ax},{ay}]}}')


_ZERO = {"0": "0.0", "-0": "-0.0"}     # the commonest whole numbers of a trace
# a contact's feature from (FEATURE, I < 0, J < 0) (docs/simulator.md)
_FEATURE_OF = {("0", i, j): FEATURES[(0, not j)] for i in (False, True) for j in (False, True)}
_FEATURE_OF.update({("1", i, j): FEATURES[(1, not i)] for i in (False, True) for j in (False, True)})
_first = operator.itemgetter(0)
_vertices = operator.attrgetter("vertices")
_S_END = ("]}\n", ",")                # after a state: the next line is not, or is, a state
_E_END = ("}\n", ',"states":[')       # after an event's head: likewise


def _columns(lines: list[str], width: int, tag: str, numbers) -> list[list[str]]:
    """The fields of many lines of `width` single-space-separated fields
    starting with `tag`, one list per field; the fields `numbers` as JSON
    numbers: a column in which every field holds a '.' (the count of '.'
    tells) passes through; in any other, "0" and "-0" get '.0' and what is
    still without a '.' goes through `_num` (an exponent, another whole
    number; NaN and infinities are refused).  Anything else raises _Slow
    (the precise path)."""
    m = len(lines)
    if not m:
        return []
    toks = " ".join(lines).split(" ")
    if len(toks) != width * m:
        raise _Slow                 # other blank space or another number of fields
    cols = [toks[c::width] for c in range(width)]
    if cols[0].count(tag) != m:
        raise _Slow
    for c in numbers:
        col = cols[c]
        if "".join(col).count(".") != m:
            col = list(map(_ZERO.get, col, col))
            if "".join(col).count(".") != m:
                col = [v if "." in v else _num(v) for v in col]
            cols[c] = col
    return cols
def _final(body, px, py, vx, vy, angle, omega) -> str:
    return (f'{{"body":{body},"position":[{px},{py}],"velocity":[{vx},{vy}],"angle":{angle},'
            f'"angular_velocity":{omega}}}')


def _features(feature, i, j) -> str:
    return f'"feature":"{feature}","features":[{i},{j}]'


def _contact(t, kind, a, b, features, cx, cy, nx, ny, impulse) -> str:
    """A collision's or support's JSON, without its states and closing brace
    (`features`: the text of _features)."""
    return (f'{{"t":{t},"kind":"{kind}","bodies":[{a},{b}],{features},'
            f'"point":[{cx},{cy}],"normal":[{nx},{ny}],"impulse":{impulse}')


class _FeatureText(dict):
    """_features by the trace's FEATURE, I and J fields as text, made on first
    use; KeyError for a FEATURE other than 0 or 1, or an I or J that is not
    a whole number from -1 to the most vertices or bodies (the precise path
    then reads the line)."""

    def __init__(self, ints: dict[str, str]):
        super().__init__()
        self.ints = ints

    def __missing__(self, key: tuple[str, str, str]) -> str:
        feat, i, j = key
        i, j = self.ints[i], self.ints[j]
        text = self[key] = _features(_FEATURE_OF[(feat, i[0] == "-", j[0] == "-")], i, j)
        return text


def _support_end(t, kind, a, b, edge) -> str:
    return f'{{"t":{t},"kind":"{kind}","bodies":[{a},{b}],"edge":{edge}'


def _json_names(names: list[str]) -> list[str]:
    """json.dumps of each name: names of printable ASCII without '"' or '\\'
    (all of them, as a rule) are only quoted (json.dumps escapes nothing else:
    control characters, DEL and non-ASCII), without a call per name."""
    joined = "".join(names)
    if joined.isascii() and joined.isprintable() and '"' not in joined and "\\" not in joined:
        return [f'"{n}"' for n in names]
    return list(map(json.dumps, names))


def trace_names(scene) -> tuple[list[str], int]:
    """The bodies' names as JSON text, in index order, and the largest index
    a trace line may name (a body, an input, a vertex): from a Scene, or as
    given by a scene the C reader compiled (max2code/sim/scene_c.py)."""
    given = getattr(scene, "json_names", None)
    if given is not None:
        return given, scene.most
    most = max(len(scene.bodies), len(scene.inputs), max(map(len, map(_vertices, scene.bodies)), default=0))
    return _json_names([b.name for b in scene.bodies]), most


class _Slow(Exception):
    """The fast path met something it does not check itself: the chunk is
    done again line by line, which gives the precise error (or the same
    output: the two paths write the same bytes)."""


class TraceConverter:
    """Turns the runtime's flat trace (docs/simulator.md) into the JSON lines
    of `max2code simulate`: each event is written when the next record
    starts, so memory does not grow with the number of events (the final
    states and statistics are per body and per variant).

    Two paths write the same bytes: `feed(line)` checks and converts one
    line; `feed_chunk(text)` converts many complete lines at once (the whole
    numbers of the chunk get their '.0' in one regular-expression pass, the
    records are formatted from their tokens, nothing is written until the
    chunk is done) and, on anything unusual (a stop line, a non-finite or
    malformed number, the event limit), does the chunk again with `feed`."""

    def __init__(self, scene: Scene | FlatScene, build: SimBuild, write, *, frames: bool = True,
                 max_events: int | None = None, accelerate: bool = False, write_bytes=None):
        self.scene, self.build, self.write = scene, build, write
        self.write_bytes = write_bytes      # the C converter's output as it is (ASCII), to write's stream, in order
        self.names, self.most = trace_names(scene)
        self.frames = frames
        self.max_events = max_events
        self.events = 0            # E records seen
        self.line = 0
        self.head: str | None = None    # the event being read: its JSON text without states
        self.states: list[str] = []     # and its states
        self.final: list[str] = []
        self._final_started = False     # the final line's start and some bodies written (by _finals)
        self.counts: dict[str, int] = {}
        self.predictions: dict[str, int] = {}
        self._c = None           # the C converter of feed_events (max2code/sim/trace_json.py)
        if accelerate:
            lib = trace_json.library()
            if lib is not None:
                self._c = trace_json.CTrace(lib, self.names, self.most, getattr(scene, "names_text", None))

    # the Python paths' integer fields by their text, made on their first use (for 10^5 bodies they take
    # 0.15 s, which the C converter never needs)
    @functools.cached_property
    def _body(self) -> dict[str, str]:
        return dict(zip(map(str, range(len(self.names))), self.names))

    @functools.cached_property
    def _int(self) -> dict[str, str]:
        ints = list(map(str, range(-1, self.most + 1)))
        return dict(zip(ints, ints))

    @functools.cached_property
    def _features(self) -> _FeatureText:
        return _FeatureText(self._int)

    def _event(self) -> str:
        if self.states:
            return f'{self.head},"states":[{",".join(self.states)}]}}\n'
        return self.head + "}\n"

    def _flush(self) -> None:
        if self.head is not None:
            self.write(self._event())
            self.head = None
            self.states = []

    def _name(self, index) -> str:
        """The JSON name of body `index` (a token or an int); a negative or
        too large index is a ValueError (a bad trace line), never a name
        read from the end of the list."""
        i = int(index)
        if i < 0:
            raise ValueError(f"body index {i} is negative")
        return self.names[i]

    def feed(self, line: str) -> None:
        """One line of the flat trace, checked."""
        self.line += 1
        w = line.split()
        if not w:
            return
        try:
            tag = w[0]
            if tag == "S":
                if self.head is None:
                    raise ValueError("a state without its event")
                self.states.append(_state(self._name(w[1]), _num(w[3]), _num(w[4]), _num(w[5]),
                                             _num(w[6]), _num(w[7]), _num(w[8]), _num(w[9]), _num(w[10])))
                return
            self._flush()
            if tag == "E":
                self.events += 1
                if self.max_events is not None and self.events > self.max_events:
                    raise TraceLimit(self.max_events, w[2])
                kind, t = w[1], _num(w[2])
                if kind in ("collision", "support"):
                    a, b, feat, i, j = int(w[3]), int(w[4]), int(w[5]), int(w[6]), int(w[7])
                    feature = FEATURES[(feat, (j >= 0) if feat == 0 else (i >= 0))]
                    head = _contact(t, kind, self._name(a), self._name(b), _features(feature, i, j), _num(w[8]),
                                    _num(w[9]), _num(w[10]), _num(w[11]), _num(w[12]))
                elif kind in ("stop", "leave"):
                    head = _support_end(t, kind, self._name(w[3]), self._name(w[4]), int(w[7]))
                elif kind == "sleep":
                    head = (f'{{"t":{t},"kind":"sleep","bodies":[{self._name(w[3])},{self._name(w[4])}],'
                            f'"island":{int(w[7])}')
                elif kind == "wake":
                    head = f'{{"t":{t},"kind":"wake","bodies":[{self._name(w[3])}],"island":{int(w[7])}'
                elif kind == "input":
                    head = f'{{"t":{t},"kind":"input","bodies":[{self._name(w[3])}],"input":{int(w[6])}'
                elif kind == "frame":
                    if not self.frames:
                        return
                    head = f'{{"t":{t},"kind":"frame"'
                else:
                    raise ValueError(f"unknown event kind {kind!r}")
                self.head = head
            elif tag == "F":
                self.final.append(_final(self._name(w[1]), _num(w[2]), _num(w[3]), _num(w[4]),
                                            _num(w[5]), _num(w[6]), _num(w[7])))
            elif tag == "N":
                self.counts[w[1]] = int(w[2])
            elif tag == "V":
                eq, k, n = w[1], int(w[2]), int(w[3])
                if k < 0:
                    raise ValueError(f"variant index {k} is negative")
                if n:
                    self.predictions[self.build.variant_names[eq][k]] = n
            elif tag == "X":
                raise SimulateError(f"{self.scene.path}: error: {self.build.lang} simulator: {line.strip()[2:]}")
            else:
                raise ValueError(f"unknown line tag {tag!r}")
        except (IndexError, ValueError, KeyError) as exc:
            raise SimulateError(f"{self.build.lang} simulator wrote a bad trace line {self.line}: {line[:120]!r} "
                                f"({exc})") from None

    def feed_events(self, data: bytes, size: int | None = None) -> None:
        """Whole events of the flat trace: `data` (its first `size` bytes,
        when given: the C converter takes them without a copy) ends with a
        newline where a line other than a state begins, or at the trace's
        end.  Converted in C when the converter was made with `accelerate`
        and the C code takes the chunk; else as feed_chunk.  The same bytes
        either way.  The final states (F lines, one per body, after the last
        event: as many lines as bodies) go to _finals."""
        n = len(data) if size is None else size
        last = data.rfind(b"\n", 0, n - 1) + 1          # the chunk's last line
        at = -1             # where its F lines begin: they come after every event, so not before an E or S line
        if n and data[last:min(last + 1, n)] not in (b"E", b"S", b""):
            at = 0 if data.startswith(b"F ", 0, n) else data.find(b"\nF ", 0, n) + 1 or -1
        if at >= 0 or (n < len(data) and self._c is None):
            data = data[:n]         # the Python paths: the chunk on its own
        if at >= 0:
            if at:
                self.feed_events(data[:at])
            end = data.find(b"\n", data.rfind(b"\nF ") + 1 if data.rfind(b"\nF ") >= at else at) + 1
            block = data[at:end] if end else data[at:]
            # F lines only (the C code checks that itself, line by line, and says no otherwise)
            if end and (self._c is not None or block.count(b"\n") == block.count(b"\nF ") + 1):
                self._finals(block)
            else:
                self.feed_chunk(block.decode("ascii", "replace"))
            if end and end < len(data):
                self.feed_chunk(data[end:].decode("ascii", "replace"))
            return
        if self._c is not None and n:
            got = self._c.convert(data, self.frames, n)
            if got is not None and (self.max_events is None or self.events + got[1] <= self.max_events):
                self._flush()           # the event an earlier chunk ended with is whole: this one starts anew
                self.events += got[1]
                self.line += got[2]
                if self.write_bytes is not None:
                    self.write_bytes(got[0])        # written from the converter's buffer
                else:
                    self.write(str(got[0], "ascii"))
                return
        self.feed_chunk(data[:n].decode("ascii", "replace"))

    def _finals(self, block: bytes) -> None:
        """Complete F lines: in C when the converter was made with
        `accelerate` and takes them; else column by column (as _states);
        anything unusual goes to feed_chunk."""
        if self._c is not None:
            got = self._c.finals(block)
            if got is not None:
                self._flush()           # the last event is whole
                self.line += block.count(b"\n")
                if self.write_bytes is not None and not self.final:
                    # streamed as they come (15 MB at 10^5 bodies: kept for the end, they would be decoded,
                    # joined and encoded after the run, in series with nothing)
                    self.write_bytes(b"," if self._final_started else self._final_head().encode("ascii"))
                    self.write_bytes(got)
                    self._final_started = True
                else:
                    self.final.append(got.decode("ascii"))  # the bodies' JSON, comma-separated
                return
        text = block.decode("ascii", "replace")
        lines = text.split("\n")
        lines.pop()                     # after the last newline
        try:
            cols = _columns(lines, 8, "F", range(2, 8))
            final = list(map(_final, map(self._body.__getitem__, cols[1]), *cols[2:]))
        except (_Slow, IndexError, ValueError, KeyError):
            self.feed_chunk(text)
            return
        self._flush()                   # the last event is whole
        self.final += final
        self.line += len(lines)

    def feed_chunk(self, text: str) -> None:
        """Complete lines of the flat trace (text ends with a newline, or is empty)."""
        if not text:
            return
        try:
            out = self._fast(text)
        except (_Slow, IndexError, ValueError, KeyError):
            self._slow(text)
            return
        if out:
            self.write("".join(out))

    def _slow(self, text: str) -> None:
        for line in text.splitlines():
            self.feed(line)

    def _fast(self, text: str) -> list[str]:
        """The chunk's output; the converter's state changes only when all of
        it converted.  No Python code runs per S line (most of a trace) nor
        per collision: the lines are sorted into S lines and the others by
        one flag per line, each kind is formatted column by column
        (`_states`, `_contacts`), each piece gets the text that closes it
        from whether the next line is a state (`_S_END`, `_E_END`), and the
        pieces are put back in line order by those flags.  The last event
        of the chunk may get more states in the next one: it is kept
        (self.head, self.states) as `feed` keeps it."""
        lines = text.split("\n")
        lines.pop()                     # after the last newline
        m = len(lines)
        is_s = list(map("S".__eq__, map(_first, lines)))     # IndexError on a blank line: the precise path
        is_o = list(map(operator.not_, is_s))
        nxt = is_s[1:]
        nxt.append(False)
        others = list(compress(lines, is_o))
        contact = list(map(str.startswith, others, repeat(("E collision ", "E support "))))
        final, counts, predictions = [], {}, {}
        if all(contact):
            heads: list = self._contacts(others)
            n_events = len(others)
            e_pieces = list(map(operator.add, heads, map(_E_END.__getitem__, compress(nxt, is_o))))
        else:
            heads, n_events = self._others(others, contact, final, counts, predictions)
            e_pieces = []
            for h, n in zip(heads, compress(nxt, is_o)):
                if h is None:
                    if n:
                        raise _Slow     # a state after a line that is no event (or a frame left out)
                    e_pieces.append("")
                else:
                    e_pieces.append(h + _E_END[n])
        if self.max_events is not None and self.events + n_events > self.max_events:
            raise _Slow                 # the precise path stops at the event over the limit
        if is_s[0] and self.head is None:
            raise _Slow                 # a state without its event
        states = self._states(list(compress(lines, is_s)))
        if not others:                  # only states, all of the event carried over
            self.states = self.states + states
            self.line += m
            return []
        if is_s[0]:
            prefix = self.head + ',"states":[' + "".join(s + "," for s in self.states)
        else:
            prefix = self._event() if self.head is not None else ""
        s_pieces = list(map(operator.add, states, map(_S_END.__getitem__, compress(nxt, is_s))))
        last = m - 1 - is_s[::-1].index(False)      # the last line that is not a state: its event is kept
        pieces = (iter(e_pieces), iter(s_pieces))
        body = "".join(map(next, map(pieces.__getitem__, is_s[:last])))
        tail = m - 1 - last             # states of the kept event
        self.head, self.states = heads[-1], (states[len(states) - tail:] if tail else [])
        self.events += n_events
        self.line += m
        self.final += final
        self.counts.update(counts)
        self.predictions.update(predictions)
        return [prefix, body]

    def _others(self, others: list[str], contact: list[bool], final: list[str], counts: dict[str, int],
                predictions: dict[str, int]) -> tuple[list, int]:
        """The heads of the lines that are not states (None for a line that
        is no event, or a frame left out) and the number of events among
        them; F, N and V lines go to final, counts and predictions."""
        frames = self.frames
        body = ints = None              # the tables, made when a line needs them (the N and V lines do not)
        contacts = iter(self._contacts(list(compress(others, contact))))
        heads: list[str | None] = []
        f_lines: list[str] = []
        n_events = 0
        for line, c in zip(others, contact):
            if c:
                heads.append(next(contacts))
                n_events += 1
                continue
            tag = line[:1]
            if tag == "F":
                f_lines.append(line)    # formatted together below
                heads.append(None)
                continue
            w = line.split()
            head = None
            if tag == "E":
                n_events += 1
                if body is None:
                    body, ints = self._body, self._int
                kind = w[1]
                t = w[2] if "." in w[2] else _num(w[2])
                if kind == "frame":
                    if frames:
                        head = f'{{"t":{t},"kind":"frame"'
                elif kind == "stop" or kind == "leave":
                    head = _support_end(t, kind, body[w[3]], body[w[4]], ints[w[7]])
                elif kind == "input":
                    head = f'{{"t":{t},"kind":"input","bodies":[{body[w[3]]}],"input":{ints[w[6]]}'
                else:
                    raise _Slow
            elif tag == "N" and len(w) == 3:
                counts[w[1]] = int(w[2])
            elif tag == "V" and len(w) == 4:
                served = int(w[3])
                if served:
                    k = int(w[2])
                    if k < 0:
                        raise _Slow     # the precise path says why
                    predictions[self.build.variant_names[w[1]][k]] = served
            else:
                raise _Slow             # blank, unknown or malformed lines: the precise path
            heads.append(head)
        cols = _columns(f_lines, 8, "F", range(2, 8))
        if cols:
            final += map(_final, map(self._body.__getitem__, cols[1]), *cols[2:])
        return heads, n_events

    def _states(self, s_lines: list[str]) -> list[str]:
        """The JSON of many S lines at once, column by column (no Python
        call per line): the tokens of all lines, one column per field; a
        number column in which every field holds a '.' (the count of '.'
        tells) passes through; in any other, "0" and "-0" get '.0' and
        what is still without a '.' goes through `_num` (an exponent, any
        other whole number; NaN and infinities are refused)."""
        cols = _columns(s_lines, 11, "S", range(3, 11))
        if not cols:
            return []
        names = map(self._body.__getitem__, cols[1])
        return list(map(_state, names, *cols[3:]))

    def _contacts(self, c_lines: list[str]) -> list[str]:
        """The JSON heads of many collision and support lines at once, as `_states`."""
        cols = _columns(c_lines, 13, "E", (2, 8, 9, 10, 11, 12))
        if not cols:
            return []
        names = self._body.__getitem__
        features = map(self._features.__getitem__, zip(cols[5], cols[6], cols[7]))
        return list(map(_contact, cols[2], cols[1], map(names, cols[3]), map(names, cols[4]), features, *cols[8:]))

    def finish(self) -> tuple[dict, dict]:
        """Write the last event, the final states and the statistics; return (final, stats)."""
        if self._final_started:
            raise ValueError("the final states were written as they came (write_bytes): call _finish")
        stats = self._finish()
        return json.loads(f'{self._final_head()}{",".join(self.final)}]}}'), stats

    def _final_head(self) -> str:
        return f'{{"kind":"final","t":{repr(float(self.scene.end_time))},"bodies":['

    def _finish(self) -> dict:
        """As finish, returning the statistics only: the final states are
        written a block at a time (one line of 15 MB at 10^5 bodies, which
        made whole, with a newline, and encoded would be four copies of it)."""
        self._flush()
        if not self._final_started:
            self.write(self._final_head())
        for k in range(0, len(self.final), 1024):
            self.write(("," if k or self._final_started else "") + ",".join(self.final[k:k + 1024]))
        self.write("]}\n")
        stats = {"kind": "stats", "lang": self.build.lang, "events": self.counts,
                 "predictions": dict(sorted(self.predictions.items()))}
        self.write(json.dumps(stats, separators=(",", ":")) + "\n")
        return stats


class TraceLimit(Exception):
    """More events than the limit: the run is stopped."""

    def __init__(self, limit: int, t: str):
        super().__init__(limit)
        self.limit = limit
        self.t = t          # the time of the event past the limit, as the trace wrote it


def parse_trace(text: str, scene: Scene, build: SimBuild) -> Trace:
    """A whole flat trace into a Trace (the JSON events as dicts)."""
    parts: list[str] = []
    conv = TraceConverter(scene, build, parts.append)
    conv.feed_chunk(text if not text or text.endswith("\n") else text + "\n")
    final, stats = conv.finish()
    lines = "".join(parts).splitlines()
    return Trace(build.lang, [json.loads(x) for x in lines[:-2]], final, stats, text)


CHUNK = 1 << 16      # bytes of trace converted at a time (a pipe's worth; 1 MB chunks measured slower)


def _events_end(data: bytes) -> int:
    """The length of the longest start of `data` that is whole events of the
    flat trace: it ends with a newline followed by the first byte of a line
    other than a state (0: none yet)."""
    p = data.rfind(b"\n")
    while p >= 0:
        if p + 1 < len(data) and data[p + 1] != 83:      # 83: "S"
            return p + 1
        p = data.rfind(b"\n", 0, p)
    return 0


CONVERTERS = ("auto", "c", "python")


PIPE_BYTES = 1 << 20    # the pipes to and from the simulator (Linux's most for an unprivileged process)


def _wide_pipes(proc: subprocess.Popen) -> None:
    """Widen the pipes to and from the simulator (Linux; 64 kB by default)
    so that neither side waits on the other at every 64 kB: the simulator
    writes its trace ahead while a chunk is converted, and reads the scene
    ahead while the next piece is made.  Where it cannot be done, nothing
    changes but the speed."""
    op = getattr(fcntl, "F_SETPIPE_SZ", None) if fcntl is not None else None
    if op is None:
        return
    for f in (proc.stdin, proc.stdout):
        try:
            fcntl.fcntl(f.fileno(), op, PIPE_BYTES)
        except OSError:
            pass        # over the system's limit (/proc/sys/fs/pipe-max-size) or not a pipe


def _close_quietly(f) -> None:
    """Close a pipe whose reader may be gone (what was still buffered is dropped)."""
    try:
        f.close()
    except OSError:
        pass


def stream_scene(scene: Scene | FlatScene, lang: str, write, *, frames: bool = True, max_events: int | None = None,
                 progress: bool = False, timeout: float = 3600, converter: str = "auto", warn=None,
                 check=None, write_bytes=None) -> dict:
    """Run the scene in `lang` and pass each JSON line of its trace to
    `write` as the simulator writes it; returns the statistics.  More than
    `max_events` events (collisions, inputs, frames) stops the simulator
    and raises SimulateError.  `converter`: "c" converts the trace in C
    (SimulateError when that converter cannot be built), "python" in
    Python, "auto" in C when it can be built, else in Python after passing
    one line saying so to `warn` (the same bytes either way).

    The flat scene goes to the simulator as it is compiled (the simulator
    reads one piece while the next is made).  `check`, when given, is
    called after that and before anything is written: the checks of the
    scene left for last (scene.check_scene of a scene read with
    check=False), which so run while the simulator starts; an exception
    from it stops the simulator and is raised as it is (and first, when
    compiling fails or a real build must run).  `write_bytes`, when given,
    writes ASCII bytes to the same stream as `write`, in order with it: the C
    converter's output then goes there without a decoding and an encoding
    (a bytes-like view of the converter's buffer, which it must write or copy
    before it returns, as a file's write does)."""
    if converter not in CONVERTERS:
        raise ValueError(f"converter {converter!r}")
    build = built_simulator(lang, scene.effects, scene.taylor_order)
    if build is None:
        if check is not None:   # generating and building take long: refuse a bad scene first
            check()
            check = None
        build = build_simulator(lang, scene.effects, scene.taylor_order, progress=progress)
    proc = start_simulator(build)
    _wide_pipes(proc)
    err: list[bytes] = []

    def drain_errors():
        err.append(proc.stderr.read()[-4000:])

    threads = [threading.Thread(target=drain_errors, daemon=True)]
    for th in threads:
        th.start()
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    try:
        # the simulators read the whole scene before they write: writing it from here cannot wait on their output
        try:
            if isinstance(scene, FlatScene):
                for part in scene.parts():
                    proc.stdin.write(part)
                scene.release()
            else:
                for part in compile_parts(scene):
                    proc.stdin.write(part.encode("ascii"))
            proc.stdin.close()
        except (BrokenPipeError, OSError):
            _close_quietly(proc.stdin)      # the simulator stopped reading: its exit status and last line say why
        except BaseException:
            if check is not None:
                check()         # a fault of the scene comes first
            raise
        if check is not None:
            check()
        # made while the simulator runs: for 10^5 bodies its tables of names take a while
        conv = TraceConverter(scene, build, write, frames=frames, max_events=max_events, write_bytes=write_bytes,
                              accelerate=converter != "python")
        if converter != "python" and conv._c is None:
            why = f"the C trace converter cannot be built ({trace_json.why_not()})"
            if converter == "c":
                raise SimulateError(f"max2code simulate: error: --converter c: {why}")
            if warn is not None:
                warn(f"max2code simulate: note: {why}; converting the trace in Python (the same bytes, slower)")
    except BaseException:
        timer.cancel()
        proc.kill()
        _close_quietly(proc.stdin)
        proc.wait()
        for th in threads:
            th.join(timeout=5)
        proc.stdout.close()
        raise
    last, rest, fed, cut = "", b"", b"", 0
    stopped: BaseException | None = None
    try:
        try:
            # chunks of whole events: the converters' fast paths
            while True:
                data = proc.stdout.read1(CHUNK)
                if not data:
                    break
                data = rest + data
                k = _events_end(data)
                if k:
                    fed, cut = data, k
                    conv.feed_events(data, k)       # its first k bytes
                rest = data[k:]
            if rest:
                last = rest.decode("ascii", "replace").rstrip("\n").rpartition("\n")[2]
                conv.feed_events(rest if rest.endswith(b"\n") else rest + b"\n")
            elif fed:                       # the trace's last line (an X line tells why the simulator stopped)
                last = fed[fed.rfind(b"\n", 0, cut - 1) + 1:cut].decode("ascii", "replace")
        except (TraceLimit, SimulateError) as exc:
            stopped = exc        # an X line, the event limit, a bad line: the events before it are written
    finally:
        timer.cancel()
        if proc.poll() is None:
            proc.kill()
        proc.wait()
        for th in threads:
            th.join(timeout=5)
        proc.stdout.close()
    if stopped is None and proc.returncode == 0:
        return conv._finish()
    # the run stopped: the trace written so far is kept (the event being converted included), and the
    # error names the instant of the stop (the last event's time)
    conv._flush()
    t = _last_time(rest) or _last_time(fed[:cut])
    if isinstance(stopped, TraceLimit):
        t = stopped.t
        message = (f"more than {stopped.limit} events (collisions, inputs, frames) at t = {t}: the run was "
                   f"stopped; raise max_events in the scene or --max-events, or shorten end_time")
        raise RunStopped(f"{scene.path}: error: {message}", t, message)
    if last.startswith("X "):
        message = f"{lang} simulator: {last[2:].strip()}"
    elif stopped is not None:
        message = str(stopped)
        if message.startswith(f"{scene.path}: "):
            message = message[len(scene.path) + 2:]
        message = message.removeprefix("error: ")
    else:
        why = "timed out" if proc.returncode < 0 else f"exit {proc.returncode}"
        message = f"{lang} simulator failed ({why}): {b''.join(err)[-2000:].decode('ascii', 'replace')}"
    named = re.search(r" at t = ([-+.0-9eE]+)", message)
    if named:
        t = named.group(1)          # the simulator named the instant (its event past a limit, a stuck instant)
    elif t is not None:
        message += f" (stopped at t = {t})"
    raise RunStopped(f"{scene.path}: error: {message}", t, message)


def run_scene(scene: Scene, lang: str, *, progress: bool = False, timeout: float = 3600) -> Trace:
    """Run the scene in `lang` and return its whole trace (events in memory:
    for tests and comparisons; `max2code simulate` streams with stream_scene)."""
    build = build_simulator(lang, scene.effects, scene.taylor_order, progress=progress)
    flat = compile_scene(scene)
    proc = start_simulator(build, text=True)
    try:
        out, errs = proc.communicate(flat, timeout=timeout)
    except BaseException:           # timed out, or interrupted (cli.Interrupted): the simulator stops too
        proc.kill()
        proc.communicate()
        raise
    proc = subprocess.CompletedProcess(build.run_cmd, proc.returncode, out, errs)
    if proc.returncode != 0:
        last = proc.stdout.rstrip().splitlines()[-1] if proc.stdout.strip() else ""
        if last.startswith("X "):
            raise SimulateError(f"{scene.path}: error: {lang} simulator: {last[2:]}")
        raise SimulateError(f"{scene.path}: error: {lang} simulator failed (exit {proc.returncode}): {proc.stderr[-2000:]}")
    return parse_trace(proc.stdout, scene, build)


def time_engine(build: SimBuild, flat: str, timeout: float = 3600) -> tuple[float, float, dict[str, int]]:
    """Run the simulator alone on a flat scene: (wall seconds, CPU seconds
    (user + system) of its process, its N counters by name).  The trace is
    drained as it comes and only its tail kept (the N lines are near the end)."""
    t0 = time.perf_counter()
    proc = start_simulator(build)
    err: list[bytes] = []

    def feed_input():
        try:
            proc.stdin.write(flat.encode("ascii"))
            proc.stdin.close()
        except (BrokenPipeError, OSError):
            pass

    threads = [threading.Thread(target=feed_input, daemon=True),
               threading.Thread(target=lambda: err.append(proc.stderr.read()[-4000:]), daemon=True)]
    for th in threads:
        th.start()
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    tail = b""
    try:
        while True:
            chunk = proc.stdout.read(1 << 20)
            if not chunk:
                break
            tail = (tail + chunk)[-65536:]
    finally:
        timer.cancel()
        _, code, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(code)
        for th in threads:
            th.join(timeout=5)
        proc.stdout.close()
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SimulateError(f"{build.lang} simulator failed (exit {proc.returncode}): "
                            f"{tail[-300:].decode('ascii', 'replace')} {b''.join(err)[-300:].decode('ascii', 'replace')}")
    counts: dict[str, int] = {}
    for line in tail.decode("ascii", "replace").splitlines():
        w = line.split()
        if len(w) == 3 and w[0] == "N":
            counts[w[1]] = int(w[2])
    return wall, usage.ru_utime + usage.ru_stime, counts
