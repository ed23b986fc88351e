import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))

LANGS = ["c", "m2", "python", "rust"]
EQUATIONS = ["circle-circle", "point-line"]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def generated():
    """(equation, lang) -> GeneratedFile, generated once per session."""
    from max2code.generate.pipeline import GenerateRequest, generate_file

    cache = {}

    def get(eq, lang, **kw):
        key = (eq, lang, tuple(sorted(kw.items())))
        if key not in cache:
            cache[key] = generate_file(GenerateRequest(path=os.path.join("equations", f"{eq}.mxm"),
                                                       lang=lang, out_name="generated", **kw))
        return cache[key]

    old = os.getcwd()
    os.chdir(ROOT)
    yield get
    os.chdir(old)
