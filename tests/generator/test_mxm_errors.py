"""Every malformed input gives FILE:LINE:COL and a non-zero exit, never a traceback."""
import os
import re
import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow      # runs the command (and Maxima) in a process of its own per case

OK_TAIL = "begin\na + b*t + c*t^2;\nend\n"

# (name, .mxm text, expected line, expected column or None, words the message must contain)
CASES = [
    ("empty-file", "", 1, 1, "empty file"),
    ("only-comment", "// nothing here\n", 1, 1, "empty file"),
    ("missing-brace", "polynomial terms 3\ninitialise {\n  VAR t: REAL ;\n" + OK_TAIL, 2, 12, "no matching '}'"),
    ("wrong-term-order", "polynomial terms 3\nterm 0 { a[0] := }\nterm 2 { a[2] := }\nterm 1 { a[1] := }\n" + OK_TAIL, 3, 6, "out of order"),
    ("unknown-keyword", "polynomal terms 3\n" + OK_TAIL, 1, 1, "unexpected 'polynomal'"),
    ("terms-not-number", "polynomial terms many\n" + OK_TAIL, 1, 18, "whole number"),
    ("begin-without-end", "polynomial terms 3\nbegin\na + t;\n", 2, 1, "no matching 'end'"),
    ("no-maxima-text", "polynomial terms 3\nterm 0 { x }\n", 2, 13, "unexpected end of file"),
    ("header-after-block", "term 0 { a := }\npolynomial terms 1\n" + OK_TAIL, 2, 1, "unexpected 'polynomial'"),
    ("maxima-syntax-error", "begin\nx: a + b*t ;\ny: (x + ;\nx;\nend\n", 3, 1, "Maxima syntax error"),
    ("maxima-runtime-error", "begin\nx: 1/0 ;\nx*t;\nend\n", 2, 1, "Maxima error"),
    ("maxima-question", "begin\nintegrate(1/(s^2+k), s) ;\nend\n", 2, 1, "Maxima asked"),
    ("unterminated-statement", "begin\nx: a + t ;\nx^2 + b\nend\n", 3, 1, "not ended by ';'"),
    ("unterminated-comment", "begin\n/* open\na + t;\nend\n", 2, 1, "unterminated comment"),
    ("unterminated-string", "begin\nprint(\"oops) ;\na+t;\nend\n", 2, 7, "unterminated string"),
    ("not-a-polynomial", "begin\na + sin(t) ;\nend\n", 2, 1, "not a polynomial in t"),
    ("division-by-t", "begin\na + b/t ;\nend\n", 2, 1, "negative power of t"),
    ("no-t", "begin\na + b ;\nend\n", 2, 1, "does not depend on t"),
    ("terms-disagree", "polynomial terms 5\n" + OK_TAIL, 1, 18, "disagrees with Maxima"),
    ("term-blocks-vs-header", "polynomial terms 3\nterm 0 { x }\nterm 1 { y }\n" + OK_TAIL, 1, 18, "2 term blocks"),
    ("duplicate-parameter", "parameter a\nparameter a\n" + OK_TAIL, 2, 11, "declared twice"),
    ("undeclared-symbol", "parameter a\nparameter b\n" + OK_TAIL, 4, 11, "'c'"),
    ("variable-as-parameter", "parameter t\n" + OK_TAIL, 1, 11, "polynomial's variable"),
    ("initialise-after-term", "term 0 { x }\ninitialise { y }\n" + OK_TAIL, 2, 13, "before the 'term'"),
    ("brace-dialect-unbalanced", "term 0 { x }\n{\n a + t;\n", 2, 1, "no matching '}'"),
]


def run_cli(path, *extra):
    return subprocess.run([sys.executable, "-m", "max2code", "--lang=c", str(path), "-o", "-", "-q", *extra],
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("name,text,line,col,words", CASES, ids=[c[0] for c in CASES])
def test_malformed_input_names_file_line_column(tmp_path, name, text, line, col, words):
    path = tmp_path / f"{name}.mxm"
    path.write_text(text)
    proc = run_cli(path)
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    m = re.match(rf"^{re.escape(str(path))}:(\d+):(\d+): error: (.*)$", proc.stderr.strip().splitlines()[-1])
    assert m, proc.stderr
    assert int(m.group(1)) == line, proc.stderr
    if col is not None:
        assert int(m.group(2)) == col, proc.stderr
    assert words in m.group(3), proc.stderr


def test_missing_file_and_bad_option(tmp_path):
    proc = run_cli(tmp_path / "nope.mxm")
    assert proc.returncode != 0 and "nope.mxm: error: no such file" in proc.stderr
    path = tmp_path / "ok.mxm"
    path.write_text("option order = 4\n" + OK_TAIL)
    proc = run_cli(path, "-D", "speed=3")
    assert proc.returncode != 0 and "no option 'speed'" in proc.stderr and "Traceback" not in proc.stderr


def test_not_utf8(tmp_path):
    path = tmp_path / "bin.mxm"
    path.write_bytes(b"begin\n\xff\xfe a+t;\nend\n")
    proc = run_cli(path)
    assert proc.returncode != 0 and "not UTF-8" in proc.stderr


def test_missing_maxima_is_explained(tmp_path, monkeypatch):
    path = tmp_path / "ok.mxm"
    path.write_text(OK_TAIL)
    # no Maxima on PATH: how to install it
    empty = tmp_path / "empty-bin"
    empty.mkdir()
    env = dict(os.environ, PATH=str(empty), MAX2CODE_CACHE=str(tmp_path / "cache"))
    env.pop("MAX2CODE_MAXIMA", None)
    proc = subprocess.run([sys.executable, "-m", "max2code", "--lang=c", str(path), "-q"],
                          capture_output=True, text=True, env=env)
    assert proc.returncode == 1
    assert "apt-get install maxima" in proc.stderr and "Traceback" not in proc.stderr
    # a wrong MAX2CODE_MAXIMA is named as such, not "not found on PATH"
    for bad, why in ((tmp_path / "no-maxima-here", "does not exist"), (tmp_path, "is a folder"), (path, "is not executable")):
        env = dict(os.environ, MAX2CODE_MAXIMA=str(bad), MAX2CODE_CACHE=str(tmp_path / "cache"))
        proc = subprocess.run([sys.executable, "-m", "max2code", "--lang=c", str(path), "-q"],
                              capture_output=True, text=True, env=env)
        assert proc.returncode == 1, proc.stderr
        assert f"MAX2CODE_MAXIMA={bad}: {why}" in proc.stderr and "PATH" not in proc.stderr.split(why)[0], proc.stderr
