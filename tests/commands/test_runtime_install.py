"""`max2code runtime c --install PREFIX` (max2code/toolchain/c.py
install_runtime): the pkg-config file it installs names the prefix of this
install, also when the same build folder installed to another prefix before
(make remakes m2c.pc only when the Makefile changed, so install_runtime
removes it first)."""
from __future__ import annotations

import subprocess

from max2code.toolchain import c


def test_an_install_to_another_prefix_writes_its_pkg_config_file_again(tmp_path, monkeypatch):
    """The install's make is run for its m2c.pc only (the file the prefix is
    written into; the libraries' compilation is the consumers' test's), with
    the install's own BUILD and PREFIX arguments."""
    build = tmp_path / "build"
    monkeypatch.setattr(c, "BUILD", build)
    made = []

    def pc_only(cmd, cwd):
        assert cmd[-1] == "install", cmd
        target = next(a for a in cmd if a.startswith("BUILD=")).removeprefix("BUILD=") + "/m2c.pc"
        subprocess.run([*cmd[:-1], target], cwd=cwd, check=True, capture_output=True, text=True)
        made.append(next(a for a in cmd if a.startswith("PREFIX=")))
        return ""

    monkeypatch.setattr(c, "run", pc_only)
    pc = build / "c-install" / "m2c.pc"
    for prefix in (tmp_path / "first", tmp_path / "second"):
        c.CToolchain().install_runtime(str(prefix))
        assert pc.read_text().splitlines()[0] == f"prefix={prefix}"
    assert made == [f"PREFIX={tmp_path / 'first'}", f"PREFIX={tmp_path / 'second'}"]
