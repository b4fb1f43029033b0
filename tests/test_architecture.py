"""The package's architecture, from the import graph of ``src/skisnow`` (``tools/import_graph.py``).

Every subpackage declares in its ``__init__`` docstring which subpackages it may import (a line
``May import: ...``; the core modules ``_errors``, ``_checks``, ``_atomic``, ``_values``,
``_lazy``, ``_parallel``, ``constants``, ``materials`` always): what it imports, at module level,
inside functions or for type checking, stays within that; no circles between subpackages or
between the modules of one; no subpackage imports another's private modules or names; names kept
for compatibility in a ``_LAZY`` map are documented as such and not used inside ``src``; no
module over 500 lines.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def tool():
    path = ROOT / "tools" / "import_graph.py"
    spec = importlib.util.spec_from_file_location("import_graph", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    yield module
    sys.modules.pop(spec.name, None)


@pytest.fixture(scope="module")
def graph(tool):
    return tool.analyse(ROOT / "src")


def _where(edges) -> list[str]:
    return [f"{e.source}:{e.line} -> {e.target} {e.names}" for e in edges]


def test_every_subpackage_declares_what_it_may_import(graph) -> None:
    assert graph.undeclared() == []
    # the declarations form a ladder (they are what the floors are checked against)
    declared = {r: d for r, d in graph.declared.items() if d is not None}
    graph_of = {r: set(d) for r, d in declared.items()}
    for room in graph_of:
        seen, todo = set(), [room]
        while todo:
            for dep in graph_of.get(todo.pop(), ()):
                assert dep != room, f"the declarations of {room} run in a circle"
                if dep not in seen:
                    seen.add(dep)
                    todo.append(dep)


def test_imports_stay_within_what_is_declared(graph) -> None:
    bad = [f"{a} -> {b}: {w}" for a, b, e in graph.against_plan() for w in _where([e])]
    assert bad == []


def test_no_circles(graph) -> None:
    assert graph.room_circles() == []
    assert graph.module_circles() == []


def test_no_cross_package_private_imports(graph) -> None:
    assert _where(graph.private_imports()) == []


def test_compatibility_names_are_documented_and_unused_inside(graph) -> None:
    undocumented = [f"{c.room}.{c.name} -> {c.target}" for c in graph.compat if not c.documented]
    assert undocumented == []
    assert _where(graph.through_compat()) == []


def test_no_module_over_500_lines(graph, tool) -> None:
    assert graph.long_modules() == []
    assert tool.MAX_LINES == 500


def test_the_checks_can_fail(tool, tmp_path: Path) -> None:
    """A small tree that breaks every rule is caught by each check."""
    pkg = tmp_path / "skisnow"
    files = {
        "__init__.py": "",
        "_errors.py": "",
        "low/__init__.py": '"""Low.\n\nMay import: core only\n"""\nfrom skisnow.low._a import f\n',
        "low/_a.py": "from skisnow.high import g\n\ndef f():\n    from skisnow.low import _b\n",
        "low/_b.py": "from skisnow.low._a import f\n",
        "high/__init__.py": (
            '"""High.\n\nMay import: low\n"""\nfrom skisnow.low._a import f\n'
            "_LAZY = {'old': 'skisnow.low'}\n"
        ),
        "high/_c.py": "from skisnow.high import old\n" + "x = 1\n" * 501,
        "loose/__init__.py": "",
    }
    for name, text in files.items():
        (pkg / name).parent.mkdir(parents=True, exist_ok=True)
        (pkg / name).write_text(text)
    g = tool.analyse(tmp_path)
    assert g.undeclared() == ["loose"]
    assert [(a, b) for a, b, _ in g.against_plan()] == [("low", "high")]
    assert g.room_circles() == [["high", "low"]]
    assert g.module_circles() == [["skisnow.low._a", "skisnow.low._b"]]
    assert [e.target for e in g.private_imports()] == ["skisnow.low._a"]
    assert [(c.name, c.documented) for c in g.compat] == [("old", False)]
    assert [e.source for e in g.through_compat()] == ["skisnow.high._c"]
    assert g.long_modules() == [("skisnow.high._c", 502)]
