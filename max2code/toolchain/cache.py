"""Built programs kept for reuse across runs, keyed by the digest of all
that made them: the .mxm file, the files its Maxima text reads, Maxima
(its program and environment), max2code's own sources and templates, the
runtimes' sources, and what the caller adds (the language, the options, the
compilers' versions: Toolchain.tool_versions).
An entry is a folder under BUILD/reuse/ holding the programs and
`entry.json` (written last: a folder without it is not an entry); a build
runs under the entry's lock, so two runs never build into one folder.
A .mxm whose reads cannot be known (Lisp, system(...), a file named by an
expression) has no key: its programs are built every time."""
from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import json
import os
import shutil
from pathlib import Path

from max2code import paths


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


@functools.lru_cache(maxsize=1)
def package_digest() -> str:
    """The digest of max2code's sources (the generator, the printers, the
    toolchains) and templates."""
    h = hashlib.sha256()
    pkg = Path(__file__).resolve().parent.parent
    files = [("max2code", p) for p in sorted(pkg.rglob("*")) if p.is_file() and p.suffix in (".py", ".txt", ".lark")]
    files += [("templates", p) for p in sorted(paths.TEMPLATES.rglob("*")) if p.is_file()]
    for top, p in files:
        h.update(f"{top}/{p.relative_to(pkg if top == 'max2code' else paths.TEMPLATES).as_posix()}".encode() + b"\0")
        h.update(p.read_bytes())
    return h.hexdigest()


def equation_key(path: str, **extra) -> str | None:
    """The key of the programs made from the .mxm at `path` with `extra`
    (JSON values), or None when what its Maxima text reads cannot be known."""
    from max2code.generate.maxima import _environment, _file_digest, inputs_of, maxima_command

    with open(path, "rb") as fh:
        data = fh.read()
    mxm = _digest(data)
    # the whole file's text, declarations too (not parsing it is faster; they name no file, as a rule)
    files = inputs_of([data.decode("utf-8", errors="replace")])
    if not isinstance(files, dict):
        return None
    exe = maxima_command()
    parts = {"mxm": mxm, "files": files, "maxima": [exe, _file_digest(Path(exe))], "environment": _environment(),
             "max2code": package_digest(), "runtimes": paths.sources_digest(), "extra": extra}
    return _digest(json.dumps(parts, sort_keys=True).encode())


def root() -> Path:
    return paths.build_dir() / "reuse"


def folder(key: str) -> Path:
    return root() / key[:32]


def load(key: str | None) -> dict | None:
    """The entry of `key` (its entry.json), or None."""
    if key is None:
        return None
    try:
        data = json.loads((folder(key) / "entry.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and data.get("key") == key else None


@contextlib.contextmanager
def building(key: str):
    """The entry's folder, emptied, under its lock; `save(key, data)` marks it built."""
    d = folder(key)
    d.parent.mkdir(parents=True, exist_ok=True)
    with open(d.parent / (d.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            if d.exists():
                shutil.rmtree(d)
            d.mkdir()
            yield d
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def save(key: str, data: dict) -> None:
    d = folder(key)
    tmp = d / f"entry.{os.getpid()}.tmp"
    tmp.write_text(json.dumps({**data, "key": key}, sort_keys=True), encoding="utf-8")
    os.replace(tmp, d / "entry.json")


# how long each language's generation and builds took when last made (seconds), for the next run's plan
def _seconds_file() -> Path:
    return root() / "seconds.json"


def seconds_taken() -> dict:
    try:
        data = json.loads(_seconds_file().read_text(encoding="utf-8"))
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def remember_seconds(name: str, seconds: float, finished: bool) -> None:
    """Record that making `name` took `seconds` (`finished` False: it was
    stopped then, so it takes more)."""
    data = seconds_taken()
    data[name] = {"seconds": round(seconds, 3), "finished": finished}
    root().mkdir(parents=True, exist_ok=True)
    tmp = _seconds_file().with_suffix(f".{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, sort_keys=True), encoding="utf-8")
    os.replace(tmp, _seconds_file())
