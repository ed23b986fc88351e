"""The harness build cache (max2code/toolchain/harness.py, compile_harness):
a harness built once is copied, not built again, wherever its folder is;
a change to any input (a source's bytes, a command, a file a command names)
builds anew; a build that fails is not kept; and build_harness makes one
program for every mode (entry) of a generated file."""
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


@pytest.mark.slow       # builds the C runtime library (on first use) and a harness
def test_one_program_serves_every_mode_of_a_generated_file(tmp_path, build_dir, generated, monkeypatch):
    """build_harness compiles one program per generated file, its mode chosen
    at run time: the coefficients, the selection entry and the time of contact
    of the same file are one build (one cache entry, no second compile), and
    each mode answers as its own entry does."""
    import random

    from max2code_rt.roots import smallest_root
    from test_generated_code import line_params

    g = generated("point-line", "c")
    ran = []
    real = subprocess.run
    monkeypatch.setattr(H.subprocess, "run", lambda cmd, *a, **k: ran.append(cmd) or real(cmd, *a, **k))
    full = H.build_harness("c", g, str(tmp_path / "full"))
    entry = H.build_harness("c", g, str(tmp_path / "entry"), mode="entry")
    toc = H.build_harness("c", g, str(tmp_path / "toc"), mode="toc")
    assert len([c for c in ran if c[0] == "gcc"]) == 1
    assert len([p for p in (build_dir / "harness").iterdir() if p.is_dir()]) == 1
    rng = random.Random(17)
    sets = [[line_params(rng)[n] for n in g.function.params] for _ in range(40)]
    coefs = full.evaluate(sets)
    picked = entry.evaluate(sets)
    contacts = toc.evaluate([s + [0.0, 10.0] for s in sets])
    assert len(coefs) == len(picked) == len(contacts) == len(sets)
    found = 0
    for c, e, (status, t) in zip(coefs, picked, contacts):
        assert len(c) == g.function.degree + 1
        # no switch's parameters are zero: the selection takes the full variant, whose coefficients these are
        assert e == [float(g.function.degree)] + c
        want = smallest_root(c, 0.0, 10.0)
        assert (status == 1.0) == (want is not None) and status in (0.0, 1.0)
        if want is not None:
            found += 1
            assert abs(t - want) <= 1e-12 * abs(want) + 1e-15, (t, want)
    assert found >= 5
    # a mode the program does not have is refused, by the program and by build_harness
    assert real(full.run_cmd, input="3\n" + " ".join(map(repr, sets[0])) + "\n", capture_output=True,
                text=True).returncode != 0
    with pytest.raises(ValueError, match="mode"):
        H.build_harness("c", g, str(tmp_path / "other"), mode="exact")
