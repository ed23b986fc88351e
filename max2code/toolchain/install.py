"""`max2code runtime LANG [--install PREFIX]` and `max2code bundled WHAT`:
where the installed package keeps a runtime's sources and the bundled
equations, examples and conformance cases, and installing a runtime as a
library for other programs (docs/using-generated-code.md)."""
from __future__ import annotations

import argparse

from max2code import paths
from max2code.errors import Max2CodeError
from max2code.toolchain import TOOLCHAINS, toolchain

BUNDLED = {"equations": paths.EQUATIONS, "examples": paths.EXAMPLES, "cases": paths.CASES,
           "templates": paths.TEMPLATES, "runtimes": paths.RUNTIMES}


def runtime_main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="max2code runtime",
                                 description="Print the folder of a runtime's sources, or build and install it "
                                             "as a library for your programs (docs/using-generated-code.md).")
    ap.add_argument("lang", choices=list(TOOLCHAINS))
    ap.add_argument("--install", metavar="PREFIX",
                    help="install the runtime under PREFIX (C: lib/libm2c.{a,so}, include/, lib/pkgconfig/m2c.pc; "
                         "Modula-2: lib/max2code/m2; Rust: lib/max2code/rust/max2code_rt, a crate to depend on "
                         "by path; Python: lib/max2code/python/max2code-rt, to pip install); prints how to use it")
    args = ap.parse_args(argv)
    tc = toolchain(args.lang)
    if args.install is None:
        print(tc.runtime_dir())
        return 0
    print(tc.install_runtime(args.install))
    return 0


def bundled_main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="max2code bundled",
                                 description="Print the folder of the data this package carries.")
    ap.add_argument("what", choices=sorted(BUNDLED))
    args = ap.parse_args(argv)
    folder = BUNDLED[args.what]
    if not folder.is_dir():
        raise Max2CodeError(f"max2code bundled: error: {folder}: missing (reinstall max2code)")
    print(folder)
    return 0
