"""The seed files parse, in both dialects; the language's details."""
import os
from pathlib import Path

import pytest

from max2code.generate.mxm import parse_mxm, read_mxm

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


@pytest.mark.parametrize("rel", ["equations/circle-circle.mxm", "equations/point-line.mxm",
                                 "equations/paper/circle-circle.mxm", "equations/paper/point-line.mxm",
                                 "tests/data/planted-error.mxm"])
def test_seed_files_parse(rel):
    m = read_mxm(os.path.join(ROOT, rel))
    assert "t" in m.maxima_text


def test_paper_files_keep_their_header_and_blocks():
    m = read_mxm(os.path.join(ROOT, "equations/paper/circle-circle.mxm"))
    assert m.terms == 8 and m.dialect == "begin-end"
    assert [b.index for b in m.blocks if b.kind == "term"] == list(range(8))
    assert "X^4/24" in m.maxima_text and "findSmallestPositiveRoot" in m.blocks[-1].text


def test_original_dialect_brace_block_and_line_comments():
    text = "// header comment\npolynomial terms 2 // trailing\nterm 0 { a[0] := }\nterm 1 { a[1] := }\n{\n a + b*t;\n}\n"
    m = parse_mxm(text, "x.mxm")
    assert m.dialect == "brace" and m.maxima_text.strip() == "a + b*t;"
    assert m.maxima_span.line == 5 and m.maxima_span.column == 2


def test_begin_end_keeps_maxima_text_verbatim_with_positions():
    text = "equation foo \"doc\"\noption order = 6 \"n\"\nparameter a \"first\"\nbegin\n  /* end of story */ a*t;\nend\n"
    m = parse_mxm(text, "x.mxm")
    assert m.equation == "foo" and m.doc == "doc"
    assert m.options[0].name == "order" and m.options[0].value == 6
    assert m.parameters[0].doc == "first"
    assert m.maxima_text == "\n  /* end of story */ a*t;\n"
    assert (m.maxima_span.line, m.maxima_span.column) == (4, 6)


def test_nested_braces_in_blocks():
    m = parse_mxm("initialise { if (x) { y(); } }\nterm 0 { a = }\nbegin\nt;\nend\n", "x.mxm")
    assert m.blocks[0].text == " if (x) { y(); } "


def test_language_tagged_blocks_override_untagged():
    m = parse_mxm("term 0 { any }\nterm 0 for c { cee }\nbegin\nt;\nend\n", "x.mxm")
    assert [b.text for b in m.blocks_for("c")] == [" cee "]
    assert [b.text for b in m.blocks_for("python")] == [" any "]
