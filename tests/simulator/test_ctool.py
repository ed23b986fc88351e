"""The command's C tools (max2code/sim/ctool.py): old library folders, one per
edit of a source, are removed past KEEP, and never while another run holds
the lock (it may be about to load from one of them)."""
from __future__ import annotations

import ctypes
import fcntl
import os
from pathlib import Path
import subprocess
import sys

import pytest

from max2code.sim import ctool
from max2code.sim.ctool import CTool

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())


def tool(tmp_path, body="int answer(void) { return 42; }"):
    src = tmp_path / "tool.c"
    src.write_text(body + "\n")
    return CTool(src, ["-O1", "-shared", "-fPIC"], "tool", ctypes.CDLL, [("answer", ctypes.c_int, [])])


def old_folders(build, n):
    """n library folders of earlier sources, the first the oldest."""
    names = [f"{k:016x}" for k in range(1, n + 1)]
    for k, name in enumerate(names):
        d = build / "tool" / name
        d.mkdir(parents=True)
        (d / "libtool.so").write_bytes(b"old")
        os.utime(d, ns=(10**18 + k * 10**9, 10**18 + k * 10**9))
    return names


def folders(build):
    return sorted(p.name for p in (build / "tool").iterdir() if p.is_dir())


@pytest.fixture
def build(tmp_path, monkeypatch):
    monkeypatch.setattr(ctool, "BUILD", tmp_path / "build")
    return tmp_path / "build"


def test_old_library_folders_are_removed_past_keep(tmp_path, build):
    names = old_folders(build, 5)
    (build / "tool" / "notes").mkdir()      # not a library folder: left alone
    t = tool(tmp_path)
    assert t.library().answer() == 42
    current = os.path.basename(os.path.dirname(t.build()))
    assert folders(build) == sorted([current, "notes", *names[-(ctool.KEEP - 1):]])


def test_a_few_folders_stay(tmp_path, build):
    names = old_folders(build, ctool.KEEP - 1)
    t = tool(tmp_path)
    assert t.library().answer() == 42
    assert len(folders(build)) == ctool.KEEP and set(names) < set(folders(build))


def test_nothing_is_removed_while_another_run_holds_the_lock(tmp_path, build):
    """Another process between finding its folder and loading from it holds
    the lock shared: the pile stays (and this run's library loads), and the
    next run after it is gone removes it."""
    names = old_folders(build, 5)
    (build / "tool" / "lock").touch()
    holder = subprocess.Popen([sys.executable, "-c", "import fcntl, sys\n"
                               f"f = open({str(build / 'tool' / 'lock')!r})\n"
                               "fcntl.flock(f, fcntl.LOCK_SH)\nprint('held', flush=True)\nsys.stdin.read()"],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline() == "held\n"
        assert tool(tmp_path).library().answer() == 42
        assert set(names) < set(folders(build))
    finally:
        holder.communicate("", timeout=30)
    t = tool(tmp_path)
    assert t.library().answer() == 42
    assert len(folders(build)) == ctool.KEEP and names[0] not in folders(build)


def test_a_library_in_use_survives_its_folder_being_removed(tmp_path, build):
    """What makes removing after loading safe: a loaded library stays mapped
    when its file goes (POSIX)."""
    first = tool(tmp_path, "int answer(void) { return 7; }")
    lib = first.library()
    mine = os.path.basename(os.path.dirname(first.build()))
    for k in range(ctool.KEEP + 1):      # later edits of the source, each built by a later run
        assert tool(tmp_path, f"int answer(void) {{ return {k}; }}").library().answer() == k
    assert mine not in folders(build)
    assert lib.answer() == 7


def test_the_lock_is_released_after_loading(tmp_path, build):
    tool(tmp_path).library()
    with open(build / "tool" / "lock") as f:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)      # raises BlockingIOError if still held
