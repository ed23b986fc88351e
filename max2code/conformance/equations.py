"""The equations conformance cases may name: the bundled ones (with their
references in motion_ref) and a user's .mxm files registered by
`max2code conformance --equation FILE.mxm`."""
from __future__ import annotations

from pathlib import Path

from max2code.conformance.motion_ref import EQUATIONS
from max2code.paths import equation as mxm_path

USER_EQUATIONS: dict[str, Path] = {}


def use_equation(path: str | Path) -> list[str]:
    """Let cases name the equation of the .mxm file `path` by its file name
    without .mxm or by its `equation` name; returns the two names."""
    from max2code.generate.mxm import read_mxm    # here: the runner starts without the generator

    path = Path(path)
    names = [path.stem, read_mxm(str(path)).equation]
    for n in names:
        USER_EQUATIONS[n] = path
    return names


def equation_file(name: str) -> Path | None:
    """The .mxm file of an equation a case names: a registered user's, else a bundled one (None: unknown)."""
    if name in USER_EQUATIONS:
        return USER_EQUATIONS[name]
    return mxm_path(name) if name in EQUATIONS else None


def known_equations() -> str:
    user = sorted({f"{n} ({p})" for n, p in USER_EQUATIONS.items() if n == p.stem})
    return ", ".join(sorted(EQUATIONS) + user)
