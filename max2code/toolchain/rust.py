"""Rust's toolchain: rustc builds of the harnesses and of the simulator
against the runtime crate max2code_rt, and cargo in runtimes/rust for that
crate, the testee and the install (a copy of the crate)."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

from max2code.paths import BUILD, RUNTIMES
from max2code.toolchain.base import Toolchain
from max2code.toolchain.tools import run

RUST_RUNTIME = RUNTIMES / "rust"

# The simulator binary: the two generated modules and the runtime's
# simulator (runtimes/rust/src/sim.rs), joined by its sim_main! macro.
SIM_MAIN = """\
// The max2code simulator with this scene's generated contact equations
// (written by max2code/toolchain/rust.py: do not edit).
#[path = {cc}]
#[allow(dead_code)]
mod circle_circle;
#[path = {pe}]
#[allow(dead_code)]
mod point_edge;

max2code_rt::sim_main!(circle_circle, point_edge);
"""


def rust_env() -> dict:
    return dict(os.environ, CARGO_TARGET_DIR=str(BUILD / "rust"), RUSTFLAGS="-Dwarnings")


def cargo(*args: str) -> None:
    """cargo in runtimes/rust (release, warnings denied), target folder BUILD/rust."""
    run(["cargo", *args], RUST_RUNTIME, rust_env())


def rust_library() -> Path:
    """The max2code_rt rlib (cargo, release, warnings denied)."""
    cargo("build", "--release", "--quiet", "--lib")
    return BUILD / "rust" / "release" / "libmax2code_rt.rlib"


def rust_sim_library() -> Path:
    """The max2code_rt rlib for the simulator's builds (cargo, the crate's
    `sim` profile: release at opt-level 3, warnings denied)."""
    cargo("build", "--profile", "sim", "--quiet", "--lib")
    return BUILD / "rust" / "sim" / "libmax2code_rt.rlib"


class RustToolchain(Toolchain):
    name = "rust"
    tools = ("rustc", "cargo")
    harness_source = "harness.rs"

    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """rustc with every warning denied."""
        return [["rustc", "--edition", "2021", "-D", "warnings", "-C", "opt-level=2", *self.runtime_flags(), src, "-o", exe]]

    def runtime_flags(self, sim: bool = False) -> list[str]:
        """rustc's flags to use the runtime crate: its release rlib, or with
        `sim` the one the simulator's builds take (opt-level 3)."""
        rlib = rust_sim_library() if sim else rust_library()
        return ["--extern", f"max2code_rt={rlib}", "-L", f"dependency={rlib.parent / 'deps'}"]

    def testee(self, baseline: bool = False) -> list[str]:
        cargo("build", "--release", "--quiet", "--bin", "max2code_rt_testee")
        return [str(BUILD / "rust" / "release" / "max2code_rt_testee")]

    def install_runtime(self, prefix: str) -> str:
        dest = Path(prefix).resolve() / "lib" / "max2code" / "rust" / "max2code_rt"
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        for name in ("Cargo.toml", "README.md"):
            shutil.copy2(RUST_RUNTIME / name, dest / name)
        shutil.copytree(RUST_RUNTIME / "src", dest / "src")
        return (f"copied the crate max2code_rt to {dest}; in your Cargo.toml:\n"
                f'  [dependencies]\n  max2code_rt = {{ path = "{dest}" }}')

    def exact_harness_build(self, src: str, exe: str, workdir: str) -> list[list[str]]:
        return self.harness_build(src, exe, [workdir])

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]

    def sim_build(self, workdir: str, generated: dict[str, str], variants: dict[str, int]) -> list[list[str]]:
        """Write main.rs (the generated modules and max2code_rt::sim_main!)
        and compile it against the runtime's rlib built for the simulator
        (the crate's `sim` profile): warnings denied, opt-level 3 for both."""
        main = Path(workdir) / "main.rs"
        text = SIM_MAIN.format(cc=_rust_str(generated["circle_circle"]), pe=_rust_str(generated["point_edge"]))
        if not main.exists() or main.read_text(encoding="utf-8") != text:
            main.write_text(text, encoding="utf-8")
        return [["rustc", "--edition", "2021", "-D", "warnings", "-C", "opt-level=3", "-C", "codegen-units=1",
                 *self.runtime_flags(sim=True), str(main), "-o", str(Path(workdir) / "sim")]]

    def sim_run(self, workdir: str, generated: dict[str, str]) -> list[str]:
        return [str(Path(workdir) / "sim")]


def _rust_str(text: str) -> str:
    """A Rust string literal holding `text`."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'
