"""Fuzzing the four simulators (C, Rust, Python, Modula-2) with hostile
flat scenes and random live-API sessions (docs/simulator.md, "Flat scene
checks").

Scenes: small valid flat scenes (max2code/sim/scene.py compiles them) with
one to three mutations: bytes flipped or inserted, two tokens swapped, a
number replaced by an extreme (nan, inf, 1e308, -0, 5e-324, hexadecimal, a
huge count, ...), the text cut, a line doubled or dropped.  Each goes to
every runtime's batch simulator.

Live sessions: a small valid scene whose inputs are made live by the
simulators' `--step DT --live` mode (docs/engine-api.md, "Checking a
port"): random set_velocity, add_velocity, apply_impulse, teleport and
remove calls, on real bodies and on indices that are no body, with extreme
vectors, between advances of random steps, each followed by every body's
state, then finish.

Every run must end with exit status 0 or 1 (no signal, no crash), within
the per-run time and address-space limits, and every runtime must answer
the same: the same `X` line on a refusal, the same trace bytes (and, for a
live session, the same state lines) on acceptance.  An output longer than
OUTPUT_CAP bytes is cut there in every runtime and its first OUTPUT_CAP
bytes compared.

    python3 bench/fuzz.py --count 20000 --live 2000 --seed 1
    python3 bench/fuzz.py --count 500 --live 0 --valgrind --langs c

prints the inputs tried, refusals, acceptances, disagreements, crashes,
timeouts, outputs with a number that is not finite (NaN or infinity in a
trace or a state line) and the peak memory of one run; with --valgrind the C simulator
runs under valgrind (memcheck, full leak check) and its errors and leaks
are counted too.  Exit status 1 when anything failed.
"""
from __future__ import annotations

import argparse
import io
import json
import os
import random
import resource
import select
import shutil
import signal
import subprocess
import sys
import time
import traceback
from pathlib import Path

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
for _p in (ROOT, ROOT / "runtimes" / "python"):
    if str(_p) not in sys.path:
        sys.path.insert(0, str(_p))

from max2code.sim.scene import compile_scene, parse_scene  # noqa: E402
from max2code.sim.simulate import LANGS, build_simulator  # noqa: E402

OUTPUT_CAP = 1 << 18          # bytes of stdout (and of stderr's state lines) read from one run
STEADY = 1 << 16              # bytes written by a run that ran out of time while still writing: cut, not stuck
TIMEOUT = 20.0                # s of wall time for one run
MEMORY = 2 << 30              # bytes of address space for one run (RLIMIT_AS)
TIME = "/usr/bin/time" if os.access("/usr/bin/time", os.X_OK) else None
PRLIMIT = shutil.which("prlimit")       # util-linux: sets a program's limits, then runs it
NONFINITE = {b"nan", b"-nan", b"inf", b"-inf", b"infinity", b"-infinity", b"+inf"}
VALGRIND_ERROR = 99           # valgrind's exit status on a memory error or a leak

# ------------------------------------------------------------------ base scenes
BOX = [{"name": n, "shape": "polygon", "fixed": True, "position": p, "restitution": 0.9, "vertices": v}
       for n, p, v in (("floor", [1.0, -0.1], [[-1.2, -0.1], [1.2, -0.1], [1.2, 0.1], [-1.2, 0.1]]),
                       ("left", [-0.1, 1.0], [[-0.1, -1.0], [0.1, -1.0], [0.1, 1.0], [-0.1, 1.0]]),
                       ("right", [2.1, 1.0], [[-0.1, -1.0], [0.1, -1.0], [0.1, 1.0], [-0.1, 1.0]]))]

BASES = {
    "ledge": {"end_time": 2.0, "gravity": [0, -9.81], "bodies": [
        {"name": "floor", "shape": "polygon", "fixed": True, "position": [0, -1],
         "vertices": [[-3, -0.5], [3, -0.5], [3, 0.5], [-3, 0.5]]},
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.0, 0.0], "velocity": [0.5, 0]},
        {"name": "box", "shape": "polygon", "mass": 2.0, "position": [1, 0],
         "vertices": [[-0.2, -0.2], [0.2, -0.2], [0.2, 0.2], [-0.2, 0.2]]}],
        "inputs": [{"time": 0.5, "body": "ball", "set_velocity": [1.0, 0.0]}]},
    "box": {"end_time": 1.5, "frame_rate": 4, "gravity": [0.0, -9.81], "bodies": BOX + [
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [0.5, 0.5],
         "velocity": [1.0, 0.0], "restitution": 0.9},
        {"name": "crate", "shape": "polygon", "mass": 2.0, "position": [1.4, 0.3], "friction": 0.3,
         "vertices": [[-0.15, -0.1], [0.15, -0.1], [0.15, 0.1], [-0.15, 0.1]], "angle": 0.2},
        {"name": "pebble", "shape": "circle", "radius": 0.05, "mass": 0.2, "position": [1.0, 1.5],
         "velocity": [-0.5, 0.3]}],
        "inputs": [{"time": 0.0, "body": "ball", "impulse": [0.0, 3.0]},
                   {"time": 0.5, "body": "pebble", "teleport": [1.7, 1.7]},
                   {"time": 0.8, "body": "ball", "add_velocity": [0.5, 1.5]},
                   {"time": 1.0, "body": "pebble", "remove": True}]},
    "wheel": {"end_time": 1.0, "gravity": [0.0, -1.0], "bodies": [
        {"name": "post", "shape": "circle", "radius": 0.05, "fixed": True, "position": [0.0, 0.0],
         "orbit": {"radius": 0.4, "angle": 0.0}, "angular_velocity": 2.0},
        {"name": "a", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [-1.0, 0.3], "velocity": [2.0, 0]},
        {"name": "b", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [1.0, 0.3], "velocity": [-2.0, 0]}],
        "inputs": []},
}


def base_scenes() -> dict[str, tuple[object, str]]:
    """name -> (the parsed scene, its flat text)."""
    out = {}
    for name, raw in BASES.items():
        sc = parse_scene(json.dumps(raw), f"{name}.json")
        out[name] = (sc, compile_scene(sc))
    return out


# ------------------------------------------------------------------ mutations
EXTREMES = ["nan", "NaN", "inf", "-inf", "Infinity", "1e308", "-1e308", "1.7976931348623157e308", "1e309", "1e999",
            "-0", "-0.0", "0", "5e-324", "1e-320", "1e-308", "1e-150", "1e150", "1e151", "2e150", "1e-15", "0x10",
            "0x1p3", "1_0", "+1", "-1", "1e", ".", "-", "2147483647", "2147483648", "4294967296", "-2147483649",
            "9223372036854775807", "18446744073709551617", "1000000000000000000", "999999999999999999",
            "2000000000", "1000001", "1000000", "1024", "1025", "10000001", "100000000", "3", "2", "1", "4", "5",
            "0.5", "1e-12", "1" * 70, "1.0e+308", "1e-400", "-1e-400", "0.0000000000000000000000000000001"]
JUNK = [b"\x00", b"\xff", b"\x7f", b"\t", b"\r", b"\n", b" ", b"\x0b", b"\x0c", b"#", b"\xc3\xa9", b"-", b"e"]


def _tokens(text: str) -> list[tuple[int, int]]:
    spans, i, n = [], 0, len(text)
    while i < n:
        while i < n and text[i] in " \n":
            i += 1
        j = i
        while j < n and text[j] not in " \n":
            j += 1
        if j > i:
            spans.append((i, j))
        i = j
    return spans


def mutate(rng: random.Random, text: str) -> tuple[str, bytes]:
    """One mutation of `text`: (its kind, the mutated bytes)."""
    kind = rng.choice(["flip", "insert", "swap", "number", "number", "number", "count", "truncate",
                       "duplicate", "drop", "copy-body"])
    data = text.encode("latin-1")
    spans = _tokens(text)
    if kind == "flip" and data:
        i = rng.randrange(len(data))
        data = data[:i] + bytes([data[i] ^ (1 << rng.randrange(8))]) + data[i + 1:]
    elif kind == "insert":
        i = rng.randrange(len(data) + 1)
        data = data[:i] + rng.choice(JUNK) + data[i:]
    elif kind == "swap" and len(spans) > 1:
        (a, b), (c, d) = sorted(rng.sample(spans, 2))
        data = (text[:a] + text[c:d] + text[b:c] + text[a:b] + text[d:]).encode("latin-1")
    elif kind in ("number", "count") and spans:
        if kind == "count":         # a count or an index: the first word of a short line, or an integer field
            ints = [s for s in spans if text[s[0]:s[1]].lstrip("-").isdigit()]
            spans = ints or spans
        a, b = rng.choice(spans)
        data = (text[:a] + rng.choice(EXTREMES) + text[b:]).encode("latin-1")
    elif kind == "truncate":
        data = data[:rng.randrange(len(data) + 1)]
    elif kind in ("duplicate", "drop", "copy-body") and text:
        lines = text.splitlines(True)
        k = rng.randrange(len(lines))
        if kind == "duplicate":
            lines.insert(k, lines[k])
        elif kind == "drop":
            del lines[k]
        else:                       # a body line and its vertices again, elsewhere
            starts = [i for i, ln in enumerate(lines) if ln.startswith("body ")] or [k]
            s = rng.choice(starts)
            e = s + 1
            while e < len(lines) and lines[e].startswith("v "):
                e += 1
            lines[k:k] = lines[s:e]
        data = "".join(lines).encode("latin-1")
    return kind, data


def mutated_scene(rng: random.Random, bases: dict) -> tuple[str, bytes]:
    name = rng.choice(sorted(bases))
    text = bases[name][1]
    kinds = []
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        kind, data = mutate(rng, text)
        kinds.append(kind)
        text = data.decode("latin-1")
    return f"{name}:{'+'.join(kinds)}", text.encode("latin-1")


# ------------------------------------------------------------------ live sessions
VECTORS = [0.0, -0.0, 0.5, -1.5, 2.0, 1e-300, 5e-324, 1e150, 7e149, -7e149, 1e200, 1e308, -1e308,
           1.7976931348623157e308, 3.0, 0.25]


def live_session(rng: random.Random, bases: dict) -> tuple[str, bytes, float]:
    """A base scene with random inputs for the `--live` mode: (name, text, step)."""
    name = rng.choice(sorted(bases))
    sc, text = bases[name]
    n = len(sc.bodies)
    end = sc.end_time
    head = text[:text.index("\ninputs ")]
    times = sorted(rng.choice([0.0, end, end * rng.random(), round(end * rng.random(), 2), end / 4])
                   for _ in range(rng.randint(0, 12)))
    lines = []
    for t in times:
        mode = rng.choice([0, 1, 1, 2, 2, 3, 3, 4])
        body = rng.choice(list(range(n)) * 3 + [n, n + 7, -1, 2147483647, -2147483648])
        if mode == 4:
            x = y = 0.0
        elif mode == 3 and rng.random() < 0.7:          # teleports mostly near the scene
            x, y = rng.uniform(-0.5, 2.5), rng.uniform(-0.5, 2.5)
        else:
            x, y = rng.choice(VECTORS), rng.choice(VECTORS)
        lines.append(f"input {t!r} {body} {mode} {x!r} {y!r}")
    body = f"{head}\ninputs {len(lines)}\n" + "".join(ln + "\n" for ln in lines) + "end\n"
    step = rng.choice([0.01, 0.0123, 0.05, 0.25, 0.3, 1.0, end])
    return f"{name}:live", body.encode("ascii"), step


# ------------------------------------------------------------------ running
class Run:
    __slots__ = ("status", "signal", "out", "err", "timed_out", "capped", "rss", "seconds")

    def __init__(self):
        self.status = self.signal = None
        self.out = self.err = b""
        self.timed_out = self.capped = False
        self.rss = 0              # peak resident set, bytes
        self.seconds = 0.0

    def cut(self) -> bool:
        """Stopped while writing: at OUTPUT_CAP bytes, or out of time after
        STEADY bytes (a scene that asks for endless work; the slower
        runtimes write less of it in the time)."""
        return self.capped or (self.timed_out and len(self.out) + len(self.err) >= STEADY)

    def answer(self, n_out: int, n_err: int) -> tuple:
        """What every runtime must agree on (a cut run: its first bytes)."""
        if self.cut():
            return ("cut", self.out[:n_out], self.err[:n_err])
        return (self.status, self.out, self.err)


def _limits(memory: int | None):
    """The child's set-up in a forked process (the Python runner's own fork):
    a session of its own, the memory limit, no core files."""
    def apply():
        os.setsid()
        if memory:
            resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def _collect(pid: int, outs: list[int], data: bytes, stdin_fd: int | None, timeout: float) -> Run:
    """Feed stdin, read stdout/stderr (cut at OUTPUT_CAP), reap the child."""
    r = Run()
    bufs = {fd: bytearray() for fd in outs}
    open_fds = list(outs)
    pending = memoryview(data)
    wfds = [stdin_fd] if stdin_fd is not None else []
    if stdin_fd is not None and not data:
        os.close(stdin_fd)
        wfds = []
    t0 = time.monotonic()
    deadline = t0 + timeout
    while open_fds or wfds:
        left = deadline - time.monotonic()
        if left <= 0:
            r.timed_out = True
            break
        rd, wr, _ = select.select(open_fds, wfds, [], left)
        for fd in wr:
            try:
                k = os.write(fd, pending[:65536])
                pending = pending[k:]
            except BrokenPipeError:
                pending = pending[:0]
            if not pending:
                os.close(fd)
                wfds = []
        for fd in rd:
            chunk = os.read(fd, 65536)
            if not chunk:
                open_fds.remove(fd)
                os.close(fd)
                continue
            bufs[fd] += chunk
            if len(bufs[fd]) > OUTPUT_CAP:
                r.capped = True
        if r.capped:
            break
    if r.timed_out or r.capped:
        try:
            os.killpg(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    for fd in open_fds + wfds:
        os.close(fd)
    _, st, ru = os.wait4(pid, 0)
    r.seconds = time.monotonic() - t0
    r.rss = ru.ru_maxrss * 1024
    if os.WIFSIGNALED(st):
        r.signal = os.WTERMSIG(st)
    else:
        r.status = os.WEXITSTATUS(st)
    r.out, r.err = bytes(bufs[outs[0]]), bytes(bufs[outs[1]])
    return r


def _pipes():
    i_r, i_w = os.pipe()
    o_r, o_w = os.pipe()
    e_r, e_w = os.pipe()
    return (i_r, i_w), (o_r, o_w), (e_r, e_w)


class Runner:
    """One runtime's simulator as a program."""

    def __init__(self, lang: str, build, *, valgrind: bool = False, memory: int = MEMORY, timeout: float = TIMEOUT):
        self.lang, self.build, self.valgrind = lang, build, valgrind
        self.memory, self.timeout = (None if valgrind else memory), timeout * (30 if valgrind else 1)
        self.env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "runtimes" / "python")]))

    def cmd(self, step: float | None) -> list[str]:
        c = list(self.build.run_cmd) + (["--step", repr(step), "--live"] if step is not None else [])
        if self.valgrind:
            c = ["valgrind", "-q", "--leak-check=full", "--errors-for-leak-kinds=definite,indirect,possible",
                 f"--error-exitcode={VALGRIND_ERROR}", *c]
        return c

    def run(self, data: bytes, step: float | None = None) -> Run:
        (i_r, i_w), (o_r, o_w), (e_r, e_w) = _pipes()
        cmd = self.cmd(step)
        # GNU time measures the program's own peak memory (wait4 on this process's child would count the
        # pages of this process it was forked from, before its exec)
        rss_file = None
        if TIME:
            rss_file = os.path.join(self.build.workdir, f"fuzz-rss.{os.getpid()}")
            cmd = [TIME, "-f", "%M", "-o", rss_file, *cmd]
        # the limits by prlimit, not a preexec_fn: Popen then starts the program with vfork instead of
        # copying this process's page tables with fork (most of a fuzz run's system time in a big process)
        if PRLIMIT:
            cmd = [PRLIMIT, "--core=0", *([f"--as={self.memory}"] if self.memory else []), "--", *cmd]
        proc = subprocess.Popen(cmd, stdin=i_r, stdout=o_w, stderr=e_w, cwd=self.build.workdir, env=self.env,
                                start_new_session=True, preexec_fn=None if PRLIMIT else _limits(self.memory),
                                close_fds=True)
        for fd in (i_r, o_w, e_w):
            os.close(fd)
        proc.returncode = 0           # reaped by _collect (os.wait4)
        r = _collect(proc.pid, [o_r, e_r], data, i_w, self.timeout)
        if rss_file:
            try:
                with open(rss_file, encoding="ascii") as fh:
                    lines = fh.read().split("\n")
                os.unlink(rss_file)
            except OSError:
                lines = []
            words = lines[0].split() if lines else []
            if words[:3] == ["Command", "terminated", "by"] and r.signal is None:
                r.signal, r.status = int(words[-1]), None       # time itself exits 128 + N
            nums = [ln for ln in lines if ln.strip().isdigit()]
            r.rss = int(nums[-1]) * 1024 if nums else r.rss
        return r


class PythonRunner(Runner):
    """The Python simulator (max2code_rt.sim_main) in a forked child of this
    process, its modules loaded once: the same program, without Python's
    start-up for every input.  An exception that escapes it is a crash
    (exit status 3)."""

    def __init__(self, build, **kw):
        super().__init__("python", build, **kw)
        from max2code_rt import sim_main
        self.sim_main = sim_main
        args = build.run_cmd[build.run_cmd.index("max2code_rt.sim_main") + 1:]
        self.args = args
        self.cc = sim_main._load(args[0], "m2c_gen_circle_circle")
        self.pe = sim_main._load(args[1], "m2c_gen_point_edge")
        sim_main._load = self._loaded

    def _loaded(self, path, name):
        return self.cc if name.endswith("circle_circle") else self.pe

    def run(self, data: bytes, step: float | None = None) -> Run:
        (i_r, i_w), (o_r, o_w), (e_r, e_w) = _pipes()
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:                                        # the child
            code = 3
            try:
                _limits(self.memory)()
                os.dup2(i_r, 0)
                os.dup2(o_w, 1)
                os.dup2(e_w, 2)
                for fd in (i_r, i_w, o_r, o_w, e_r, e_w):
                    os.close(fd)
                sys.stdin = io.TextIOWrapper(io.FileIO(0, "r"), encoding="latin-1")
                sys.stdout = io.TextIOWrapper(io.FileIO(1, "w", closefd=False), encoding="ascii")
                sys.stderr = io.TextIOWrapper(io.FileIO(2, "w", closefd=False), encoding="ascii")
                argv = self.args + (["--step", repr(step), "--live"] if step is not None else [])
                code = self.sim_main.main(argv)
                sys.stdout.flush()
                sys.stderr.flush()
            except BaseException:                           # noqa: B902: any escape is the finding
                try:
                    os.write(2, traceback.format_exc().encode("utf-8", "replace"))
                except OSError:
                    pass
                code = 3
            os._exit(code)
        for fd in (i_r, o_w, e_w):
            os.close(fd)
        return _collect(pid, [o_r, e_r], data, i_w, self.timeout)


def runners(langs, *, valgrind: bool = False, progress=None) -> dict[str, Runner]:
    """The built simulators (built when needed) of the base scenes' effects."""
    sc = next(iter(base_scenes().values()))[0]
    effects = {base_scenes()[n][0].effects for n in BASES}
    assert len(effects) == 1, effects       # one build per runtime serves every base scene
    out = {}
    for lang in langs:
        if progress:
            progress(f"building the {lang} simulator")
        b = build_simulator(lang, sc.effects, sc.taylor_order)
        out[lang] = PythonRunner(b) if lang == "python" else Runner(lang, b, valgrind=valgrind and lang == "c")
    return out


# ------------------------------------------------------------------ checking
class Tally:
    def __init__(self):
        self.inputs = self.refused = self.accepted = self.capped = 0
        self.disagreements = self.crashes = self.timeouts = self.valgrind_errors = self.nonfinite = 0
        self.slow = 0                           # runs out of time on a scene the others stopped at an event limit
        self.stopped = False                    # interrupted before the last input
        self.peak = {}                          # lang -> bytes
        self.cpu = {}                           # lang -> s of wall time in its runs
        self.failures: list[str] = []

    def figures(self) -> dict:
        return {"inputs": self.inputs, "refused": self.refused, "accepted": self.accepted, "capped": self.capped,
                "disagreements": self.disagreements, "crashes": self.crashes, "timeouts": self.timeouts,
                "nonfinite": self.nonfinite, "slow_on_stuck": self.slow,
                "valgrind_errors": self.valgrind_errors,
                "peak_memory_mb": {k: round(v / 2 ** 20, 1) for k, v in sorted(self.peak.items())},
                "seconds": {k: round(v, 1) for k, v in sorted(self.cpu.items())}}


def _show(b: bytes, n: int = 160) -> str:
    return repr(b[-n:] if len(b) > n else b)


# the ends of the X lines of a run stopped by one of its event limits
STUCK = b"the scene is stuck"                                   # max_same_time events at one instant
STOPPED = b": the run was stopped; raise max_events in the scene or --max-events, or shorten end_time"


def _stuck_elsewhere(lang: str, runs: dict[str, Run]) -> bool:
    """At least two runtimes ended the input in time, all with the same X
    line of an event limit: `... the scene is stuck` (more than
    max_same_time events at one instant) or `more than N events ...: the
    run was stopped` (max_events).  A runtime out of time there is slow, not
    stuck for ever: per event Python takes about 50 times C's time and
    Modula-2 about 1.3 times (an orbiting circle turning at 1e151 rad/s
    meets a horizon every 4e-153 s; the 10^7 events up to the flat scenes'
    max_events take C and Rust 10 s, Modula-2 13 s, Python about 500 s on
    the shared 2 cores, near or past the 20 s a run has)."""
    done = [r for k, r in runs.items() if k != lang and not r.timed_out]
    if len(done) < 2 or any(r.status != 1 for r in done):
        return False
    lasts = {r.out.rstrip(b"\n").rsplit(b"\n", 1)[-1] for r in done}
    last = next(iter(lasts))
    return len(lasts) == 1 and (last.endswith(STUCK) or last.endswith(STOPPED))


def check(name: str, data: bytes, runs: dict[str, Run], tally: Tally, keep: int = 20) -> list[str]:
    """The faults of one input's runs (none: every runtime gave the same
    answer with exit status 0 or 1); counted into tally."""
    faults = []
    tally.inputs += 1
    for lang, r in runs.items():
        tally.peak[lang] = max(tally.peak.get(lang, 0), r.rss)
        tally.cpu[lang] = tally.cpu.get(lang, 0.0) + r.seconds
        if r.cut():
            continue
        if r.timed_out:
            if _stuck_elsewhere(lang, runs):
                tally.slow += 1
                continue
            tally.timeouts += 1
            faults.append(f"{lang}: no answer within its time limit")
        elif r.status == VALGRIND_ERROR:
            tally.valgrind_errors += 1
            faults.append(f"{lang}: valgrind: {r.err.decode('latin-1')[-1500:]}")
        elif r.signal is not None or r.status not in (0, 1):
            tally.crashes += 1
            what = f"signal {r.signal}" if r.signal is not None else f"exit {r.status}"
            faults.append(f"{lang}: {what}: {_show(r.out)} {_show(r.err, 600)}")
        elif r.status == 1 and not r.out.rstrip(b"\n").rsplit(b"\n", 1)[-1].startswith(b"X "):
            tally.crashes += 1
            faults.append(f"{lang}: exit 1 without an X line: {_show(r.out)} {_show(r.err, 600)}")
    for lang, r in runs.items():
        words = set(r.out.lower().split()) | set(r.err.lower().split())
        if words & NONFINITE:
            tally.nonfinite += 1
            faults.append(f"{lang}: a number that is not finite in its output")
    done = {lang: r for lang, r in runs.items() if r.cut() or not r.timed_out}
    cut = [r for r in done.values() if r.cut()]
    n_out = min((len(r.out) for r in cut), default=0)
    n_err = min((len(r.err) for r in cut), default=0)
    answers = {}
    for lang, r in done.items():
        answers.setdefault(r.answer(n_out, n_err), []).append(lang)
    if len(answers) > 1:
        tally.disagreements += 1
        parts = []
        for ans, langs in answers.items():
            parts.append(f"{','.join(langs)}: {ans[0]} {_show(ans[1])} {_show(ans[2], 200)}")
        faults.append("disagree: " + " | ".join(parts))
    if cut:
        tally.capped += 1
    elif done and all(r.status == 0 for r in done.values()):
        tally.accepted += 1
    elif done:
        tally.refused += 1
    if faults and len(tally.failures) < keep:
        tally.failures.append(f"{name}: {data[:4000]!r}\n    " + "\n    ".join(faults))
    return faults


def fuzz(count: int, live: int, seed: int, langs, *, valgrind: bool = False, progress=None,
         rs: dict[str, Runner] | None = None, keep: int = 20, report=None) -> Tally:
    """`count` mutated scenes and `live` live sessions, from `seed`, in every runtime of `langs`."""
    rng = random.Random(seed)
    bases = base_scenes()
    rs = rs or runners(langs, valgrind=valgrind, progress=progress)
    tally = Tally()
    total = count + live
    every = max(1, total // 50)
    t0 = time.monotonic()
    for k in range(total):
        if tally.stopped:
            break
        if k < count:
            name, data = mutated_scene(rng, bases)
            step = None
        else:
            name, data, step = live_session(rng, bases)
        try:
            runs = {lang: r.run(data, step) for lang, r in rs.items()}
        except KeyboardInterrupt:       # stopped (Ctrl-C or SIGTERM): the figures so far
            tally.stopped = True
            break
        faults = check(f"#{k} {name}", data, runs, tally, keep)
        if faults and report:           # as found: a long run shows its failures while it runs
            report(f"#{k} {name}: {data[:4000]!r}\n    " + "\n    ".join(faults))
        if progress and ((k + 1) % every == 0 or k + 1 == total):
            progress(f"{k + 1}/{total} inputs, {tally.refused} refused, {tally.accepted} accepted, "
                     f"{tally.disagreements} disagreements, {tally.crashes} crashes, {tally.timeouts} timeouts, "
                     f"{time.monotonic() - t0:.0f} s")
    return tally


def _progress_printer():
    """Progress on stderr: one line rewritten in place on a terminal, plain lines otherwise."""
    tty = sys.stderr.isatty()

    def say(msg: str | None):
        if msg is None:                 # done
            if tty:
                sys.stderr.write("\n")
        elif tty:
            sys.stderr.write("\r\033[K" + msg)
        else:
            sys.stderr.write(msg + "\n")
        sys.stderr.flush()
    return say


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="bench/fuzz.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=2000, help="mutated flat scenes (default 2000)")
    ap.add_argument("--live", type=int, default=200, help="random live sessions (default 200)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--langs", default=",".join(LANGS), help="runtimes, comma-separated (default: all four)")
    ap.add_argument("--valgrind", action="store_true", help="run the C simulator under valgrind's memcheck")
    ap.add_argument("--json", metavar="FILE", help="write the figures as JSON too")
    ap.add_argument("--show", type=int, default=10, help="failures printed in full (default 10)")
    a = ap.parse_args(argv)
    langs = [x for x in a.langs.split(",") if x]
    bad = [x for x in langs if x not in LANGS]
    if bad:
        ap.error(f"unknown runtime {bad[0]} (choose from {', '.join(LANGS)})")
    if a.valgrind and "c" not in langs:
        ap.error("--valgrind runs the C simulator: --langs must name c")
    say = _progress_printer()

    def stop(signum, frame):
        raise KeyboardInterrupt
    signal.signal(signal.SIGTERM, stop)
    t0 = time.monotonic()
    shown = []

    def report(text: str):
        if len(shown) < a.show:
            shown.append(text)
            print(text, flush=True)
    tally = fuzz(a.count, a.live, a.seed, langs, valgrind=a.valgrind, progress=say, keep=a.show, report=report)
    say(None)
    figs = tally.figures()
    figs.update(seed=a.seed, scenes=a.count, live_sessions=a.live, langs=langs, valgrind=a.valgrind,
                wall_seconds=round(time.monotonic() - t0, 1))
    print(("stopped early: " if tally.stopped else "")
          + f"inputs {figs['inputs']} ({a.count} scenes, {a.live} live sessions; seed {a.seed}; {', '.join(langs)}"
          f"{'; C under valgrind' if a.valgrind else ''})")
    print(f"refused {figs['refused']}, accepted {figs['accepted']}, cut at {OUTPUT_CAP} bytes {figs['capped']}; "
          f"out of time where the others stopped at an event limit {figs['slow_on_stuck']}")
    print(f"disagreements {figs['disagreements']}, crashes {figs['crashes']}, timeouts {figs['timeouts']}, "
          f"numbers not finite {figs['nonfinite']}"
          + (f", valgrind errors or leaks {figs['valgrind_errors']}" if a.valgrind else ""))
    print("peak memory of one run (MB): " + ", ".join(f"{k} {v}" for k, v in figs["peak_memory_mb"].items()))
    print(f"wall time {figs['wall_seconds']} s")
    if a.json:
        Path(a.json).write_text(json.dumps(figs, indent=1) + "\n", encoding="utf-8")
    bad = figs["disagreements"] + figs["crashes"] + figs["timeouts"] + figs["valgrind_errors"] + figs["nonfinite"]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
