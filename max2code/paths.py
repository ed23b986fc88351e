"""Where max2code finds its data and puts its builds: the one place that
knows the layout.

The data are the design card's top-level folders (templates/, equations/,
examples/, runtimes/, tests/conformance/).  In a checkout (run from the
source tree, or installed with `pip install -e .`) they are read where they
are; an installed wheel carries copies of them as package data under
max2code/_data/ with the same relative layout (setup.py copies them at build
time), found through importlib.resources.

Runtime libraries, harnesses and simulators are compiled under BUILD: the
checkout's build/ folder (gitignored) when running from a checkout, and
otherwise a user cache folder, `$MAX2CODE_CACHE/build/<version>-<hash of the
runtime sources>` (default cache `$XDG_CACHE_HOME/max2code` or
`~/.cache/max2code`), never site-packages nor the current directory.
`$MAX2CODE_BUILD` names another build folder.
"""
from __future__ import annotations

import functools
import os
import zlib
from importlib import resources
from pathlib import Path

from max2code import __version__, filestate

# the top-level folders of the repository that the package carries
DATA_FOLDERS = ("templates", "equations", "examples", "runtimes/c", "runtimes/m2", "runtimes/python",
                "runtimes/rust", "tests/conformance")
# never copied into the package: build products and caches
IGNORED = ("target", "build", "__pycache__", "*.o", "*.a", "*.so", "*.pyc", "*.egg-info")


def _data_root() -> tuple[Path, bool]:
    """(the folder holding templates/, equations/, ...; whether it is a checkout)."""
    packaged = resources.files("max2code") / "_data"
    if packaged.is_dir():
        return Path(str(packaged)), False
    checkout = Path(__file__).resolve().parent.parent
    if (checkout / "templates").is_dir() and (checkout / "runtimes").is_dir():
        return checkout, True
    raise RuntimeError(f"max2code's data (templates, equations, runtimes) are neither in {packaged} nor in "
                       f"{checkout}: reinstall the package")


ROOT, CHECKOUT = _data_root()
TEMPLATES = ROOT / "templates"
EQUATIONS = ROOT / "equations"
EXAMPLES = ROOT / "examples"
RUNTIMES = ROOT / "runtimes"
CASES = ROOT / "tests" / "conformance"
EXPECTED_FAILURES = CASES / "expected_failures"


def equation(name: str) -> Path:
    """A bundled equation by its name (`circle-circle` -> .../equations/circle-circle.mxm)."""
    return EQUATIONS / f"{name}.mxm"


def cache_dir() -> Path:
    """The user's max2code cache ($MAX2CODE_CACHE, else $XDG_CACHE_HOME/max2code or ~/.cache/max2code)."""
    base = os.environ.get("MAX2CODE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "max2code")
    return Path(base)


def _runtime_files() -> list[str]:
    """The runtime sources, in a fixed order (no build products nor caches)."""
    out = []
    for base, dirs, files in os.walk(RUNTIMES):     # top-down: the folders left out of dirs are not entered
        dirs[:] = sorted(d for d in dirs if d not in ("target", "__pycache__"))
        out += [os.path.join(base, f) for f in sorted(files)]
    return out


def sources_digest() -> str:
    """A digest of the runtime sources (names and bytes), which names an
    installed package's build folder: remembered for the files' stat in the
    cache folder (max2code/filestate.py), so that a command reads and hashes
    them only when they changed."""
    files = _runtime_files()
    now = filestate.state(files, str(RUNTIMES))
    memo = cache_dir() / f"sources-{zlib.crc32(str(RUNTIMES).encode()):08x}.state"
    digest = filestate.recall(memo, now)
    if digest is not None:
        return digest
    import hashlib      # only here: importing it (OpenSSL) costs more than a run of a small scene
    h = hashlib.sha256()
    for p in files:
        h.update(os.path.relpath(p, RUNTIMES).encode() + b"\0")
        with open(p, "rb") as fh:
            h.update(fh.read())
    digest = h.hexdigest()
    filestate.remember(memo, now, digest)
    return digest


@functools.lru_cache(maxsize=None)
def build_dir() -> Path:
    """Where runtimes, harnesses and simulators are compiled (see the module's doc)."""
    if os.environ.get("MAX2CODE_BUILD"):
        return Path(os.environ["MAX2CODE_BUILD"]).resolve()
    if CHECKOUT:
        return ROOT / "build"
    return cache_dir() / "build" / f"{__version__}-{sources_digest()[:16]}"


def __getattr__(name: str):
    # BUILD is computed on first use (hashing the runtime sources costs a few ms)
    if name == "BUILD":
        return build_dir()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
