"""Rust (f64)."""
from max2code.targets.base import Target


class Rust(Target):
    name = "rust"
    extension = ".rs"
    comment = ("// ", "")
    calls = {"sin": "f64::sin({})", "cos": "f64::cos({})", "sqrt": "f64::sqrt({})", "abs": "f64::abs({})"}

    single_type = "f32"
    single_calls = {"sin": "f32::sin({})", "cos": "f32::cos({})", "sqrt": "f32::sqrt({})", "abs": "f32::abs({})"}
    single_suffix = "_f32"

    harness_source = "harness.rs"
    def harness_build(self, src: str, exe: str, include_dirs: list[str]) -> list[list[str]]:
        """rustc with every warning denied."""
        return [["rustc", "--edition", "2021", "-D", "warnings", "-C", "opt-level=2", *self.runtime_flags(), src, "-o", exe]]

    def runtime_flags(self) -> list[str]:
        from max2code import runtimes
        rlib = runtimes.rust_library()
        return ["--extern", f"max2code_rt={rlib}", "-L", f"dependency={rlib.parent / 'deps'}"]

    def harness_run(self, src: str, exe: str) -> list[str]:
        return [exe]
