"""The package's layout: subpackages by job, and no import cycles between
its modules (every import, at module level or inside a function)."""
import ast
import os
import pathlib

PKG = next(p for p in pathlib.Path(__file__).resolve().parents if (p / "pyproject.toml").exists()) / "max2code"


def module_name(path: pathlib.Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def import_graph() -> dict[str, set[str]]:
    """Module -> the max2code modules it imports (a package's __init__ only
    when it is imported by its own name)."""
    files = {module_name(p): p for p in PKG.rglob("*.py")}
    graph: dict[str, set[str]] = {m: set() for m in files}
    for mod, path in files.items():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                base = node.module
                names = [f"{base}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                base, names = None, [a.name for a in node.names]
            else:
                continue
            targets = [n for n in names if n in files] or ([base] if base in files else [])
            graph[mod].update(t for t in targets if t.startswith("max2code") and t != mod)
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> list[str] | None:
        state[m] = 1
        stack.append(m)
        for n in sorted(graph.get(m, ())):
            if state.get(n) == 1:
                return stack[stack.index(n):] + [n]
            if n not in state:
                found = visit(n)
                if found:
                    return found
        stack.pop()
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_cycle_finder_finds_a_planted_cycle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}
    assert find_cycle(g) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_subpackages_by_job():
    top = sorted(p.name for p in PKG.iterdir() if p.suffix == ".py")
    assert top == ["__init__.py", "__main__.py", "cli.py", "errors.py", "facts.py", "filestate.py", "paths.py",
                   "progress.py", "record.py", "textio.py"], top
    for sub in ("generate", "targets", "toolchain", "sim", "draw", "reports", "conformance"):
        assert (PKG / sub / "__init__.py").is_file(), sub
    assert not os.path.exists(PKG / "harness"), "harness programs are built by max2code/toolchain"
    assert not os.path.exists(PKG / "grammar"), "grammars live with the generator (max2code/generate/grammar)"


def test_every_language_has_a_toolchain():
    """The printers and the toolchains cover the same languages, in the same
    order, and the printers import nothing that builds or runs."""
    from max2code.targets import LANGUAGES
    from max2code.toolchain import TOOLCHAINS
    assert list(TOOLCHAINS) == list(LANGUAGES)
    graph = import_graph()
    printers = [m for m in graph if m == "max2code.targets" or m.startswith("max2code.targets.")]
    assert printers and all(not n.startswith("max2code.toolchain") for m in printers for n in graph[m])
