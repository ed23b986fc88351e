"""Rust (f64)."""
import re

from max2code.targets.base import Target, visible


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


