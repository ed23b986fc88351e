"""The harness build cache (max2code/toolchain/harness.py, compile_harness):
a harness built once is copied, not built again, wherever its folder is;
a change to any input (a source's bytes, a command, a file a command names)
builds anew; a build that fails is not kept."""
import os
import subprocess

import pytest

from max2code.toolchain import harness as H


@pytest.fixture()
def build_dir(tmp_path, monkeypatch):
    d = tmp_path / "build"
    monkeypatch.setattr(H.paths, "build_dir", lambda: d)
    return d


def workdir(base, name, text="int main(void) { return 42; }\n"):
    d = base / name
    d.mkdir()
    (d / "prog.c").write_text(text)
    return str(d)


def cmds(wd, *extra):
    return [["gcc", "-O1", *extra, os.path.join(wd, "prog.c"), "-o", os.path.join(wd, "prog")]]


def exit_code(wd):
    return subprocess.run([os.path.join(wd, "prog")]).returncode


def test_a_built_harness_is_copied_into_another_folder(tmp_path, build_dir, monkeypatch):
    a = workdir(tmp_path, "a")
    H.compile_harness(cmds(a), a, timeout=60)
    assert exit_code(a) == 42
    (entry,) = [p for p in (build_dir / "harness").iterdir() if p.is_dir()]
    assert sorted(p.name for p in entry.iterdir()) == ["harness-key", "prog"]
    # the same build elsewhere runs no command: the program comes from the entry
    ran = []
    real = subprocess.run
    monkeypatch.setattr(H.subprocess, "run", lambda cmd, *a, **k: ran.append(cmd) or real(cmd, *a, **k))
    b = workdir(tmp_path, "b")
    H.compile_harness(cmds(b), b, timeout=60)
    assert [c for c in ran if c[0] == "gcc"] == [] and exit_code(b) == 42


@pytest.mark.parametrize("change", ["source", "command", "named file"])
def test_any_changed_input_builds_anew(tmp_path, build_dir, change):
    a = workdir(tmp_path, "a")
    H.compile_harness(cmds(a), a, timeout=60)
    if change == "source":
        b = workdir(tmp_path, "b", "int main(void) { return 7; }\n")
        commands, expect = cmds(b), 7
    elif change == "command":
        b = workdir(tmp_path, "b")
        commands, expect = cmds(b, "-O0"), 42
    else:       # a file outside the folder that a command names (as a runtime library is named)
        lib = tmp_path / "lib.c"
        lib.write_text("int unused_a(void) { return 1; }\n")
        b = workdir(tmp_path, "b")
        commands = [["gcc", "-O1", os.path.join(b, "prog.c"), str(lib), "-o", os.path.join(b, "prog")]]
        H.compile_harness(commands, b, timeout=60)
        lib.write_text("int unused_b(void) { return 2; }\n")
        c = workdir(tmp_path, "c")
        commands = [["gcc", "-O1", os.path.join(c, "prog.c"), str(lib), "-o", os.path.join(c, "prog")]]
        b, expect = c, 42
    H.compile_harness(commands, b, timeout=60)
    assert exit_code(b) == expect
    entries = [p for p in (build_dir / "harness").iterdir() if p.is_dir()]
    assert len(entries) == (3 if change == "named file" else 2)


def test_a_failed_build_is_not_kept(tmp_path, build_dir):
    a = workdir(tmp_path, "a", "int main(void) { return }\n")
    with pytest.raises(H.HarnessBuildError):
        H.compile_harness(cmds(a), a, timeout=60)
    assert not [p for p in (build_dir / "harness").iterdir() if p.is_dir()]
