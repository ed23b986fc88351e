"""Unlucky or hostile text in a .mxm file (names, doc strings, the file's own
name) never gives wrong or broken code: a name no target or Maxima can take
is refused at its place, and doc strings and file names are escaped by each
target's printer so that every generated file still compiles or parses and
declares nothing more than the same file with plain text."""
import ast
import dataclasses
import functools
import os
from pathlib import Path
import re
import shutil
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from max2code.cli import main
from max2code.generate.derive import derive
from max2code.generate.mxm import parse_mxm
from max2code.generate.pipeline import GenerateRequest, generate
from max2code.targets import target
from max2code.toolchain.c import FLAGS

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def run(capsys, *argv):
    code = main(list(map(str, argv)))
    out, err = capsys.readouterr()
    return code, out, err


def error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "internal error" not in err and "Traceback" not in err, err
    return lines[0]


# ---- names --------------------------------------------------------------

@pytest.mark.parametrize("name,lang", [
    ("step", "maxima"), ("thru", "maxima"), ("linel", "maxima"), ("inf", "maxima"),
    ("sqrt", "c"), ("fabs", "c"), ("cosf", "c"), ("isnan", "c"), ("HUGE_VAL", "c"), ("EOF", "c"), ("size_t", "c"),
    ("INFINITY", "c"), ("NAN", "c"), ("M_PI", "c"), ("int8_t", "c"), ("linux", "c"), ("round", "python"),
    ("class", "c"), ("Vec", "rust"), ("Some", "rust"), ("sum", "python"), ("ValueError", "python"),
    ("WORD", "m2"), ("ELSIF", "m2")])
def test_reserved_parameter_names_the_language(tmp_path, capsys, name, lang):
    p = tmp_path / "p.mxm"
    p.write_text(f"parameter {name}\nparameter b\nbegin\n{name} + b*t;\nend\n")
    code, out, err = run(capsys, "--lang=python", p, "-q")
    line = error_line(err)
    assert code == 1 and out == ""
    assert line.startswith(f"{p}:1:11: error: parameter '{name}' is reserved in "), line
    assert lang in line.split("reserved in ", 1)[1].split(" (")[0].split(", "), line


def test_reserved_words_of_maxima_in_options_and_exact_arguments(tmp_path, capsys):
    p = tmp_path / "o.mxm"
    p.write_text("option step = 2\nbegin\na + step*t;\nend\n")
    code, _, err = run(capsys, "--lang=c", p, "-q")
    assert code == 1 and "option 'step' is reserved in maxima (a keyword" in error_line(err), err
    assert error_line(err).startswith(f"{p}:1:8: error: ")
    q = tmp_path / "x.mxm"
    q.write_text("exact S(w, for) { sin(w*t) }\nbegin\nS(w, f) := w*t;\na + S(b, c)*t;\nend\n")
    code, _, err = run(capsys, "--lang=c", q, "-q")
    assert code == 1 and "the argument 'for' of 'S' is reserved in maxima" in error_line(err), err


def test_symbol_outside_the_identifier_alphabet_is_refused_at_its_use(tmp_path, capsys):
    p = tmp_path / "s.mxm"
    p.write_text("begin\n/* x%y */\na + x%y*t;\nend\n")
    code, out, err = run(capsys, "--lang=c", p, "-q")
    line = error_line(err)
    assert code == 1 and out == ""
    assert line.startswith(f"{p}:3:5: error: the polynomial's symbol 'x%y' is not an identifier"), line


def test_reserved_symbol_without_declarations_is_refused_at_its_use(tmp_path, capsys):
    p = tmp_path / "s.mxm"
    p.write_text("begin\nq: 2$\na + fabs*t;\nend\n")
    code, _, err = run(capsys, "--lang=python", p, "-q")
    line = error_line(err)
    assert code == 1 and line.startswith(f"{p}:3:5: error: the polynomial's symbol 'fabs' is reserved in c "), line


# ---- error positions --------------------------------------------------------

def test_undeclared_name_is_reported_at_its_use(tmp_path, capsys):
    p = tmp_path / "u.mxm"
    p.write_text('parameter a "x"\nparameter b\nbegin\n/* c is not declared */\nq: "c"$\na + b*t + c*t^2;\nend\n')
    code, _, err = run(capsys, "--lang=c", p, "-q")
    line = error_line(err)
    assert code == 1 and line.startswith(f"{p}:6:11: error: the polynomial uses 'c'"), line


def test_unknown_option_is_an_error_of_the_command_line(tmp_path, capsys):
    p = tmp_path / "o.mxm"
    p.write_text("option order = 4\noption scale = 1\nbegin\na + order*t;\nend\n")
    code, out, err = run(capsys, "--lang=c", p, "-q", "-D", "ordr=6")
    line = error_line(err)
    assert code == 1 and out == ""
    assert line.startswith("max2code: error: -D ordr=6: "), line
    assert "no option 'ordr'" in line and "order, scale" in line, line


# ---- doc strings and file names: concrete cases -----------------------------

INJECT_MXM = ('equation e "{doc}"\nparameter a "{doc}"\nparameter b\nbegin\na + b*t + t^2;\nend\n')


def _gcc_syntax(path, *extra):
    return subprocess.run([*FLAGS, "-fsyntax-only", *extra, str(path)], capture_output=True, text=True)


@pytest.mark.slow
def test_c_doc_cannot_close_the_comment(tmp_path, capsys):
    p = tmp_path / "e.mxm"
    p.write_text(INJECT_MXM.format(doc="x */ int injected; /* y"))
    out = tmp_path / "e.c"
    code, _, err = run(capsys, "--lang=c", p, "-q", "-o", out, "--no-header")
    assert code == 0, err
    r = _gcc_syntax(out)
    assert r.returncode == 0, r.stderr
    assert "injected" not in _c_code(out.read_text())


@pytest.mark.slow
def test_m2_doc_cannot_close_the_comment(tmp_path, capsys):
    p = tmp_path / "e.mxm"
    p.write_text(INJECT_MXM.format(doc="x *) VAR injected: INTEGER ; (* y"))
    code, out, err = run(capsys, "--lang=m2", p, "-q")
    assert code == 0, err
    assert "injected" not in _m2_code(out)
    if shutil.which("gm2"):
        _gm2_syntax(tmp_path, out)


def test_python_doc_with_backslash_escapes_compiles(tmp_path, capsys):
    p = tmp_path / "e.mxm"
    p.write_text(INJECT_MXM.format(doc=r"see \N and \x and a trailing backslash \ "))
    code, out, err = run(capsys, "--lang=python", p, "-q")
    assert code == 0, err
    tree = ast.parse(out)
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "e")
    assert ast.get_docstring(fn, clean=False).startswith(r"see \N and \x and a trailing backslash \ .")


@pytest.mark.slow
def test_file_name_with_a_line_end(tmp_path, capsys):
    p = tmp_path / 'we"ird\nimport os; os.system("false") # *\\ (* ??=.mxm'
    p.write_text(INJECT_MXM.format(doc="plain"))
    code, out, err = run(capsys, "--lang=python", p, "-q")
    assert code == 0, err
    tree = ast.parse(out)
    assert not any(isinstance(n, ast.Import) and n.names[0].name == "os" for n in ast.walk(tree))
    outc = tmp_path / "e.c"
    code, _, err = run(capsys, "--lang=c", p, "-q", "-o", outc, "--no-header")
    assert code == 0, err
    assert _gcc_syntax(outc).returncode == 0
    # the #line directives name the .mxm file exactly: a compiler message quotes it back
    bad = tmp_path / "bad.c"
    bad.write_text(outc.read_text().replace("coef[0] = ", "coef[0] = undeclared_name + ", 1))
    r = _gcc_syntax(bad)
    assert r.returncode != 0 and f"{p}:5:" in r.stderr.replace("\\n", "\n").replace('\\"', '"'), r.stderr


# ---- doc strings and file names: properties ---------------------------------

BASE_MXM = 'equation hostile "plain"\nparameter a "plain"\nparameter b "plain"\nbegin\na + b*t + a*t^2;\nend\n'


@functools.lru_cache(maxsize=1)
def _derivation():
    return derive(parse_mxm(BASE_MXM, "plain.mxm"))


def _render(lang: str, doc: str, path: str, out_name: str, header: bool = False):
    d = _derivation()
    mod = dataclasses.replace(d.module, doc=doc, path=path,
                              parameters=tuple(dataclasses.replace(p, doc=doc) for p in d.module.parameters))
    req = GenerateRequest(path=path, lang=lang, out_name=out_name, header=header)
    return generate(dataclasses.replace(d, module=mod), req)


def _c_code(text: str) -> str:
    """C text without comments (the C preprocessor's view) and with the #line file names dropped."""
    r = subprocess.run(["gcc", "-fpreprocessed", "-E", "-P", "-x", "c", "-"], input=text, capture_output=True,
                       text=True, errors="surrogateescape")
    assert r.returncode == 0, r.stderr
    return " ".join(re.sub(r'(?m)^#line \d+ ".*"$', "#line", r.stdout).split())


def _m2_code(text: str) -> str:
    """Modula-2 text without its (nesting) comments and with the #line file names dropped
    (the C preprocessor of gm2 -fcpp reads those lines, as C)."""
    text = re.sub(r'(?m)^#line \d+ ".*"$', "#line", text)
    out, depth, i = [], 0, 0
    while i < len(text):
        if text.startswith("(*", i):
            depth, i = depth + 1, i + 2
        elif depth and text.startswith("*)", i):
            depth, i = depth - 1, i + 2
        else:
            if not depth:
                out.append(text[i])
            i += 1
    assert depth == 0, "a comment is not closed"
    return " ".join("".join(out).split())


def _rust_code(text: str) -> str:
    return " ".join(re.sub(r"//[^\n]*", "", text).split())


def _gm2_syntax(tmp_path, text: str) -> None:
    (tmp_path / "gen.mxd").write_text(text, encoding="utf-8", errors="surrogateescape")
    (tmp_path / "W.mod").write_text('MODULE W ;\nFROM RealMath IMPORT sin, cos ;\n#include "gen.mxd"\nBEGIN\nEND W.\n')
    r = subprocess.run(["gm2", "-fiso", "-fcpp", "-fsyntax-only", f"-I{tmp_path}", str(tmp_path / "W.mod")],
                       capture_output=True, text=True, errors="replace")
    assert r.returncode == 0, r.stderr


PAYLOADS = ["*/", "/*", "(*", "*)", "//", "\n", "\r", "\r\n", "\u2028", "\x00", "\x0b", "\x0c", "\x85", '"', '"""',
            "'", "\\", "\\N", "\\x", "??/", "#", "#line 1", "```", "    ", "\u202e", "\u2066", "\udc80", "\ud800",
            "é", "\U0001f600", "*/ int injected; /*", "*) VAR injected: INTEGER ; (*",
            '"""\nimport os\n"""', "\nfn injected() {}\n"]
hostile = st.lists(st.one_of(st.text(max_size=6), st.sampled_from(PAYLOADS)), max_size=6).map("".join)
SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@functools.lru_cache(maxsize=None)
def _baseline(lang: str) -> str:
    return _render(lang, "plain", "plain.mxm", "plain.out").text


@pytest.mark.slow
@SETTINGS
@given(doc=hostile, path=hostile)
def test_python_doc_and_path_property(doc, path):
    text = _render("python", doc, path, "out.py").text
    tree = ast.parse(text)                      # a SyntaxError fails the test
    compile(text, "out.py", "exec")
    base = ast.parse(_baseline("python"))
    assert [type(n).__name__ for n in ast.walk(tree)] == [type(n).__name__ for n in ast.walk(base)]
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef))
    assert ast.get_docstring(fn, clean=False).startswith((doc or "hostile") + ".")   # the doc reads back as written


@pytest.mark.slow
@SETTINGS
@given(doc=hostile, path=hostile, out_name=hostile)
def test_c_doc_and_path_property(tmp_path_factory, doc, path, out_name):
    g = _render("c", doc, path, out_name or "x", header=True)
    assert _c_code(g.text) == _c_code(_baseline("c"))
    d = tmp_path_factory.mktemp("c")
    (d / "gen.c").write_text(g.text, encoding="utf-8", errors="surrogateescape")
    (d / "gen.h").write_text(g.header, encoding="utf-8", errors="surrogateescape")
    for f in ("gen.c", "gen.h"):
        r = _gcc_syntax(d / f)
        assert r.returncode == 0, r.stderr


@pytest.mark.slow
@SETTINGS
@given(doc=hostile, path=hostile, out_name=hostile)
def test_m2_doc_and_path_property(tmp_path_factory, doc, path, out_name):
    text = _render("m2", doc, path, out_name or "x").text
    assert _m2_code(text) == _m2_code(_baseline("m2"))
    assert "/*" not in re.sub(r"(?m)^#line .*$", "", text)     # gm2 -fcpp would read it as a C comment
    if shutil.which("gm2") and len(doc) % 5 == 0:     # gm2 is slow: a fifth of the examples
        _gm2_syntax(tmp_path_factory.mktemp("m2"), text)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(doc=hostile, path=hostile)
def test_rust_doc_and_path_property(doc, path):
    text = _render("rust", doc, path, "out.rs").text
    assert _rust_code(text) == _rust_code(_baseline("rust"))
    for line in text.splitlines():
        assert line.isprintable(), line       # a comment cannot end early, nor hold what rustc denies
        if line.startswith("///"):
            assert not re.match(r"/// ?\s{0,3}(```|~~~)", line)   # no Markdown fence: no doctest


@pytest.mark.slow
@pytest.mark.skipif(not shutil.which("rustc"), reason="needs rustc")
@pytest.mark.parametrize("doc", ["x */ fn injected() {} /*", "line\nfn injected() {}", "\u202e\x00 ``` \\"])
def test_rust_doc_compiles(tmp_path, doc):
    text = _render("rust", doc, doc, "out.rs").text
    (tmp_path / "gen.rs").write_text(text, encoding="utf-8", errors="surrogateescape")
    r = subprocess.run(["rustc", "--edition", "2021", "--crate-type=lib", "--emit=metadata", "-D", "warnings",
                        "-o", str(tmp_path / "gen.rmeta"), str(tmp_path / "gen.rs")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


EXACT_MXM = """parameter a "line end"  : body 1 position
parameter b "its velocity" : body 1 velocity
parameter d "orbit radius" : body 1 orbit_radius
parameter e "angular velocity" : body 1 angular_velocity
parameter f "phase" : body 1 phase
parameter g "point" : body 2 position
exact SIN(w, phi) { sin(w*t /* a /* b */ int injected; (* *) // c
import injected */ + phi) }
shift a { a + b*t }
shift f { f + e*t }
begin
C(X) := 1 - X^2/2 $
S(X) := X - X^3/6 $
SIN(w, phi) := sin(phi)*C(w*t) + cos(phi)*S(w*t) $
a + b*t + d*SIN(e, f) - g ;
end
"""


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["c", "m2", "python", "rust"])
def test_exact_text_in_the_header_comment(tmp_path, lang):
    """The `exact` declaration's Maxima text (a comment, a line end) is quoted in a comment of the output."""
    from max2code.generate.pipeline import generate_file
    p = tmp_path / "eq.mxm"
    p.write_text(EXACT_MXM)
    text = generate_file(GenerateRequest(path=str(p), lang=lang, exact=True, out_name="generated")).text
    assert "Exact motion" in text and "injected" in text
    if lang == "python":
        ast.parse(text)
    elif lang == "c":
        (tmp_path / "gen.c").write_text(text)
        assert "injected" not in _c_code(text)
        r = _gcc_syntax(tmp_path / "gen.c", f"-I{ROOT}/runtimes/c/include")
        assert r.returncode == 0, r.stderr
    elif lang == "m2":
        assert "injected" not in _m2_code(text) and "/*" not in text
    else:
        assert "injected" not in _rust_code(text)
