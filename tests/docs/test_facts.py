"""Every runtime's copy of the shared facts (max2code/facts.py) is the same:
the version, the solvers' largest degree, the simulator's event kinds and
their codes, the words of the trace's E lines and the names and order of
its N lines.  Each copy is read from its source text, the way its compiler
reads it, so a runtime that drifts fails here without being built."""
import re
import tomllib
from pathlib import Path

import pytest

import max2code
from max2code import facts

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
RT = ROOT / "runtimes"
C_SIM = sorted((RT / "c" / "src").glob("m2c_sim_*.[ch]"))
RUST_SIM = sorted((RT / "rust" / "src" / "sim").glob("*.rs"))
PY_SIM = sorted((RT / "python" / "max2code_rt" / "sim").glob("*.py"))
M2_SIM = sorted((RT / "m2").glob("Sim*.mod")) + sorted((RT / "m2").glob("Sim*.def"))


def text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def only(pattern: str, path: Path, flags: int = 0) -> str:
    found = re.findall(pattern, text(path), flags)
    assert len(found) == 1, f"{path.relative_to(ROOT)}: {pattern!r} found {len(found)} times"
    return found[0]


# ---- the version ----

def test_the_version_is_the_same_everywhere():
    assert facts.VERSION == max2code.__version__
    copies = {
        "runtimes/python/pyproject.toml": tomllib.loads(text(RT / "python" / "pyproject.toml"))["project"]["version"],
        "runtimes/rust/Cargo.toml": tomllib.loads(text(RT / "rust" / "Cargo.toml"))["package"]["version"],
        "runtimes/rust/Cargo.lock": next(p["version"] for p in tomllib.loads(text(RT / "rust" / "Cargo.lock"))["package"]
                                         if p["name"] == "max2code_rt"),
        "runtimes/c/Makefile": only(r"(?m)^VERSION\s*=\s*(\S+)\s*$", RT / "c" / "Makefile"),
    }
    assert copies == dict.fromkeys(copies, facts.VERSION)
    # the release has its section in the changelog
    assert re.search(rf"(?m)^## {re.escape(facts.VERSION)}$", text(ROOT / "CHANGELOG.md"))


def test_the_package_takes_its_version_from_one_place():
    pyproject = tomllib.loads(text(ROOT / "pyproject.toml"))
    assert "version" not in pyproject["project"] and "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "max2code.__version__"}


# ---- the largest degree ----

# (file, its definition) per runtime; every other file of that runtime uses the name, never the number
DEGREE = {
    "c": (RT / "c" / "include" / "m2c_roots.h", r"(?m)^#define M2C_MAX_DEGREE (\d+)$", r"#define \w*MAX_DEGREE\b"),
    "rust": (RT / "rust" / "src" / "roots.rs", r"(?m)^pub const MAX_DEGREE: usize = (\d+);$", r"const MAX_DEGREE\b"),
    "python": (RT / "python" / "max2code_rt" / "roots.py", r"(?m)^MAX_DEGREE = (\d+)$", r"(?m)^\s*MAX_DEGREE\s*="),
    "m2": (RT / "m2" / "Roots.def", r"(?m)^\s*MaxDegree = (\d+) ;", r"\bMaxDegree\s*="),
}
SOURCES = {"c": ("c", "*.[ch]"), "rust": ("rust/src", "*.rs"), "python": ("python/max2code_rt", "*.py"),
           "m2": ("m2", "*.[dm][eo][fd]")}


@pytest.mark.parametrize("lang", sorted(DEGREE))
def test_the_largest_degree_is_defined_once_per_runtime(lang):
    path, definition, any_definition = DEGREE[lang]
    assert int(only(definition, path)) == facts.MAX_DEGREE
    folder, pattern = SOURCES[lang]
    defined = [p.relative_to(ROOT).as_posix() for p in sorted((RT / folder).rglob(pattern))
               if "build" not in p.relative_to(RT).parts and "target" not in p.relative_to(RT).parts
               and re.search(any_definition, text(p))]
    assert defined == [path.relative_to(ROOT).as_posix()]
    # messages that spell the number out
    for p in sorted((RT / folder).rglob(pattern)):
        for n in re.findall(r"degree (?:above|exceeds) (\d+)", text(p)):
            assert int(n) == facts.MAX_DEGREE, p


# ---- the event kinds ----

def kinds_python() -> dict[str, int]:
    from max2code_rt.sim import queue
    assert queue.KIND_NAMES == facts.EVENT_KINDS
    return {name: getattr(queue, name.upper()) for name in queue.KIND_NAMES}


def kinds_c() -> dict[str, int]:
    enum = only(r"enum \{([^}]*M2C_SIM_KINDS[^}]*)\}", RT / "c" / "src" / "m2c_sim_internal.h")
    codes = {k.lower(): int(v) for k, v in re.findall(r"M2C_SIM_([A-Z]+) = (\d+)", enum)}
    assert codes.pop("kinds") == len(facts.EVENT_KINDS)
    return codes


def kinds_rust() -> dict[str, int]:
    src = text(RT / "rust" / "src" / "sim" / "queue.rs")
    block = src[src.index("/// Event kinds"):]
    block = block[:block.index("\n\n")]
    return {k.lower(): int(v) for k, v in re.findall(r"pub const ([A-Z]+): u64 = (\d+);", block)}


def kinds_m2() -> dict[str, int]:
    src = text(RT / "m2" / "SimQueue.def")
    codes = {k.lower(): int(v) for k, v in re.findall(r"\bK([A-Z][a-z]+) = (\d+) ;", src)}
    first, last = re.search(r"Kind = \[K(\w+)\.\.K(\w+)\]", src).groups()
    assert (first.lower(), last.lower()) == (facts.EVENT_KINDS[0], facts.EVENT_KINDS[-1])
    return codes


@pytest.mark.parametrize("reader", [kinds_python, kinds_c, kinds_rust, kinds_m2], ids=lambda f: f.__name__[6:])
def test_the_event_kinds_and_their_codes(reader):
    assert reader() == {name: code for code, name in enumerate(facts.EVENT_KINDS)}


def test_the_docs_list_the_event_kinds_in_order():
    rows = re.findall(r"(?m)^\| (\d+) ([a-z]+) \|", text(ROOT / "docs" / "simulator.md"))
    assert [(int(k), n) for k, n in rows] == list(enumerate(facts.EVENT_KINDS))


# ---- the words of the E lines ----

# how each runtime spells an E line's word: a literal "E word ..." or the word handed to the writer of such lines
E_WORDS = {
    "c": (C_SIM, r'"E ([a-z]+)[ "]'),
    "rust": (RUST_SIM, r'"E ([a-z]+)[ "]|(?:contact|support_end)\(\s*"([a-z]+)"'),
    "python": (PY_SIM, r'"E ([a-z]+)[ "]|(?:emit_contact|emit_support_end)\(\s*"([a-z]+)"'),
    "m2": (M2_SIM, r'"E ([a-z]+)[ "]|Emit(?:Contact|SupportEnd) \(\s*"([a-z]+)"'),
}


@pytest.mark.parametrize("lang", sorted(E_WORDS))
def test_the_words_of_the_event_lines(lang):
    files, pattern = E_WORDS[lang]
    words = set()
    for p in files:
        for m in re.finditer(pattern, text(p)):
            words.add(next(g for g in m.groups() if g))
    assert words == set(facts.TRACE_EVENTS), lang


def test_the_docs_and_the_converter_know_every_event_line():
    doc = text(ROOT / "docs" / "simulator.md")
    block = doc[doc.index("## Flat trace"):]
    assert re.findall(r"(?m)^E ([a-z]+) ", block) == list(facts.TRACE_EVENTS)
    # `max2code simulate` converts every line a batch run writes (E add: only the live world's add_body)
    converter = text(ROOT / "max2code" / "sim" / "simulate.py")
    assert [w for w in facts.TRACE_EVENTS if f'"{w}"' not in converter] == ["add"]


# ---- the statistics ----

def stats_python() -> list[str]:
    from max2code_rt.sim.world import STAT_NAMES
    return list(STAT_NAMES)


def stats_c() -> list[str]:
    table = only(r"stat_lines\[\] = \{(.*?)\n\};", RT / "c" / "src" / "m2c_sim_out.c", re.S)
    names = re.findall(r'\{ "(\w+)", offsetof\(m2c_sim_stats, (\w+)\) \}', table)
    assert all(a == b for a, b in names)
    fields = only(r"long long (collisions[a-z, \n]+);", RT / "c" / "src" / "m2c_sim_internal.h")
    assert [f.strip() for f in fields.split(",")] == list(facts.STAT_NAMES)
    return [a for a, _ in names]


def stats_rust() -> list[str]:
    src = text(RT / "rust" / "src" / "sim" / "world.rs")
    body = src[src.index("pub fn lines(&self)"):]
    body = body[:body.index("\n    }\n")]
    names = re.findall(r'\("(\w+)", self\.(\w+)\)', body)
    assert all(a == b for a, b in names)
    assert int(re.search(r"u64\); (\d+)\]", body).group(1)) == len(names)
    return [a for a, _ in names]


def stats_m2() -> list[str]:
    names = re.findall(r'Stat \("(\w+)", Stats\.(\w+)\)', text(RT / "m2" / "SimHandlers.mod"))
    assert all(a == b for a, b in names)
    fields = only(r"\n\s+(collisions[a-z, \n]+):", RT / "m2" / "SimWorld.def")
    assert [f.strip() for f in fields.split(",")] == list(facts.STAT_NAMES)
    return [a for a, _ in names]


@pytest.mark.parametrize("reader", [stats_python, stats_c, stats_rust, stats_m2], ids=lambda f: f.__name__[6:])
def test_the_statistics_names_in_order(reader):
    assert reader() == list(facts.STAT_NAMES)


def test_the_docs_and_the_converter_know_the_statistics():
    from max2code.sim.simulate import WORK_COUNTERS
    assert set(WORK_COUNTERS) <= set(facts.STAT_NAMES)
    doc = text(ROOT / "docs" / "simulator.md")
    line = doc[doc.index("N NAME COUNT"):]
    line = line[:line.index("\nV ")]
    assert re.findall(r"(?<=\s)([a-z]+)(?=\s)", line.split("COUNT", 1)[1] + "\n") == list(facts.STAT_NAMES)
