"""The build-cache checks that look at the files' stat instead of their bytes
(max2code/filestate.py) still see every change: a source edited to the same
size, a file added, different flags; a file changed in the last moments is
not trusted; and the simulator's key and the command's C tools follow their
sources through it (max2code/sim/simulate.py _build_key, max2code/sim/ctool.py)."""
import ctypes
import os
import shutil
import time

import pytest

from max2code import filestate
from max2code.paths import ROOT


def _later(seconds=60):
    """The clock `seconds` from now: a file's change time cannot be set back,
    so the tests move the clock that filestate compares it with instead."""
    t = time.time_ns() + seconds * 1_000_000_000
    return lambda: t


def test_recall_gives_the_digest_only_for_the_same_state(tmp_path, monkeypatch):
    a, b = tmp_path / "a.c", tmp_path / "b.c"
    a.write_text("int f(void) { return 1; }\n")
    b.write_text("x\n")
    memo = tmp_path / "memo"
    now = filestate.state([str(a), str(b)], "flags")
    monkeypatch.setattr(filestate, "_clock", _later())
    filestate.remember(memo, now, "D1")
    assert filestate.recall(memo, filestate.state([str(a), str(b)], "flags")) == "D1"
    assert filestate.recall(memo, filestate.state([str(a), str(b)], "other flags")) is None
    assert filestate.recall(memo, filestate.state([str(a)], "flags")) is None
    a.write_text("int f(void) { return 2; }\n")         # the same size
    assert filestate.recall(memo, filestate.state([str(a), str(b)], "flags")) is None
    assert filestate.state([str(a), str(tmp_path / "gone")], "flags") is None
    assert filestate.recall(memo, None) is None


def test_a_file_changed_just_now_is_not_remembered(tmp_path):
    a = tmp_path / "a.c"
    a.write_text("int f(void) { return 1; }\n")
    memo = tmp_path / "memo"
    filestate.remember(memo, filestate.state([str(a)]), "D1")
    assert not memo.exists()


def test_simulator_key_follows_its_sources(tmp_path, monkeypatch):
    from max2code.sim import simulate

    runtimes = tmp_path / "runtimes"
    shutil.copytree(ROOT / "runtimes" / "c", runtimes / "c", ignore=shutil.ignore_patterns("build", "target"))
    monkeypatch.setattr(simulate, "RUNTIMES", runtimes)
    monkeypatch.setattr(simulate, "BUILD", tmp_path / "build")
    (tmp_path / "build" / "sim" / "c" / "none-o4").mkdir(parents=True)
    monkeypatch.setattr(filestate, "_clock", _later())
    workdir, first = simulate._build_key("c", (), 4)
    assert (workdir / "inputs.state").exists()
    hashed = []
    real_recall = filestate.recall
    monkeypatch.setattr(filestate, "recall", lambda memo, now: hashed.append(memo) or real_recall(memo, now))
    assert simulate._build_key("c", (), 4)[1] == first
    source = next(p for p in sorted((runtimes / "c").rglob("*.c")) if p.name not in simulate.COMMAND_TOOLS)
    text = source.read_bytes()
    source.write_bytes(text[:-2] + (b"\n\n" if text[-2:] != b"\n\n" else b" \n"))     # the same size
    second = simulate._build_key("c", (), 4)[1]
    assert second != first
    (workdir / "inputs.state").unlink()
    assert simulate._build_key("c", (), 4)[1] == second        # what hashing the bytes gives
    (runtimes / "c" / "new.h").write_text("/* new */\n")
    assert simulate._build_key("c", (), 4)[1] not in (first, second)
    assert simulate._build_key("c", (), 5)[1] != simulate._build_key("c", (), 4)[1]
    assert hashed      # the memo was consulted every time


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_c_tool_is_rebuilt_when_its_source_changes(tmp_path, monkeypatch):
    from max2code.sim import ctool

    src = tmp_path / "m2c_probe.c"
    src.write_text("int probe(void) { return 1; }\n")
    monkeypatch.setattr(ctool, "BUILD", tmp_path / "build")
    monkeypatch.setattr(filestate, "_clock", _later())

    def value():
        tool = ctool.CTool(src, ["-O2", "-shared", "-fPIC"], "probe", ctypes.CDLL, [("probe", ctypes.c_int, [])])
        lib = tool.library()
        assert lib is not None, tool.why_not()
        return lib.probe(), tool.build()

    one, path1 = value()
    assert one == 1 and (tmp_path / "build" / "probe" / "source.state").exists()
    assert value() == (1, path1)
    src.write_text("int probe(void) { return 2; }\n")       # the same size
    two, path2 = value()
    assert two == 2 and path2 != path1
    os.unlink(tmp_path / "build" / "probe" / "source.state")
    assert value() == (2, path2)
