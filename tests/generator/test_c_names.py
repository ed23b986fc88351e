"""Which names the generated C can take (max2code/targets/c.py).

A parameter may hide a function of the C library: in C an identifier
declared in a parameter list hides one declared at file scope, and gcc's
-Wshadow does not warn of it.  So a parameter is refused only when it is a
keyword, a macro or a type of the library, or a function the generated C
calls (taken from the printer and the templates); the equation's name, which
the generated C declares at file scope, is refused for every library
function too.  Proved by compiling: the generated C (double, float,
--exact, its header also as C++) with hypothesis-drawn accepted names of the
library as its parameters, warnings as errors and -Wshadow, in a
translation unit that includes the harness programs' headers first."""
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from max2code.generate.names import clash
from max2code.targets.c import LIBRARY, C

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
INCLUDE = ROOT / "runtimes" / "c" / "include"
FLAGS = ["-std=c11", "-D_GNU_SOURCE", "-Wall", "-Wextra", "-Werror", "-Wshadow", "-O2", "-ffp-contract=off"]
PRELUDE = "#include <stdio.h>\n#include <stdlib.h>\n#include <time.h>\n"     # as the harness programs
PLACEHOLDERS = [f"zq{k}" for k in range(1, 9)]
EQUATION = ('equation zqeq "placeholders"\n' + "".join(f"parameter {p}\n" for p in PLACEHOLDERS) +
            "begin\nzq1 + zq2*t + sin(zq3)*zq4*t^2 + cos(zq5)*t^3 + {last}*zq7*zq8*t^4 ;\nend\n")
NATURAL = ["y0", "y1", "j0", "j1", "yn", "jn", "gamma", "exp", "log", "pow", "round", "floor", "hypot", "atan2",
           "erf", "nan", "lgamma", "drem", "significand", "scalb", "index", "time", "clock", "rand", "abs", "div"]

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("g++") is None, reason="needs gcc and g++")


def c_clash(name: str, file_scope: bool) -> str | None:
    return C.reserved_as(name, file_scope)


def test_the_functions_the_generated_c_calls_come_from_the_printer_and_the_templates():
    called = dict(C.words)["a function the generated C calls"]
    assert {"sin", "cos", "sqrt", "fabs", "sinf", "cosf", "sqrtf", "fabsf", "m2c_smallest_root"} <= called
    assert not called & {"if", "switch", "return", "sizeof"}
    for name in ("sqrt", "fabs", "cosf"):
        assert clash(name, file_scope=False) and "a function the generated C calls" in clash(name, file_scope=False)


@pytest.mark.parametrize("name", ["NAN", "INFINITY", "M_PI", "HUGE_VAL", "isnan", "signbit", "fpclassify", "EOF",
                                  "RAND_MAX", "int8_t", "size_t", "double_t", "FILE", "sqrt", "fabs", "sin", "while"])
def test_macros_types_keywords_and_called_functions_are_refused_as_parameters(name):
    assert c_clash(name, file_scope=False), name


@pytest.mark.parametrize("name", NATURAL)
def test_library_functions_are_parameters_but_not_equations(name):
    assert name in LIBRARY["functions"], name
    assert c_clash(name, file_scope=False) is None, name
    assert "a function of the C library" in c_clash(name, file_scope=True), name


def test_y0_j0_y1_gamma_are_parameters_of_a_file(tmp_path, capsys):
    """The whole command: a file with these parameters generates (an equation named y0 does not)."""
    from max2code.cli import main
    src = tmp_path / "q.mxm"
    src.write_text("parameter y0\nparameter y1\nparameter j0\nparameter gamma\nbegin\ny0 + y1*t + j0*gamma*t^2;\nend\n")
    assert main(["--lang=c", str(src), "-q", "-o", str(tmp_path / "q.c")]) == 0, capsys.readouterr().err
    text = (tmp_path / "q.c").read_text()
    assert "double y0, double y1, double j0, double gamma" in text
    bad = tmp_path / "b.mxm"
    bad.write_text("equation y0\nparameter a\nbegin\na*t - 1;\nend\n")
    assert main(["--lang=c", str(bad), "-q"]) == 1
    assert "equation name 'y0' is reserved in c (a function of the C library" in capsys.readouterr().err


# ---- compiled ----

@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """The generated C of the placeholder equation: {kind: (file text, header text)}."""
    from max2code.cli import main
    d = tmp_path_factory.mktemp("cnames")
    out = {}
    for kind, last, args in (("double", "sqrt(zq6)", []), ("float", "sqrt(zq6)", ["--real=float"]),
                             ("exact", "zq6", ["--exact"])):
        src = d / f"{kind}.mxm"
        src.write_text(EQUATION.format(last=last))
        assert main(["--lang=c", str(src), "-q", "-o", str(d / f"{kind}.c"), *args]) == 0
        out[kind] = ((d / f"{kind}.c").read_text(), (d / f"{kind}.h").read_text())
    return out


def substitute(text: str, names: list[str]) -> str:
    for old, new in zip(PLACEHOLDERS, names):
        text = re.sub(rf"\b{old}\b", new, text)
    return text


def compile_all(where: Path, generated, names: list[str]) -> str:
    """gcc's and g++'s errors for the generated files with `names` as their parameters ('' when they compile)."""
    errors = []
    for kind, (code, header) in generated.items():
        (where / f"{kind}.c").write_text(substitute(code, names))
        (where / f"{kind}.h").write_text(substitute(header, names))
        (where / f"{kind}_tu.c").write_text(f'{PRELUDE}#include "{kind}.c"\n')
        (where / f"{kind}_h.cc").write_text(f'{PRELUDE}#include "{kind}.h"\n')
    units = [str(where / f"{k}_tu.c") for k in generated]
    r = subprocess.run(["gcc", *FLAGS, f"-I{INCLUDE}", "-c", *units], cwd=where, capture_output=True, text=True)
    errors.append(r.stderr if r.returncode else "")
    r = subprocess.run(["g++", "-std=c++17", "-Wall", "-Wextra", "-Werror", "-Wshadow", f"-I{INCLUDE}",
                        "-fsyntax-only", *[str(where / f"{k}_h.cc") for k in generated]],
                       cwd=where, capture_output=True, text=True)
    errors.append(r.stderr if r.returncode else "")
    return "".join(errors)


@pytest.mark.slow
@needs_gcc
def test_natural_names_compile(generated, tmp_path):
    for k in range(0, len(NATURAL), 8):
        names = (NATURAL[k:k + 8] + PLACEHOLDERS)[:8]
        assert compile_all(tmp_path, generated, names) == "", names


@pytest.mark.slow
@needs_gcc
@pytest.mark.parametrize("bad", ["sqrt", "NAN", "fabs"])
def test_a_refused_name_breaks_the_build(generated, tmp_path, bad):
    """The compile check can fail: a name the check refuses, planted, does not compile."""
    assert c_clash(bad, file_scope=False)
    assert compile_all(tmp_path, generated, [bad, *PLACEHOLDERS[1:]]) != ""
    assert compile_all(tmp_path, generated, ["zq0", *PLACEHOLDERS[1:]]) == ""


CANDIDATES = sorted(set().union(*LIBRARY.values(), *(names for _, names in C.words)))
ACCEPTED = [n for n in CANDIDATES if c_clash(n, file_scope=False) is None and clash(n, file_scope=False) is None]


def test_most_library_functions_are_accepted_as_parameters():
    accepted = set(ACCEPTED)
    assert len(accepted & LIBRARY["functions"]) > 0.8 * len(LIBRARY["functions"])
    assert not accepted & LIBRARY["macros"] and not accepted & LIBRARY["types"]


@pytest.mark.slow
@needs_gcc
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(names=st.lists(st.sampled_from(ACCEPTED), min_size=8, max_size=8, unique=True))
def test_every_accepted_name_compiles(generated, tmp_path, names):
    """Any 8 names the check accepts, drawn from the C library's names, are
    the parameters of generated C that compiles."""
    assert compile_all(tmp_path, generated, names) == "", names


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
