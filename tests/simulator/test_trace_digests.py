"""Every example scene writes the trace whose digest is pinned in
tests/data/trace-digests.json (tests/trace_digests.py says how to refresh)."""
import pytest

import trace_digests as td

pytestmark = pytest.mark.slow      # builds or runs the native runtimes (scripts/test --fast leaves it out)


def test_every_example_is_pinned():
    assert sorted(td.pinned()) == [p.name for p in td.examples()]


@pytest.mark.parametrize("path", td.examples(), ids=lambda p: p.stem)
def test_trace_digest(path):
    assert td.digest(path) == td.pinned()[path.name], (
        f"{path.name}: the {td.LANG} trace changed; if intended, run 'python3 tests/trace_digests.py --update' "
        "and say why in the commit")
