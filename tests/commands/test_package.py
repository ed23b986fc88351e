"""The package as a user installs it: the wheel carries the templates,
equations, examples, runtime sources and conformance cases, and from an
empty folder `max2code` generates all four languages, simulates an example
and runs the Python conformance cases; runtime builds go to the user cache,
never into site-packages or the current folder."""
from __future__ import annotations

import os
import subprocess
import zipfile

import pytest

from max2code import paths

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def sh(cmd: str, cwd, env, timeout=900) -> str:
    r = subprocess.run(["bash", "-euo", "pipefail", "-c", cmd], cwd=cwd, env=env, capture_output=True, text=True,
                       timeout=timeout)
    assert r.returncode == 0, f"{cmd}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r.stdout


def test_the_wheel_carries_the_data(installed):
    venv, _ = installed
    wheel = next((venv.parent / "wheels").glob("max2code-*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    tracked = subprocess.run(["git", "ls-files", *paths.DATA_FOLDERS], cwd=paths.ROOT, capture_output=True,
                             text=True, check=True).stdout.split()
    assert len(tracked) > 100
    missing = [f for f in tracked if f"max2code/_data/{f}" not in names]
    assert not missing, missing[:10]
    assert "max2code/generate/grammar/mxm.lark" in names or any(n.endswith(".lark") for n in names)
    assert "max2code_rt/roots.py" in names


def test_installed_package_works_from_an_empty_folder(installed, tmp_path):
    venv, env = installed
    work = tmp_path / "empty"
    work.mkdir()
    where = sh("python -c 'import max2code, max2code.paths as p; print(max2code.__file__); print(p.ROOT); "
               "print(p.BUILD)'", work, env).split("\n")
    assert where[0].startswith(str(venv)), where        # the wheel's package, not this checkout
    assert where[1].endswith(os.path.join("max2code", "_data")), where
    cache = os.environ.get("MAX2CODE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "max2code")
    assert where[2].startswith(os.path.join(cache, "build", "0.1.0-")), where
    eq = sh("max2code bundled equations", work, env).strip()
    # point-line: the bundled equation quickest to generate (a second each, circle-circle takes ten)
    for lang, ext in (("c", "c"), ("m2", "mxd"), ("python", "py"), ("rust", "rs")):
        sh(f"max2code --lang={lang} -q {eq}/point-line.mxm -o pl.{ext}", work, env)
        text = (work / f"pl.{ext}").read_text(encoding="utf-8")
        assert len(text) > 5000 and "point_line_toc" in text, (lang, len(text))
    assert (work / "pl.h").exists()        # the C header, next to pl.c
    ex = sh("max2code bundled examples", work, env).strip()
    for lang in ("python", "c"):
        sh(f"max2code simulate --lang {lang} {ex}/newtons-cradle.json -o cradle-{lang}.jsonl", work, env)
    assert sh("tail -n 1 cradle-python.jsonl", work, env).startswith('{"kind":"stats"')
    out = sh("max2code conformance --lang python -q", work, env)
    counts = [int(line.split()[1]) for line in out.splitlines() if line.startswith("[python]") and " cases: " in line]
    assert counts and counts[0] > 0, out
    assert "conformance: OK" in out
    # nothing was built in the current folder nor in site-packages
    assert sorted(p.name for p in work.iterdir()) == sorted(
        ["pl.c", "pl.h", "pl.mxd", "pl.py", "pl.rs", "cradle-python.jsonl", "cradle-c.jsonl"])
    data = where[1]
    assert not [p for p in os.listdir(os.path.join(data, "runtimes", "c")) if p not in os.listdir(paths.RUNTIMES / "c")]
    assert not os.path.exists(os.path.join(os.path.dirname(data), "build"))


def test_an_empty_case_file_is_an_error(installed, tmp_path):
    _, env = installed
    (tmp_path / "none.jsonl").write_text("")
    r = subprocess.run(["max2code", "conformance", "--lang", "python", "--cases", "none.jsonl"], cwd=tmp_path,
                       env=env, capture_output=True, text=True)
    assert r.returncode == 1 and "OK" not in r.stdout
    assert r.stderr.strip() == 'none.jsonl: error: no cases in the file (expected JSON lines {"id", "op", ...})'


@pytest.mark.parametrize("flag,expect", [([], True), (["--no-header"], False)])
def test_c_header_switch(installed, tmp_path, flag, expect):
    _, env = installed
    eq = sh("max2code bundled equations", tmp_path, env).strip()
    sh(f"max2code --lang=c -q {' '.join(flag)} {eq}/point-line.mxm -o pl.c", tmp_path, env)
    assert (tmp_path / "pl.h").exists() == expect
