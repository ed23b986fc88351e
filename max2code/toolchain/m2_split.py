"""Generated Modula-2 compiled as several modules.

gm2 12's front end takes time in the square of a module's length (each
quadruple it removes while resolving constant expressions walks the whole
module's list), so a module that includes a generated file of many variants
(circle-circle's 64) is slow to compile whatever the optimisation level.  The
builds of the harnesses and of the simulator therefore move the generated
file's self-contained coefficient procedures (function.j2's: only their
parameters, locals, REAL, SHORTREAL, VAL, ABS and sin, cos, sinf, cosf) into
implementation modules of a bounded length, STEMPartK.def/.mod, and include in
the module that included the generated file a text of the same interface:
FROM STEMPartK IMPORT those procedures, then the rest of the generated file
(its constants, selection and time-of-contact entries, exact part) as it was.
The procedures are the same text, so the code and its bits are the same;
`#line` directives keep compiler messages on the .mxm lines.  The user's
include of the generated file (docs/using-generated-code.md) is unchanged:
this is only how the bundled builds compile it."""
from __future__ import annotations

import os
import re

# at most this many lines of procedures per part module: small enough that the
# square stays small, large enough that a part's fixed cost (gm2 starting,
# reading RealMath's interface) does not dominate
PART_LINES = 1200

_HEADING = re.compile(r"PROCEDURE (\w+) \(([\w, ]+): REAL; VAR (\w+): ARRAY OF REAL\) ;$")
_LOCAL = re.compile(r"\s+(\w+): (?:REAL|SHORTREAL) ;$")
_COMMENT = re.compile(r"\(\*.*?\*\)", re.S)
_NUMBER = re.compile(r"\b\d+(?:\.\d*)?(?:E[+-]?\d+)?")
_WORD = re.compile(r"[A-Za-z_]\w*")
_KEYWORDS = frozenset("PROCEDURE VAR ARRAY OF BEGIN END REAL SHORTREAL VAL ABS".split())
_CALLS = ("sin", "cos", "sinf", "cosf")
_IMPORTS = {"sin": "RealMath", "cos": "RealMath", "sinf": "ShortMath", "cosf": "ShortMath"}


class _Proc:
    """A movable procedure: its name, heading line, lines and the calls it makes."""
    __slots__ = ("name", "heading", "lines", "calls")

    def __init__(self, name: str, heading: str, lines: list[str], calls: set[str]):
        self.name, self.heading, self.lines, self.calls = name, heading, lines, calls


def _movable(lines: list[str]) -> _Proc | None:
    """The procedure of `lines` (its heading to its END) when it can live in a
    module of its own: function.j2's shape, using no name but its own and _CALLS."""
    m = _HEADING.match(lines[0])
    if m is None or lines[-1] != f"END {m.group(1)} ;":
        return None
    name, params, out = m.group(1), [p.strip() for p in m.group(2).split(",")], m.group(3)
    own = {name, out, *params}
    body = "\n".join(ln for ln in lines[1:] if not ln.startswith("#"))
    for ln in lines[1:]:
        if ln.strip() == "BEGIN":
            break
        lm = _LOCAL.match(ln)
        if lm:
            own.add(lm.group(1))
    words = set(_WORD.findall(_NUMBER.sub(" ", _COMMENT.sub(" ", body))))
    calls = words & set(_CALLS)
    if words - own - _KEYWORDS - calls:
        return None
    return _Proc(name, lines[0], lines, calls)


def split(text: str, stem: str, origin: str, part_lines: int = PART_LINES) -> tuple[list[str], str, dict[str, str]]:
    """(the imports of the part modules, the rest of `text` to include after
    them, {file name: text} of the part modules).  `origin` is the generated
    file's name for the `#line` directives; with nothing to move, ([], text, {})."""
    lines = text.split("\n")
    rest: list[str] = [f'#line 1 "{origin}"']
    parts: list[list[_Proc]] = [[]]
    size = 0
    i = 0
    while i < len(lines):
        ln = lines[i]
        m = re.match(r"PROCEDURE (\w+)\b", ln)
        if m:
            end = next((j for j in range(i, len(lines)) if lines[j] == f"END {m.group(1)} ;"), None)
            if end is not None:
                proc = _movable(lines[i:end + 1])
                if proc is not None:
                    proc.lines = [f'#line {i + 1} "{origin}"', *proc.lines]
                    if parts[-1] and size + len(proc.lines) > part_lines:
                        parts.append([])
                        size = 0
                    parts[-1].append(proc)
                    size += len(proc.lines)
                    # the lines after it keep their numbers in compiler messages
                    rest.append(f'#line {end + 2} "{origin}"')
                    i = end + 1
                    continue
        rest.append(ln)
        i += 1
    if not parts[-1]:
        return [], text, {}
    files, imports = {}, []
    for k, procs in enumerate(parts, 1):
        mod = f"{stem}Part{k}"
        calls = set().union(*(p.calls for p in procs))
        uses = "".join(f"FROM {lib} IMPORT {', '.join(c for c in _CALLS if c in calls and _IMPORTS[c] == lib)} ;\n"
                       for lib in sorted({_IMPORTS[c] for c in calls}))
        files[f"{mod}.def"] = (f"DEFINITION MODULE {mod} ;\n\n" + "".join(p.heading + "\n" for p in procs)
                               + f"\nEND {mod}.\n")
        files[f"{mod}.mod"] = (f"IMPLEMENTATION MODULE {mod} ;\n\n{uses}\n"
                               + "".join("\n".join(p.lines) + "\n\n" for p in procs) + f"END {mod}.\n")
        imports.append(f"FROM {mod} IMPORT {', '.join(p.name for p in procs)} ;")
    return imports, "\n".join(rest), files


def split_files(paths: list[str], outdir: str, shim_dir: str, suffix: str = "") -> list[str]:
    """Split the generated files `paths`, which a module includes one after
    the other right after its imports (split()): their part modules go into
    `outdir`, and the texts to include instead into `shim_dir`, each under
    its generated file's name followed by `suffix` (the first begins with every part's import, as
    Modula-2 wants imports before declarations).  Returns the part modules'
    names, in order; none when nothing moved."""
    texts, modules, imports = {}, [], []
    for path in paths:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        name = os.path.basename(path)
        uses, rest, files = split(text, re.sub(r"\W", "_", os.path.splitext(name)[0]), name)
        imports += uses
        texts[os.path.join(shim_dir, name + suffix)] = rest
        texts.update((os.path.join(outdir, f), body) for f, body in files.items())
        modules += [f[:-4] for f in files if f.endswith(".mod")]
    first = os.path.join(shim_dir, os.path.basename(paths[0]) + suffix)
    texts[first] = "".join(f"{u}\n" for u in imports) + texts[first]
    for target, body in texts.items():
        os.makedirs(os.path.dirname(target), exist_ok=True)
        try:
            with open(target, encoding="utf-8") as fh:
                if fh.read() == body:
                    continue            # kept as is: make-like builds see no change
        except OSError:
            pass
        with open(target, "w", encoding="utf-8") as fh:
            fh.write(body)
    return modules
