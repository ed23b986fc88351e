"""The four runtimes' simulators are split by the same concepts, under the
same names (docs/architecture.md, "The simulator's files"): a newcomer who
knows where a concept lives in one runtime finds it in the other three."""
import pathlib

import pytest

ROOT = next(p for p in pathlib.Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
RUNTIMES = ROOT / "runtimes"

# the concepts, in the order a prediction's data flows through them
CONCEPTS = ("scene", "queue", "grid", "motion", "predict", "contact", "cluster", "support", "sleep", "overlap",
            "world", "live", "handlers", "out")


def concept_file(lang: str, concept: str) -> pathlib.Path:
    if lang == "c":
        return RUNTIMES / "c" / "src" / f"m2c_sim_{concept}.c"
    if lang == "rust":
        return RUNTIMES / "rust" / "src" / "sim" / f"{concept}.rs"
    if lang == "python":
        return RUNTIMES / "python" / "max2code_rt" / "sim" / f"{concept}.py"
    return RUNTIMES / "m2" / f"Sim{concept.capitalize()}.mod"


@pytest.mark.parametrize("lang", ["c", "m2", "python", "rust"])
def test_every_concept_has_its_file_in_every_runtime(lang):
    missing = [str(concept_file(lang, c).relative_to(ROOT)) for c in CONCEPTS if not concept_file(lang, c).is_file()]
    assert not missing, f"{lang}: missing concept files {missing}"


def test_modula2_concepts_have_definition_modules():
    missing = [c for c in CONCEPTS if not (RUNTIMES / "m2" / f"Sim{c.capitalize()}.def").is_file()]
    assert not missing, missing


def test_no_simulator_file_outside_the_concepts():
    """A file of the simulator is a concept file or one of each runtime's few
    named extras (number printing, huge pages, the program's main, headers)."""
    extras = {
        "c": {"m2c_sim_format.c", "m2c_sim_pages.c"},
        "rust": {"g17.rs", "huge.rs"},
        "python": {"__init__.py"},
        "m2": set(),
    }
    found = {
        "c": {p.name for p in (RUNTIMES / "c" / "src").glob("m2c_sim*.c")},
        "rust": {p.name for p in (RUNTIMES / "rust" / "src" / "sim").glob("*.rs")},
        "python": {p.name for p in (RUNTIMES / "python" / "max2code_rt" / "sim").glob("*.py")},
        "m2": {p.name for p in (RUNTIMES / "m2").glob("Sim*.mod")} - {"SimMain.mod", "SimOutCheck.mod"},
    }
    for lang, names in found.items():
        concepts = {concept_file(lang, c).name for c in CONCEPTS}
        stray = sorted(names - concepts - extras[lang])
        assert not stray, f"{lang}: files that are no concept: {stray}"


def test_the_c_include_folder_holds_only_public_headers():
    """What a user's program includes; the simulator's internal headers live in src/."""
    assert sorted(p.name for p in (RUNTIMES / "c" / "include").iterdir()) == ["m2c_exact.h", "m2c_roots.h", "m2c_toi.h",
                                                                              "m2c_world.h"]
