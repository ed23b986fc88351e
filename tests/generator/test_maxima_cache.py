"""The Maxima result cache: its key covers what can change Maxima's answer
(init files, the files the text reads), a text whose reads cannot be known
is never cached, and a damaged entry is recomputed, with a note."""
import json

import pytest

from max2code.generate.derive import derive
from max2code.generate.maxima import inputs_of
from max2code.generate.mxm import parse_mxm


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("MAX2CODE_CACHE", str(d))
    monkeypatch.setenv("MAXIMA_USERDIR", str(tmp_path / "userdir"))
    (tmp_path / "userdir").mkdir()
    monkeypatch.chdir(tmp_path)
    return d


def _poly(text: str):
    d = derive(parse_mxm(text, "c.mxm"))
    return d.maxima_text, d.maxima.cached


def test_an_edited_init_file_is_not_ignored(tmp_path, cache):
    init = tmp_path / "userdir" / "maxima-init.mac"
    init.write_text("k0: 2$\n")
    text = "begin\na + k0*t;\nend\n"
    assert _poly(text) == ("2*t+a", False)
    assert _poly(text) == ("2*t+a", True)
    init.write_text("k0: 3$\n")
    assert _poly(text) == ("3*t+a", False)


def test_an_edited_loaded_file_is_not_ignored(tmp_path, cache):
    lib = tmp_path / "lib.mac"
    inner = tmp_path / "inner.mac"
    lib.write_text(f'load("{inner}")$\nk1: 5$\n')
    inner.write_text("k2: 7$\n")
    text = f'begin\nload("{lib}")$\na + k1*t + k2*t^2;\nend\n'
    assert _poly(text) == ("7*t^2+5*t+a", False)
    assert _poly(text)[1] is True
    inner.write_text("k2: 8$\n")          # a file the loaded file loads
    assert _poly(text) == ("8*t^2+5*t+a", False)


def test_reads_that_cannot_be_known_are_not_cached(tmp_path, cache):
    (tmp_path / "lib.mac").write_text("k1: 5$\n")
    text = f'begin\nload(sconcat("{tmp_path}/li", "b.mac"))$\na + k1*t;\nend\n'
    assert _poly(text) == ("5*t+a", False)
    assert _poly(text) == ("5*t+a", False)
    assert "by an expression" in inputs_of([text])
    assert "system" in inputs_of(['x: system("true")$'])
    assert "Lisp" in inputs_of([":lisp (print 1)"])
    assert inputs_of(['/* load("x") */ s: "load(y)"$ a;']) == {}


def test_a_damaged_entry_is_a_miss(tmp_path, cache, capsys):
    text = "begin\na + 4*t;\nend\n"
    assert _poly(text) == ("4*t+a", False)
    entries = sorted(cache.glob("*.json"))
    assert entries
    for e in entries:                    # edit every entry's result, leave its digest
        data = json.loads(e.read_text())
        data["items"] = {k: v.replace("4", "5") for k, v in data["items"].items()}
        e.write_text(json.dumps(data))
    capsys.readouterr()
    assert _poly(text) == ("4*t+a", False)
    assert "is damaged; Maxima runs again" in capsys.readouterr().err
    assert _poly(text) == ("4*t+a", True)
