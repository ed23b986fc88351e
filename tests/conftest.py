import os
import sys
from pathlib import Path

import pytest

# the repository: the folder above this file that holds pyproject.toml
ROOT = next(str(p) for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
sys.path.insert(0, os.path.join(ROOT, "tests"))

from max2code.targets import LANGUAGES  # noqa: E402  (the only list of languages)

# The suite's command (scripts/test, hence CI) sets MAX2CODE_HYPOTHESIS=derandomize: every
# property test then draws the same examples on every run, so CI passes or fails the same way
# for the same code.  Without it (plain `pytest`) hypothesis explores new examples each run:
# the way to hunt for new failures, each then pinned as a test of its own.
from hypothesis import settings  # noqa: E402

settings.register_profile("suite", derandomize=True, database=None, print_blob=True)
if os.environ.get("MAX2CODE_HYPOTHESIS") == "derandomize":
    settings.load_profile("suite")

LANGS = sorted(LANGUAGES)
EQUATIONS = ["circle-circle", "point-line"]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def generated():
    """(equation, lang, **options) -> GeneratedFile, generated once per session (per worker)
    from the equation's absolute path: the tests that build a harness of the same file then
    build the same text, which compile_harness builds once for all of them."""
    from max2code.generate.pipeline import GenerateRequest, generate_file

    cache = {}

    def get(eq, lang, **kw):
        key = (eq, lang, tuple(sorted(kw.items())))
        if key not in cache:
            cache[key] = generate_file(GenerateRequest(path=os.path.join(ROOT, "equations", f"{eq}.mxm"),
                                                       lang=lang, out_name="generated", **kw))
        return cache[key]

    old = os.getcwd()
    os.chdir(ROOT)
    yield get
    os.chdir(old)


@pytest.fixture(scope="session")
def installed(tmp_path_factory):
    """This checkout built as a wheel and installed in a fresh venv, made
    once per run: the parallel workers of a run share it (it is made under a
    lock in the run's temporary folder, which they share).  The venv sees the
    system's site-packages for the dependencies (lark, numpy, matplotlib,
    ...: nothing is downloaded) but max2code itself comes from the wheel; it
    holds no pip of its own (the suite's pip installs the wheel into it).
    Returns (venv folder, environment for subprocesses: the venv's bin first
    on PATH, no PYTHONPATH)."""
    import subprocess

    from max2code.toolchain.tools import build_lock

    run = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        run = run.parent            # the folder of the run, above each worker's own
    base = run / "installed"
    venv = base / "venv"
    with build_lock(base):
        if not (base / "made").exists():
            _make_installed(base, venv, subprocess)
            (base / "made").write_text("")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "MAX2CODE_BUILD", "VIRTUAL_ENV")}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env['PATH']}"
    return venv, env


def _make_installed(base: Path, venv: Path, subprocess) -> None:
    from max2code.toolchain.tools import build_lock

    wheels = base / "wheels"
    # one wheel build at a time from this checkout: setuptools writes its egg-info and build/lib
    # in the checkout, and a parallel worker's build would mix into this one
    with build_lock(Path(ROOT) / "build" / "wheel"):
        subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation", ROOT,
                        "-w", str(wheels)], check=True, capture_output=True, text=True)
    (wheel,) = wheels.glob("max2code-*.whl")
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    if sys.prefix != sys.base_prefix:
        # the suite runs in a venv (scripts/setup's .venv), whose packages the new one sees
        # too, after its own: a path line, so the .venv's editable max2code is not loaded
        import sysconfig
        here = sorted({sysconfig.get_path("purelib"), sysconfig.get_path("platlib")})
        site = subprocess.run([str(venv / "bin" / "python"), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                              check=True, capture_output=True, text=True).stdout.strip()
        (Path(site) / "parent-environment.pth").write_text("".join(f"{d}\n" for d in here))
    subprocess.run([sys.executable, "-m", "pip", "--python", str(venv / "bin" / "python"), "install", "-q", "--no-deps",
                    "--no-index", "--ignore-installed", str(wheel)], check=True, capture_output=True, text=True)


def _null_is_device() -> bool:
    import stat
    try:
        return stat.S_ISCHR(os.stat(os.devnull).st_mode)
    except OSError:
        return False


@pytest.fixture(autouse=True)
def null_device_kept():
    """/dev/null stays the device: a tool that renames or links a file over
    its output (as root) replaces it, and every later `> /dev/null` on the
    machine then fills a file.  Fails the
    test during which it changed, so the culprit is named."""
    before = _null_is_device()
    yield
    if before and not _null_is_device():
        pytest.fail(f"{os.devnull} is no longer a character device after this test (something wrote a file over it)")


NATIVE = {"c", "m2", "rust"}


def _runs_a_native_runtime(item) -> bool:
    """A test parametrized with a compiled runtime as its language or engine
    (`lang`, `engine`): it builds that runtime's simulator or harness on first
    use and runs it, so it counts as slow without a mark of its own."""
    params = getattr(getattr(item, "callspec", None), "params", {})
    return any(params.get(k) in NATIVE for k in ("lang", "engine"))


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """The tests of a compiled runtime are marked slow; and the files
    holding slow tests come first, so that parallel workers do not end on one
    long test while the other idles (a file's own order is kept: its
    module-scoped fixtures are made once)."""
    for item in items:
        if _runs_a_native_runtime(item):
            item.add_marker(pytest.mark.slow)
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)      # stable: the order within each part is kept
