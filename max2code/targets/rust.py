"""Rust (f64)."""
from max2code.targets.base import Target


class Rust(Target):
    name = "rust"
    extension = ".rs"
    comment = ("// ", "")
    calls = {"sin": "f64::sin({})", "cos": "f64::cos({})", "sqrt": "f64::sqrt({})", "abs": "f64::abs({})"}

    reserved = frozenset("""
        as break const continue crate else enum extern false fn for if impl in let loop match mod move mut pub ref
        return self Self static struct super trait true type unsafe use where while async await dyn abstract become
        box do final macro override priv typeof unsized virtual yield try union
        f32 f64 i32 i64 u32 u64 usize isize bool str Option Some None Result Ok Err
        coef degree mask BY_MASK lo hi t horizon options out rate rk wk nparams max2code_rt ExactOptions Motion
        smallest_root exact_toc""".split()
        + [f"coef{k}" for k in range(17)])
    reserved_prefixes = ("_",)

    single_type = "f32"
    single_calls = {"sin": "f32::sin({})", "cos": "f32::cos({})", "sqrt": "f32::sqrt({})", "abs": "f32::abs({})"}
    single_suffix = "_f32"
    requires = "Rust (cargo); the crate max2code_rt (no dependencies)"
    links = "`mod eq;` in your crate; depend on max2code_rt"
