"""Run Maxima: statements with sentinels, failure detection, a result cache.

Maxima exits 0 on syntax and runtime errors and loops forever when it asks a
question in batch mode, so success is read from the output: a `:lisp`
sentinel before every user statement (it does not disturb `%`), a final
sentinel, and the requested items written to files by Lisp.  A failure is
mapped back to the statement's place in the .mxm file.
"""
from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from max2code import paths
from max2code.errors import Max2CodeError, SourceError, Span

DRIVER_VERSION = "2"   # bump when the script layout or the cache entry changes: it is part of the cache key
INSTALL_HINT = ("Maxima was not found on PATH. Install it with 'apt-get install maxima' "
                "(Debian/Ubuntu; 'bash scripts/setup' does it), or set MAX2CODE_MAXIMA to its path.")
_QUESTION = re.compile(r"^(Is .*\?|.*(positive, negative|positive or negative|or zero\?|integer\?).*)$", re.M)
_MAX_OUTPUT = 64 << 20   # bytes of Maxima output before we stop it


@dataclass(frozen=True)
class Statement:
    """One Maxima statement with its terminator, and where it starts."""
    text: str
    span: Span


@dataclass(frozen=True)
class MaximaResult:
    """Items computed by Maxima, as the strings Maxima's `string()` gave."""
    items: dict[str, str]
    seconds: float
    cached: bool
    version: str
    output_lines: int      # lines Maxima printed (its echo and results)


def _advance(span: Span, text: str) -> Span:
    line, col = span.line, span.column
    for ch in text:
        if ch == "\n":
            line, col = line + 1, 1
        else:
            col += 1
    return Span(span.file, line, col)


def split_statements(text: str, start: Span) -> list[Statement]:
    """Split Maxima text into statements ended by ';' or '$'.

    Strings and /* comments */ are skipped over; a line starting with
    ':lisp' is a statement of its own.  Text after the last terminator that
    is not blank or a comment is an error.
    """
    out: list[Statement] = []
    i, n, begin = 0, len(text), None
    while i < n:
        ch = text[i]
        if ch == "/" and text.startswith("/*", i):
            end = text.find("*/", i + 2)
            if end < 0:
                raise SourceError(_advance(start, text[:i]), "unterminated comment '/*' in the Maxima text")
            i = end + 2
            continue
        if begin is None:
            if ch.isspace():
                i += 1
                continue
            begin = i
            line_start = text.rfind("\n", 0, i) + 1
            if text.startswith(":lisp", i) and not text[line_start:i].strip():
                end = text.find("\n", i)
                end = n if end < 0 else end
                out.append(Statement(text[i:end], _advance(start, text[:i])))
                i, begin = end, None
                continue
        if ch == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            if j >= n:
                raise SourceError(_advance(start, text[:i]), "unterminated string in the Maxima text")
            i = j + 1
            continue
        if ch in ";$":
            out.append(Statement(text[begin:i + 1], _advance(start, text[:begin])))
            begin = None
        i += 1
    if begin is not None:
        raise SourceError(_advance(start, text[:begin]),
                          "Maxima statement is not ended by ';' or '$': " + text[begin:].strip().splitlines()[0][:40])
    if not out:
        raise SourceError(start, "the Maxima text has no statement")
    return out


def is_quit(stmt: Statement) -> bool:
    """A `quit();` statement: it would stop Maxima before the result is read."""
    return re.fullmatch(r"\s*(quit|quit\s*\(\s*\))\s*[;$]\s*", stmt.text) is not None


DEFAULT_TIMEOUT = 60.0   # seconds per Maxima run: our equations take about 1 s


def maxima_command() -> str:
    env = os.environ.get("MAX2CODE_MAXIMA")
    if env:
        found = shutil.which(env)
        if not found:
            why = ("is not executable" if os.path.isfile(env) else
                   "is a folder" if os.path.isdir(env) else "does not exist")
            raise Max2CodeError(f"max2code: error: MAX2CODE_MAXIMA={env}: {why}; point it at the maxima "
                                "program, or unset it to use the one on PATH")
        return found
    exe = shutil.which("maxima")
    if not exe:
        raise Max2CodeError(f"max2code: error: {INSTALL_HINT}")
    return exe


def _not_runnable(exe: str, exc: OSError) -> Max2CodeError:
    if os.environ.get("MAX2CODE_MAXIMA"):
        return Max2CodeError(f"max2code: error: MAX2CODE_MAXIMA={os.environ['MAX2CODE_MAXIMA']}: cannot run it "
                             f"({exc.strerror or exc})")
    return Max2CodeError(f"max2code: error: cannot run {exe} ({exc.strerror or exc}). {INSTALL_HINT}")


@functools.lru_cache(maxsize=None)
def maxima_version(exe: str | None = None) -> str:
    exe = exe or maxima_command()
    try:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=60).stdout
    except OSError as exc:
        raise _not_runnable(exe, exc) from None
    except subprocess.TimeoutExpired:
        raise Max2CodeError(f"max2code: error: {exe} --version did not answer within 60 s: is it Maxima?") from None
    return out.strip() or "unknown"


# Maxima functions that read a file named by their first argument: the file's
# content is part of the cache key (a Maxima-language file's own reads too)
_READERS = ("load", "batch", "batchload", "loadfile", "demo", "printfile", "restore", "setup_autoload",
            "read_list", "read_matrix", "read_array", "read_hashed_array", "read_nested_list",
            "read_binary_list", "read_binary_matrix", "read_binary_array", "openr", "openr_binary", "file_search")
# what makes a result depend on more than the text and the files it names: never cached
_OPAQUE = ("system", "eval_string", "parse_string", "getenv", "run_testsuite", "batch_string")
_MAXIMA_FILES = (".mac", ".mc", ".wxm", ".max", ".dem")
_LOAD_EXTENSIONS = ("", ".mac", ".mc", ".wxm", ".max", ".lisp", ".lsp")
_CALL = re.compile(r"/\*.*?\*/|\"(?:[^\"\\]|\\.)*\"|\?[A-Za-z_%\-]|(?<![A-Za-z0-9_%])([A-Za-z_%][A-Za-z0-9_%]*)\s*\(",
                   re.S)
_LITERAL_ARG = re.compile(r'\s*"((?:[^"\\]|\\.)*)"\s*[,)]')


def _user_dir() -> Path:
    """Maxima's user folder (maxima-init.mac lives there): $MAXIMA_USERDIR, else ~/.maxima."""
    return Path(os.environ.get("MAXIMA_USERDIR") or os.path.expanduser("~/.maxima"))


def _file_digest(path: Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def _resolve(name: str, loader: bool) -> Path | None:
    """The file Maxima would open for `name` (a loader also tries Maxima's
    extensions, in the current folder and the user folder), or None."""
    bases = [Path(name)] if os.path.isabs(name) else [Path(name), _user_dir() / name]
    for base in bases:
        for ext in (_LOAD_EXTENSIONS if loader else ("",)):
            cand = Path(str(base) + ext)
            if cand.is_file():
                return cand.resolve()
    return None


def inputs_of(texts: list[str], seen: dict[str, str] | None = None) -> dict[str, str] | str:
    """The files the Maxima `texts` read (path -> sha256 of the content, a
    Maxima-language file's own reads included), or, when what they read
    cannot be known (a file name that is not a string literal, a file that
    cannot be found, Lisp, system(...), eval_string(...), getenv(...)), why."""
    seen = {} if seen is None else seen
    for text in texts:
        if text.lstrip().startswith(":lisp"):
            return "it runs Lisp (:lisp)"
        for m in _CALL.finditer(text):
            tok = m.group(0)
            if tok.startswith("?"):
                return "it calls Lisp (?name)"
            func = m.group(1)
            if func is None:
                continue
            if func in _OPAQUE:
                return f"it calls {func}(...)"
            if func not in _READERS:
                continue
            arg = _LITERAL_ARG.match(text, m.end())
            if not arg:
                return f"{func}(...) names its file by an expression, not a string"
            name = arg.group(1).replace('\\"', '"').replace("\\\\", "\\")
            path = _resolve(name, func in ("load", "batch", "batchload", "loadfile", "demo", "setup_autoload"))
            if path is None:
                return f'{func}("{name}"): no such file here or in {_user_dir()}'
            if path.suffix in (".lisp", ".lsp"):
                return f'{func}("{name}") loads Lisp'
            key = str(path)
            if key in seen:
                continue
            try:
                seen[key] = _file_digest(path)
                if path.suffix in _MAXIMA_FILES:
                    with open(path, encoding="utf-8", errors="replace") as fh:
                        inner = inputs_of([fh.read()], seen)
                    if isinstance(inner, str):
                        return f"{path.name}: {inner}"
            except OSError as exc:
                return f"{path}: {exc.strerror or exc}"
    return seen


def _environment() -> dict:
    """What besides the text and the files it names can change Maxima's
    answer: the program itself, its MAXIMA_* environment, its init files
    (maxima-init.mac and .lisp, in the user folder and the current folder)."""
    out: dict = {k: v for k, v in sorted(os.environ.items()) if k.startswith("MAXIMA_")}
    init = {}
    names = [os.environ.get("MAXIMA_INITMAC") or "maxima-init.mac", os.environ.get("MAXIMA_INITLISP") or "maxima-init.lisp"]
    for folder in (_user_dir(), Path.cwd()):     # Maxima finds its init files in either
        for name in names:
            path = (folder / name).absolute()
            try:
                init[str(path)] = _file_digest(path)
            except OSError:
                init[str(path)] = None
    out["init files"] = init
    return out


def _entry_digest(items: dict, output_lines: int) -> str:
    return hashlib.sha256(json.dumps({"items": items, "output_lines": output_lines}, sort_keys=True).encode()).hexdigest()


def _lisp_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def build_script(prelude: list[str], statements: list[Statement], items: dict[str, str], outdir: str) -> str:
    """The batch script: settings, prelude, marked statements, items to files."""
    lines = ["display2d:false$", "linel:1000000$", "ratprint:false$", "keepfloat:false$"]
    lines += prelude
    for k, st in enumerate(statements):
        lines.append(f':lisp (format t "~%@@S {k}~%")')
        lines.append(st.text)
    lines.append(':lisp (format t "~%@@USER-DONE~%")')
    lines.append("__m2c_r: %$")
    # the polynomial: quoted calls evaluated, an equation moved to one side
    lines.append("__m2c_p: block([r: ev(__m2c_r, nouns)], if not atom(r) and op(r) = \"=\" then lhs(r) - rhs(r) else r)$")
    for name, expr in items.items():
        if not re.fullmatch(r"[A-Za-z0-9_]+", name):
            raise ValueError(f"bad item name {name!r}")
        path = os.path.join(outdir, name + ".txt")
        lines.append(f':lisp (format t "~%@@ITEM {name}~%")')
        lines.append(f"__m2c_v: string({expr})$")
        lines.append(f":lisp (with-open-file (s {_lisp_string(path)} :direction :output :if-exists :supersede) (princ $__m2c_v s))")
    lines.append(':lisp (format t "~%@@DONE~%")')
    return "\n".join(lines) + "\n"


def _run_streaming(cmd: list[str], timeout: float) -> tuple[str, str | None]:
    """Run `cmd`; return (output, why_stopped) where why_stopped is None on a normal exit."""
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    chunks: list[bytes] = []
    size = [0]
    stop = threading.Event()

    def reader():
        assert proc.stdout is not None
        for chunk in iter(lambda: proc.stdout.read1(65536), b""):
            chunks.append(chunk)
            size[0] += len(chunk)
            if size[0] > _MAX_OUTPUT or _QUESTION.search(chunk.decode("utf-8", "replace")):
                stop.set()
                return
        stop.set()

    th = threading.Thread(target=reader, daemon=True)
    th.start()
    finished = stop.wait(timeout)
    why = None
    if proc.poll() is None:
        if not finished:
            why = "timeout"
        elif _QUESTION.search(b"".join(chunks).decode("utf-8", "replace")):
            why = "question"
        elif size[0] > _MAX_OUTPUT:
            why = "output"
        proc.kill()
    proc.wait()
    th.join(timeout=5)
    return b"".join(chunks).decode("utf-8", "replace"), why


def _failure(output: str, why: str | None, statements: list[Statement], fallback: Span, timeout: float) -> SourceError:
    marks = [int(m) for m in re.findall(r"^@@S (\d+)$", output, re.M)]
    k = marks[-1] if marks else None
    after_user = "@@USER-DONE" in output
    span = statements[k].span if (k is not None and not after_user) else fallback
    tail = output.split(f"@@S {k}\n", 1)[-1] if k is not None else output
    if why == "question":
        q = _QUESTION.search(tail) or _QUESTION.search(output)
        question = q.group(0).strip() if q else "a question"
        return SourceError(span, f"Maxima asked '{question}' and cannot be answered in batch mode; "
                                 "state the fact first, e.g. assume(k > 0)$ or declare(n, integer)$")
    if why == "timeout":
        return SourceError(span, f"Maxima did not finish within {timeout:g} s (raise --maxima-timeout, or simplify)")
    if why == "output":
        return SourceError(span, "Maxima printed more than 64 MiB; stopped (end statements with '$' to silence them)")
    m = re.search(r"^incorrect syntax: (.*)$", tail, re.M)
    if m:
        return SourceError(span, f"Maxima syntax error: {m.group(1).strip()}")
    lines = tail.splitlines()
    for i, line in enumerate(lines):
        if "-- an error." in line or "Maxima encountered a Lisp error" in line:
            before = [x.strip() for x in lines[max(0, i - 3):i] if x.strip() and not x.startswith("@@")]
            msg = before[-1] if before else line.strip()
            if "Lisp error" in line:
                msg = " ".join(x.strip() for x in lines[i:i + 3] if x.strip())
            where = "Maxima error" if not after_user else "Maxima error while extracting the result"
            return SourceError(span, f"{where}: {msg}")
    last = [x for x in lines if x.strip()][-3:]
    return SourceError(span, "Maxima stopped before the end of the script: " + " | ".join(x.strip() for x in last))


def run_maxima(prelude: list[str], statements: list[Statement], items: dict[str, str], *,
               fallback: Span, timeout: float = DEFAULT_TIMEOUT, use_cache: bool = True) -> MaximaResult:
    """Run the statements, then evaluate `items` (name -> Maxima expression over `__m2c_p`:
    the value of the last statement, nouns evaluated, `lhs = rhs` as `lhs - rhs`).  Raises SourceError on any Maxima failure."""
    exe = maxima_command()
    version = maxima_version(exe)
    stmts = [s for s in statements if not is_quit(s)]
    if not stmts:
        raise SourceError(fallback, "the Maxima text has no statement besides quit()")
    cache_file = None
    if use_cache:
        files = inputs_of(prelude + [s.text for s in stmts])
        if isinstance(files, dict):     # else the result depends on what cannot be known here: not cached
            try:
                program = _file_digest(Path(exe))
            except OSError:
                program = exe
            key_src = json.dumps({"driver": DRIVER_VERSION, "maxima": version, "program": program,
                                  "environment": _environment(), "files": files, "prelude": prelude,
                                  "statements": [s.text for s in stmts], "items": items}, sort_keys=True)
            cache_file = paths.cache_dir() / (hashlib.sha256(key_src.encode()).hexdigest() + ".json")
    if cache_file is not None and cache_file.exists():
        try:
            data = json.loads(cache_file.read_text(encoding="utf-8"))
            if data["digest"] != _entry_digest(data["items"], data["output_lines"]):
                raise ValueError("digest")
            return MaximaResult(data["items"], 0.0, True, version, data["output_lines"])
        except (ValueError, KeyError, TypeError, OSError):
            print(f"max2code: note: the Maxima cache entry {cache_file} is damaged; Maxima runs again "
                  "and replaces it", file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="max2code-") as tmp:
        script = os.path.join(tmp, "job.mac")
        with open(script, "w", encoding="utf-8") as fh:
            fh.write(build_script(prelude, stmts, items, tmp))
        try:
            output, why = _run_streaming([exe, "--very-quiet", "--batch=" + script], timeout)
        except OSError as exc:
            raise _not_runnable(exe, exc) from None
        if why is not None or not re.search(r"^@@DONE$", output, re.M):
            raise _failure(output, why, stmts, fallback, timeout)
        got: dict[str, str] = {}
        for name in items:
            try:
                with open(os.path.join(tmp, name + ".txt"), encoding="utf-8") as fh:
                    got[name] = fh.read().strip()
            except OSError:
                raise SourceError(fallback, f"Maxima wrote no result for '{name}'") from None
    seconds = time.perf_counter() - t0
    out_lines = output.count("\n")
    if cache_file is not None:
        try:
            cache_file.parent.mkdir(parents=True, exist_ok=True)
            tmpf = cache_file.with_suffix(f".{os.getpid()}.tmp")
            tmpf.write_text(json.dumps({"items": got, "output_lines": out_lines,
                                        "digest": _entry_digest(got, out_lines)}), encoding="utf-8")
            os.replace(tmpf, cache_file)
        except OSError:
            pass
    return MaximaResult(got, seconds, False, version, out_lines)
