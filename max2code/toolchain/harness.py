"""Compile generated coefficient code into a small program per language
(templates/<lang>/harness.j2) that reads parameter sets on stdin and prints
the coefficients exactly; used by the tests and the benchmarks.  Also the
two steps every harness shares (exact.py's too): writing the generated file
and the harness source into a workdir, and running the build commands."""
from __future__ import annotations

import contextlib
import fcntl
import hashlib
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from max2code import paths
from max2code.errors import Max2CodeError
from max2code.generate.render import environment
from max2code.targets import LANGUAGES
from max2code.toolchain import toolchain
from max2code.toolchain.tools import tool_version


class HarnessBuildError(Max2CodeError):
    """The generated code did not compile; the message holds the compiler's output."""


MODES = {"full": 0, "entry": 1, "toc": 2}


@dataclass
class Harness:
    lang: str
    workdir: str
    run_cmd: list[str]
    nparams: int
    mode: str = "full"

    def evaluate(self, param_sets: list[list[float]], timeout: float = 300) -> list[list[float]]:
        text = f"{MODES[self.mode]}\n" + "\n".join(" ".join(repr(float(x)) for x in ps) for ps in param_sets) + "\n"
        proc = subprocess.run(self.run_cmd, input=text, capture_output=True, text=True,
                              timeout=timeout, cwd=self.workdir)
        if proc.returncode != 0:
            raise RuntimeError(f"{self.lang} harness failed: {proc.stderr[-2000:]}")
        return [[float(w) for w in line.split()] for line in proc.stdout.splitlines()]


def build_harness(lang: str, generated, workdir: str, mode: str = "full") -> Harness:
    """Write the generated file (`generated`, a GeneratedFile) and the harness
    into `workdir` and compile them.  The harness is one program for the
    file's every entry, its mode chosen at run time: the same file compiles
    once (compile_harness keeps the build) whichever modes the callers ask.
    The Harness returned runs `mode`:
    "full": the coefficient function; each input line is the parameters;
    "entry": the selection entry (NAME_coefficients): prints the selected
    degree, then that many + 1 coefficients (-1 when unsupported);
    "toc": the time-of-contact entry (NAME_toc): each input line is the
    parameters then lo and hi, and the harness prints `status t`.
    "entry" and "toc" need a file generated with its variants (a selection)."""
    fn, sel = generated.function, generated.selection
    if mode not in MODES:
        raise ValueError(f"harness mode must be one of {', '.join(MODES)}, not {mode!r}")
    if mode != "full" and sel is None:
        raise ValueError(f"the generated file has no selection entry, so no {mode} mode")
    entry = sel.name if sel is not None else None
    toc = sel.name.replace("_coefficients", "_toc") if sel is not None else None
    tc = toolchain(lang)
    src, exe = write_harness(lang, generated.text, workdir, "harness.j2", name=fn.name, nparams=len(fn.params),
                             degree=fn.degree, nterms=max(fn.degree, sel.max_degree if sel else 0) + 1,
                             entry=entry, toc=toc)
    compile_harness(tc.harness_build(src, exe, [workdir]), workdir, timeout=600)
    return Harness(lang, workdir, tc.harness_run(src, exe), len(fn.params), mode)


def write_harness(lang: str, generated_text: str, workdir: str, template: str, **ctx) -> tuple[str, str]:
    """Write the generated file and the harness made from LANG's `template`
    (given `generated`, the generated file's name, and `ctx`) into `workdir`;
    return the harness source's and executable's paths."""
    os.makedirs(workdir, exist_ok=True)
    gen = "generated" + LANGUAGES[lang].extension
    with open(os.path.join(workdir, gen), "w", encoding="utf-8") as fh:
        fh.write(generated_text)
    src = os.path.join(workdir, toolchain(lang).harness_source)
    text = environment().get_template(f"{lang}/{template}").render(generated=gen, **ctx)
    with open(src, "w", encoding="utf-8") as fh:
        fh.write(text)
    return src, os.path.join(workdir, "harness")


def compile_harness(commands: list[list[str]], workdir: str, timeout: float) -> None:
    """Run the build commands in `workdir`; HarnessBuildError with the tool's output on failure.
    A build that succeeded is kept under BUILD/harness/, keyed by all that
    made it (_build_key): the same harness built again (by another test, a
    parallel worker or a later run) is copied from there instead."""
    key = _build_key(commands, workdir)
    entry = paths.build_dir() / "harness" / key[:32]
    with _locked(entry):
        if (entry / _DONE).is_file() and (entry / _DONE).read_text(encoding="utf-8") == key:
            for f in entry.iterdir():
                if f.name != _DONE:
                    shutil.copy2(f, os.path.join(workdir, f.name))
            return
        before = {name: os.stat(os.path.join(workdir, name)).st_mtime_ns for name in os.listdir(workdir)}
        for cmd in commands:
            proc = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True, cwd=workdir,
                                  timeout=timeout)
            if proc.returncode != 0:
                raise HarnessBuildError(f"{' '.join(cmd)}\n{proc.stdout}{proc.stderr}")
        # the entry: what the commands made or changed in workdir (programs, objects), written whole, then marked
        made = [n for n in sorted(os.listdir(workdir)) if os.path.isfile(os.path.join(workdir, n))
                and before.get(n) != os.stat(os.path.join(workdir, n)).st_mtime_ns]
        tmp = entry.with_name(f"{entry.name}.{os.getpid()}.tmp")
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir(parents=True)
        for n in made:
            shutil.copy2(os.path.join(workdir, n), tmp / n)
        (tmp / _DONE).write_text(key, encoding="utf-8")
        shutil.rmtree(entry, ignore_errors=True)
        os.replace(tmp, entry)


@contextlib.contextmanager
def _locked(entry: Path):
    """Hold the lock of a cache entry (the file ENTRY.lock next to it): two
    workers that build the same harness take turns, and the second copies."""
    entry.parent.mkdir(parents=True, exist_ok=True)
    with open(entry.with_name(entry.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


_DONE = "harness-key"       # an entry's last file: the full key; a folder without it is not an entry


def _build_key(commands: list[list[str]], workdir: str) -> str:
    """The digest of a harness build: the commands (workdir written as a
    placeholder, so the same build in another folder has the same key), the
    bytes of every file in workdir (the generated file, the harness source)
    and of every other file a command names (the runtime's library, objects
    and rlib), the runtime sources (their headers and interfaces), and the
    tools' versions."""
    h = hashlib.sha256()
    wd = os.path.abspath(workdir)

    def add(label: str, data: bytes) -> None:
        h.update(f"{label} {len(data)}\0".encode())
        h.update(data)
    add("runtimes", paths.sources_digest().encode())
    for name in sorted(os.listdir(wd)):
        p = os.path.join(wd, name)
        if os.path.isfile(p):
            with open(p, "rb") as fh:
                add(f"workdir/{name}", fh.read())
    for cmd in commands:
        add("tool", tool_version(cmd[0]).encode())
        add("command", "\0".join(a.replace(wd, "<workdir>") for a in cmd).encode())
        for a in cmd[1:]:
            p = os.path.abspath(os.path.join(wd, a))
            if not p.startswith(wd + os.sep) and os.path.isfile(p):
                with open(p, "rb") as fh:
                    add(f"file {a}", fh.read())
    return h.hexdigest()
