"""The layering of docs/architecture.md, read from the source with ``ast``: the numerical
core imports nothing from the boundary (files, rendering, the command line, the
orchestrator), not even lazily inside a function, and the package graph has no cycle
through the core."""

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "eigenupdate"
CORE = ("model", "solve", "identify", "measure", "design")
BOUNDARY = ("io", "report", "plot", "cli", "workflow")


def _imports(path: Path) -> list[tuple[int, str]]:
    package = ".".join(path.relative_to(SRC.parent).with_suffix("").parts[:-1])
    return _imports_in(path.read_text(encoding="utf-8"), package)


def _imports_in(source: str, package: str) -> list[tuple[int, str]]:
    """Every module an import statement in ``source`` names (absolute, or resolved from a
    relative import in ``package``), with its line, at any depth (inside functions too);
    ``from eigenupdate import x`` names eigenupdate.x."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            out += [(node.lineno, f"{base}.{a.name}") for a in node.names]
    return out


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if parts[0] == "eigenupdate" and len(parts) > 1 else None


def test_the_walk_sees_every_kind_of_import():
    # the test of the test: lazy, relative and package-level imports are all found
    probe = ("def f():\n    from eigenupdate import workflow\n"
             "    from ..io import study\n    import eigenupdate.plot.plots\n")
    found = {_layer(m) for _, m in _imports_in(probe, "eigenupdate.measure")}
    assert found == {"workflow", "io", "plot"}


@pytest.mark.parametrize("layer", CORE)
def test_core_imports_no_boundary_module(layer):
    bad = [f"{p.relative_to(SRC)}:{line}: {m}"
           for p in sorted((SRC / layer).rglob("*.py"))
           for line, m in _imports(p) if _layer(m) in BOUNDARY]
    assert not bad, "\n".join(bad)


def test_package_graph():
    # which subpackage imports which: the core only downwards, printed for the docs
    graph: dict[str, set[str]] = {}
    for p in SRC.rglob("*.py"):
        rel = p.relative_to(SRC).with_suffix("").parts
        src = rel[0] if len(rel) > 1 else rel[0]
        for _, m in _imports(p):
            dst = _layer(m)
            if dst and dst != src and (SRC / dst).is_dir() | (SRC / f"{dst}.py").is_file():
                graph.setdefault(src, set()).add(dst)
    for core in CORE:
        assert not graph.get(core, set()) & set(BOUNDARY), core
    # model is the bottom of the core; solve uses only model
    assert graph.get("model", set()) <= {"errors", "budget", "choices", "schema"}
    assert graph.get("solve", set()) <= {"model", "errors", "budget", "choices", "schema"}


def test_modules_of_one_idea_stay_short():
    # issue 24: no module over 600 lines (a longer one holds two ideas: split it)
    long = {str(p.relative_to(SRC)): n for p in sorted(SRC.rglob("*.py"))
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 600}
    assert not long, long
