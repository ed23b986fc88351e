"""Rust (f64)."""
import re
from pathlib import Path

from max2code.targets.base import Target, visible

# The simulator binary: the two generated modules and the runtime's
# simulator (runtimes/rust/src/sim.rs), joined by its sim_main! macro.
SIM_MAIN = """\
// The max2code simulator with this scene's generated contact equations
// (written by max2code/targets/rust.py: do not edit).
#[path = {cc}]
#[allow(dead_code)]
mod circle_circle;
#[path = {pe}]
#[allow(dead_code)]
mod point_edge;

max2code_rt::sim_main!(circle_circle, point_edge);
"""


class Rust(Target):
    name = "rust"
    extension = ".rs"
    comment = ("// ", "")
    calls = {"sin": "f64::sin({})", "cos": "f64::cos({})", "sqrt": "f64::sqrt({})", "abs": "f64::abs({})"}

    words = (
        ("a keyword of Rust (strict, reserved or weak)", frozenset("""
            as break const continue crate else enum extern false fn for if impl in let loop match mod move mut pub
            ref return self Self static struct super trait true type unsafe use where while async await dyn
            abstract become box do final macro override priv typeof unsized virtual yield try union gen
            macro_rules raw safe""".split())),
        ("a name of Rust's prelude or a primitive type", frozenset("""
            f32 f64 i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 usize isize bool char str std core alloc
            Copy Send Sized Sync Unpin Drop Fn FnMut FnOnce AsyncFn AsyncFnMut AsyncFnOnce drop Box ToOwned Clone
            PartialEq PartialOrd Eq Ord AsRef AsMut Into From Default Iterator Extend IntoIterator
            DoubleEndedIterator ExactSizeIterator Option Some None Result Ok Err String ToString Vec TryFrom TryInto
            FromIterator size_of size_of_val align_of align_of_val""".split())),
        ("a name the generated Rust uses", frozenset("""
            coef degree mask BY_MASK lo hi t horizon options out rate rk wk nparams max2code_rt ExactOptions Motion
            smallest_root exact_toc""".split() + [f"coef{k}" for k in range(17)])),
    )
    reserved_prefixes = ("_",)

    single_type = "f32"
    single_calls = {"sin": "f32::sin({})", "cos": "f32::cos({})", "sqrt": "f32::sqrt({})", "abs": "f32::abs({})"}
    single_suffix = "_f32"
    requires = "Rust (cargo); the crate max2code_rt (no dependencies)"
    links = "`mod eq;` in your crate; depend on max2code_rt"

    def escape(self, text: str, where: str) -> str:
        """A '//' comment and a '///' doc end at a line end (rustc also denies
        bidirectional overrides in them: not printable, so escaped); a doc is
        Markdown, where a fence (```, ~~~) would turn the lines after it into a
        doctest, so a fence's first character is escaped."""
        if where == "string":
            return "".join("\\" + ch if ch in '\\"' else ch if ch.isprintable() else f"\\u{{{ord(ch):x}}}"
                           for ch in text)
        text = visible(text, lambda c: f"\\u{{{c:x}}}")
        return re.sub(r"([`~])(?=\1\1)", r"\\\1", text) if where == "doc" else text

    harness_source = "harness.rs"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """rustc with every warning denied."""
        return [["rustc", "--edition", "2021", "-D", "warnings", "-C", "opt-level=2", *self.runtime_flags(), src, "-o", exe]]

    def runtime_flags(self, sim: bool = False) -> list[str]:
        """rustc's flags to use the runtime crate: its release rlib, or with
        `sim` the one the simulator's builds take (opt-level 3)."""
        from max2code.harness import runtimes
        rlib = runtimes.rust_sim_library() if sim else runtimes.rust_library()
        return ["--extern", f"max2code_rt={rlib}", "-L", f"dependency={rlib.parent / 'deps'}"]

    def testee(self, baseline: bool = False) -> list[str]:
        from max2code.harness import runtimes
        runtimes.cargo("build", "--release", "--quiet", "--bin", "max2code_rt_testee")
        return [str(runtimes.BUILD / "rust" / "release" / "max2code_rt_testee")]

    def install_runtime(self, prefix: str) -> str:
        import shutil
        from max2code.harness import runtimes
        dest = Path(prefix).resolve() / "lib" / "max2code" / "rust" / "max2code_rt"
        if dest.exists():
            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        for name in ("Cargo.toml", "README.md"):
            shutil.copy2(runtimes.RUST_RUNTIME / name, dest / name)
        shutil.copytree(runtimes.RUST_RUNTIME / "src", dest / "src")
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
