"""The user documentation (README.md, docs/*.md) says what the software is
and does, not how it came to be: no development history ("session 12",
"issue 14", "the fifth attempt", commit hashes), and every relative link
points at a file (and heading) that exists.

`narration(text)` is the check itself: it returns the offending matches.
Code, comments and build files are held to the same words."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())

# Files held to the history rule: the README and every page under docs/.
# CHANGELOG.md is exempt: a changelog is history by design.
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LINKED = DOCS + [ROOT / "CHANGELOG.md"]

ORDINALS = ("first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth|"
            "thirteenth|fourteenth|fifteenth|\\d+(?:st|nd|rd|th)")
HISTORY_WORDS = [
    re.compile(r"\bsession \d+", re.IGNORECASE),
    re.compile(r"\bissue #?\d+", re.IGNORECASE),
    re.compile(r"\b(?:attempt|try) \d+\b", re.IGNORECASE),
    re.compile(rf"\b(?:{ORDINALS}) (?:attempt|try)\b", re.IGNORECASE),
]
# A commit hash: 7 to 40 lower-case hex digits with at least one digit and
# one letter, standing alone (not part of a word, a number like 2.66e110 or
# a path).  Looked for in prose only: code blocks and `code spans` may hold
# hex constants and digests.
HASH = re.compile(r"(?<![\w.\-/])(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}(?![\w\-/]|\.\w)")
FENCE = re.compile(r"^(```|~~~).*?^\1[^\n]*$", re.MULTILINE | re.DOTALL)
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1", re.DOTALL)


def prose(text: str) -> str:
    """The text without fenced code blocks and inline code spans (replaced
    by blanks of the same length, so offsets and line numbers stay)."""
    blank = lambda m: re.sub(r"[^\n]", " ", m.group(0))
    return CODE_SPAN.sub(blank, FENCE.sub(blank, text))


def narration(text: str, hashes_in_code: bool = False) -> list[tuple[int, str]]:
    """(line number, match) for every development-history phrase in `text`:
    the words anywhere, commit hashes in prose (everywhere with
    `hashes_in_code`)."""
    found = []
    for rx in HISTORY_WORDS:
        found += [(m.start(), m.group(0)) for m in rx.finditer(text)]
    found += [(m.start(), m.group(0)) for m in HASH.finditer(text if hashes_in_code else prose(text))]
    return [(text.count("\n", 0, pos) + 1, word) for pos, word in sorted(found)]


@pytest.mark.parametrize("path", DOCS, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_development_history(path):
    hits = narration(path.read_text(encoding="utf-8"))
    assert not hits, "\n".join(f"{path.relative_to(ROOT)}:{line}: {word!r}" for line, word in hits)


# Code, comments and build files held to the same words (hashes are left out
# there: hex constants and digests are common in code).
SOURCE_SUFFIXES = {".py", ".c", ".h", ".rs", ".mod", ".def", ".j2", ".toml", ".lark", ".cfg", ".in", ".sh",
                   ".mxm", ".mac"}


def source_files() -> list[Path]:
    """The project's code and build files (tracked by git when it is a checkout)."""
    import subprocess
    try:
        listed = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
        paths = [ROOT / f for f in listed.split()]
    except (OSError, subprocess.CalledProcessError):
        paths = [p for p in ROOT.rglob("*") if p.is_file() and ".git" not in p.parts and "build" not in p.parts]
    keep = []
    for p in paths:
        rel = p.relative_to(ROOT).as_posix()
        if rel == "tests/docs/test_docs.py" or not p.is_file():
            continue
        if p.suffix in SOURCE_SUFFIXES or p.name == "Makefile" or rel.startswith(("scripts/", ".ci/")):
            keep.append(p)
    return keep


def test_no_development_history_in_code_and_build_files():
    hits = []
    for path in source_files():
        text = path.read_text(encoding="utf-8", errors="replace")
        for rx in HISTORY_WORDS:
            hits += [f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)!r}"
                     for m in rx.finditer(text)]
    assert not hits, "comments and build files say what the code is, not its history:\n" + "\n".join(hits)


@pytest.mark.parametrize("text, expected", [
    ("Session 15 changed no answer", ["Session 15"]),
    ("measured in session 9 at a load of 2", ["session 9"]),
    ("see issue 12, item 3, and issue #14", ["issue 12", "issue #14"]),
    ("attempt 3 and try 11 failed", ["attempt 3", "try 11"]),
    ("the eleventh attempt; a 4th try; the first try", ["eleventh attempt", "4th try", "first try"]),
    ("merged at 2fdb223 and bf8bbce", ["2fdb223", "bf8bbce"]),
    ("the full hash 9b660f6d1e2a3b4c5d6e7f8091a2b3c4d5e6f708", ["9b660f6d1e2a3b4c5d6e7f8091a2b3c4d5e6f708"]),
])
def test_narration_finds_history(text, expected):
    assert [w for _, w in narration(text)] == expected


@pytest.mark.parametrize("text", [
    "10000000 events, 0.6000000000000001 m, 2.66e110, 1e-307, 4,530 ns",
    "a live session of the game; the session's trace; an attempt at a contact",
    "deadbeef and defaced are words; 12345678 is a number",
    "`3ff0000000000000` is the wire's 1.0, and so is\n```\nroots 0 3ff0000000000000\n```\n",
    "see docs/a1b2c3d4.md and build/sim/c/ab12cd3/x",
    "the 64 x 64-bit product of 1e6 and 2e7",
])
def test_narration_leaves_facts_alone(text):
    assert narration(text) == []


# ---- links -------------------------------------------------------------------------------------

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, code marks and punctuation
    dropped (letters, digits, spaces, '-' and '_' kept), spaces as '-'."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    out, seen = set(), {}
    for line in prose_headings(path.read_text(encoding="utf-8")):
        s = slug(line)
        n = seen.get(s, 0)
        out.add(s if n == 0 else f"{s}-{n}")
        seen[s] = n + 1
    return out


def prose_headings(text: str) -> list[str]:
    text = FENCE.sub("", text)
    return [m.group(1) for m in re.finditer(r"^#{1,6}\s+(.*?)\s*#*\s*$", text, re.MULTILINE)]


def links(path: Path) -> list[tuple[int, str]]:
    text = path.read_text(encoding="utf-8")
    bare = FENCE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    bare = CODE_SPAN.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), bare)
    return [(bare.count("\n", 0, m.start()) + 1, m.group(1)) for m in LINK.finditer(bare)]


def broken_links(path: Path) -> list[str]:
    bad = []
    for line, target in links(path):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):          # http:, https:, mailto:
            continue
        file_part, _, anchor = target.partition("#")
        dest = (path.parent / file_part).resolve() if file_part else path
        where = f"{path.relative_to(ROOT)}:{line}: {target}"
        if not dest.exists():
            bad.append(f"{where}: no such file")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            bad.append(f"{where}: no heading with anchor #{anchor} in {dest.relative_to(ROOT)}")
    return bad


@pytest.mark.parametrize("path", LINKED, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(path):
    bad = broken_links(path)
    assert not bad, "\n".join(bad)


def test_link_check_sees_a_broken_file_and_anchor(tmp_path):
    (tmp_path / "b.md").write_text("# Title\n\n## Flat trace (written by every runtime; `%.17g` numbers)\n")
    page = tmp_path / "a.md"
    page.write_text("[ok](b.md#flat-trace-written-by-every-runtime-17g-numbers) [gone](c.md) "
                    "[bad anchor](b.md#nowhere) [self](#here) [web](https://example.org/x)\n"
                    "```\n[in code](missing.md)\n```\n\n## Here\n")
    global ROOT
    saved, ROOT = ROOT, tmp_path
    try:
        bad = broken_links(page)
    finally:
        ROOT = saved
    assert [b.split(": ")[1] for b in bad] == ["c.md", "b.md#nowhere"]


def test_slug_follows_github():
    assert slug("Scene files (JSON)") == "scene-files-json"
    assert slug("Why advance stops *before* t") == "why-advance-stops-before-t"
    assert slug("The game: examples/game/") == "the-game-examplesgame"
    assert slug("Checking a port: `sim --step DT`") == "checking-a-port-sim---step-dt"


# ---- the command reference against the parsers ---------------------------------------------------

def _help(*argv: str) -> str:
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-m", "max2code", *argv, "--help"], capture_output=True, text=True,
                       timeout=120, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_command_reference_names_every_command_and_option():
    """README.md's command summary and docs/command-line.md name every
    subcommand and every long option that `--help` prints."""
    from max2code.cli import SUBCOMMANDS

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    reference = (ROOT / "docs" / "command-line.md").read_text(encoding="utf-8")
    missing = []
    for sub in ["", *sorted(SUBCOMMANDS)]:
        text = _help(sub) if sub else _help()
        usage = text.split("\n\n", 1)[0] if sub else text[text.index("options:"):]
        options = set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", usage)) - {"--help"}
        for doc_name, doc in (("README.md", readme), ("docs/command-line.md", reference)):
            if sub and f"max2code {sub}" not in doc:
                missing.append(f"{doc_name}: no `max2code {sub}`")
            missing += [f"{doc_name}: {sub or 'the generator'} {o}" for o in sorted(options)
                        if not re.search(re.escape(o) + r"(?![a-z0-9-])", doc)]
    assert not missing, "\n".join(missing)


TEST_PATH = re.compile(r"\btests/(?:[a-z_]+/)*test_[a-z0-9_]+\.py\b")


def named_test_files(text: str) -> list[str]:
    """The test files a text names by their path from the repository root."""
    return TEST_PATH.findall(text)


def test_named_test_files_exist():
    """Docs, comments and build files that point a reader at a test file
    name one that exists (tests move between area folders)."""
    missing = []
    for path in [*DOCS, ROOT / "CHANGELOG.md", *source_files()]:
        text = path.read_text(encoding="utf-8", errors="replace")
        for name in named_test_files(text):
            if not (ROOT / name).is_file():
                missing.append(f"{path.relative_to(ROOT)}: {name}")
    assert not missing, "no such test file:\n" + "\n".join(sorted(set(missing)))


def test_named_test_files_sees_paths():
    assert named_test_files("see tests/simulator/test_contact.py and tests/test_gone.py, not mytests/x.py") == [
        "tests/simulator/test_contact.py", "tests/test_gone.py"]
