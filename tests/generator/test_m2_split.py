"""max2code/toolchain/m2_split.py: the generated Modula-2 as part modules
and a text that imports them.  Every line of the generated file is kept (in
the rest, in order, or in exactly one part module), only self-contained
coefficient procedures move, and a part stays within its bound.  (That the
split builds print the same bytes is the harness and simulator tests':
their builds all go through it.)"""
from __future__ import annotations

import re

import pytest

from max2code.toolchain.m2_split import PART_LINES, split, split_files

ORIGIN = "ORIGIN.mxd"
CASES = [("point-line", {}), ("point-line", {"exact": True}), ("point-line", {"real": "float"}),
         ("circle-circle", {"effects": ("acceleration",)})]


def _mine(line: str) -> bool:
    """A #line directive the split adds (the generated file's own name the .mxm)."""
    return re.fullmatch(rf'#line \d+ "{re.escape(ORIGIN)}"', line) is not None


def _procedures(text: str) -> dict[str, list[str]]:
    """name -> lines (heading to END) of the top-level procedures of a text."""
    lines, out = text.split("\n"), {}
    for i, ln in enumerate(lines):
        m = re.match(r"PROCEDURE (\w+)\b", ln)
        if m:
            end = lines.index(f"END {m.group(1)} ;", i)
            out[m.group(1)] = lines[i:end + 1]
    return out


@pytest.fixture(params=CASES, ids=[f"{eq}-{'-'.join(map(str, kw.values())) or 'plain'}" for eq, kw in CASES])
def text(request, generated):
    eq, kw = request.param
    return generated(eq, "m2", **kw).text


def test_every_line_is_kept_once_in_order(text):
    imports, rest, files = split(text, "gen", ORIGIN)
    original = text.split("\n")
    moved = {}          # the line a moved procedure began on -> its lines
    for fname, body in files.items():
        if fname.endswith(".mod"):
            lines = body.split("\n")
            for k, ln in enumerate(lines):
                m = re.fullmatch(rf'#line (\d+) "{re.escape(ORIGIN)}"', ln)
                if m:
                    name = re.match(r"PROCEDURE (\w+)", lines[k + 1]).group(1)
                    moved[int(m.group(1))] = lines[k + 1:lines.index(f"END {name} ;", k) + 1]
    assert moved
    # the rest, each moved procedure put back where the rest's #line directive resumes, is the original
    rebuilt = []
    for ln in rest.split("\n"):
        m = re.fullmatch(rf'#line (\d+) "{re.escape(ORIGIN)}"', ln)
        if m is None:
            rebuilt.append(ln)
        elif int(m.group(1)) > 1:
            rebuilt += moved.pop(len(rebuilt) + 1)
            assert int(m.group(1)) == len(rebuilt) + 1
    assert rebuilt == original and not moved


def test_only_self_contained_coefficient_procedures_move(text):
    imports, rest, files = split(text, "gen", ORIGIN)
    top = set(_procedures(text)) | set(re.findall(r"^  (\w+) = ", text, re.M))
    for fname, body in files.items():
        if not fname.endswith(".mod"):
            continue
        for name, lines in _procedures(body).items():
            assert re.fullmatch(rf"PROCEDURE {name} \([\w, ]+: REAL; VAR \w+: ARRAY OF REAL\) ;", lines[0])
            code = re.sub(r"\(\*.*?\*\)", " ", "\n".join(ln for ln in lines[1:] if not ln.startswith("#")), flags=re.S)
            assert not (set(re.findall(r"[A-Za-z_]\w*", code)) & (top - {name})), name
    # what calls other generated names stays: the selection and time-of-contact entries
    for name, lines in _procedures(rest).items():
        assert name.endswith(("_coefficients", "_variant", "_toc")) or "_exact" in name or "_gap" in name \
            or not re.fullmatch(r"PROCEDURE \w+ \([\w, ]+: REAL; VAR \w+: ARRAY OF REAL\) ;", lines[0]), name


def test_parts_are_bounded_and_each_name_is_imported_from_its_part(text):
    imports, rest, files = split(text, "gen", ORIGIN)
    mods = sorted(f[:-4] for f in files if f.endswith(".mod"))
    assert sorted(f[:-4] for f in files if f.endswith(".def")) == mods
    assert len(imports) == len(mods)
    for imp in imports:
        m = re.fullmatch(r"FROM (\w+) IMPORT ([\w, ]+) ;", imp)
        assert m and m.group(1) in mods
        names = m.group(2).split(", ")
        body = files[f"{m.group(1)}.mod"]
        assert sorted(_procedures(body)) == sorted(names)
        assert sorted(re.findall(r"^PROCEDURE (\w+)", files[f"{m.group(1)}.def"], re.M)) == sorted(names)
        procs = _procedures(body).values()
        assert len(procs) == 1 or sum(len(p) + 1 for p in procs) <= PART_LINES
        for name in names:
            assert not re.search(rf"^PROCEDURE {name}\b", rest, re.M)


def test_a_text_with_nothing_to_move_is_left_as_it_is():
    text = "CONST\n  k = 1 ;\nPROCEDURE f (a: REAL; VAR coef: ARRAY OF REAL) ;\nBEGIN\n  coef[0] := a * k\nEND f ;\n"
    assert split(text, "gen", ORIGIN) == ([], text, {})


def test_split_files_puts_every_import_in_the_first_text(tmp_path, generated):
    for name, (eq, kw) in (("one.mxd", CASES[0]), ("two.mxd", CASES[3])):
        (tmp_path / name).write_text(generated(eq, "m2", **kw).text, encoding="utf-8")
    mods = split_files([str(tmp_path / "one.mxd"), str(tmp_path / "two.mxd")], str(tmp_path / "parts"),
                       str(tmp_path / "shim"))
    assert {m.rstrip("0123456789") for m in mods} == {"onePart", "twoPart"}
    first = (tmp_path / "shim" / "one.mxd").read_text(encoding="utf-8").split("\n")
    second = (tmp_path / "shim" / "two.mxd").read_text(encoding="utf-8")
    assert [ln.split()[1] for ln in first[:len(mods)]] == mods
    assert "IMPORT" not in re.sub(r"\(\*.*?\*\)", "", second, flags=re.S)
    for m in mods:
        assert (tmp_path / "parts" / f"{m}.mod").is_file() and (tmp_path / "parts" / f"{m}.def").is_file()
