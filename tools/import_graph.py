"""The import graph of ``src/skisnow``: rooms, floors, arrows against the plan, circles.

Run from the repository root::

    uv run python tools/import_graph.py            # the report
    uv run python tools/import_graph.py --src DIR  # another tree (e.g. a checkout of main)

It reads the source as text (:mod:`ast`; nothing is imported) and prints

* the rooms: each subpackage of ``skisnow`` with its modules and lines (the core modules,
  ``_errors``, ``_checks``, ``_atomic``, ``_values``, ``_lazy``, ``_parallel``, ``constants``,
  ``materials`` and ``skisnow/__init__``, form one room, ``core``, that every room may import);
* the floors: a topological layering of the rooms by their actual imports (a circle of rooms
  shares one floor, joined by ``<->``);
* the arrows that run against the plan: an import of a room that the importer's ``__init__``
  docstring does not list on its ``May import:`` line (rooms without that line are named);
* the compatibility re-exports: names a room's ``_LAZY`` map sends to another room, allowed only
  where the room's docstring names them in a paragraph saying they are "kept for compatibility";
* circles between rooms and between the modules of one room;
* imports inside ``src`` that go through such a compatibility re-export;
* cross-room private imports: ``skisnow.X._module`` or a ``_name`` from another room;
* modules over 500 lines.

Every ``import`` counts, at module level, inside a function (imported on first use) or under
``TYPE_CHECKING``; a ``_LAZY`` entry within its own room counts as an import of that module.
``tests/test_architecture.py`` asserts the same rules on this analysis (:func:`analyse`).
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = "skisnow"
CORE = "core"
MAX_LINES = 500
# the "May import:" line and the lines that continue it, up to a blank line
_MAY_IMPORT = re.compile(r"^\s*May import:\s*(.*(?:\n[ \t]*\S.*)*)", re.MULTILINE)
_COMPAT = re.compile(r"kept for compatibility", re.IGNORECASE)


@dataclass(frozen=True)
class Edge:
    """One import: ``source`` module imports ``target`` module (``names`` from it)."""

    source: str
    target: str
    line: int
    names: tuple[str, ...]
    kind: str  # "top", "function", "type-checking", "lazy-map"

    @property
    def private(self) -> bool:
        """``target`` is a private module of its room, or a private name is taken from it."""
        parts = self.target.split(".")[2:]
        return any(_private(p) for p in parts) or any(_private(n) for n in self.names)


@dataclass(frozen=True)
class Compat:
    """A compatibility re-export: ``room.__init__``'s ``_LAZY`` sends ``name`` to ``target``."""

    room: str
    name: str
    target: str
    documented: bool


@dataclass
class Graph:
    """The analysis of one tree (see :func:`analyse`)."""

    modules: dict[str, Path]
    lines: dict[str, int]
    edges: list[Edge]
    compat: list[Compat]
    declared: dict[str, set[str] | None]  # room -> May import (None: no line)
    rooms: list[str] = field(default_factory=list)

    def room_of(self, module: str) -> str:
        return room_of(module, self.rooms)

    def room_edges(self) -> dict[tuple[str, str], list[Edge]]:
        """Edges between different rooms (core excluded), grouped by (importer, imported)."""
        out: dict[tuple[str, str], list[Edge]] = defaultdict(list)
        for e in self.edges:
            a, b = self.room_of(e.source), self.room_of(e.target)
            if a != b and b != CORE:
                out[a, b].append(e)
        return out

    def against_plan(self) -> list[tuple[str, str, Edge]]:
        """(room, imported room, edge) for every import not on the room's ``May import:``."""
        bad = []
        for (a, b), edges in sorted(self.room_edges().items()):
            allowed = self.declared.get(a)
            if a == CORE or (allowed is not None and b in allowed):
                continue
            bad.extend((a, b, e) for e in edges)
        return bad

    def undeclared(self) -> list[str]:
        return [r for r in self.rooms if r != CORE and self.declared.get(r) is None]

    def private_imports(self) -> list[Edge]:
        """Imports of another room's private module or name (core modules are shared)."""
        out = []
        for e in self.edges:
            a, b = self.room_of(e.source), self.room_of(e.target)
            if a != b and b != CORE and e.private:
                out.append(e)
        return out

    def through_compat(self) -> list[Edge]:
        """Imports inside ``src`` of a name through another room's compatibility re-export
        (the name should be imported from its home)."""
        compat = {(f"{ROOT}.{c.room}", c.name) for c in self.compat}
        return [
            e
            for e in self.edges
            if e.kind != "lazy-map" and any((e.target, n) in compat for n in e.names)
        ]

    def room_circles(self) -> list[list[str]]:
        graph = {r: set() for r in self.rooms}
        for a, b in self.room_edges():
            graph[a].add(b)
        return [c for c in _sccs(graph) if len(c) > 1]

    def module_circles(self) -> list[list[str]]:
        """Circles between the modules of one room (a package's ``__init__`` importing its own
        modules is not an arrow back: Python runs the ``__init__`` first anyway)."""
        graph: dict[str, set[str]] = {m: set() for m in self.modules}
        for e in self.edges:
            if self.room_of(e.source) == self.room_of(e.target) and e.source != e.target:
                graph[e.source].add(e.target)
        return [c for c in _sccs(graph) if len(c) > 1]

    def floors(self) -> list[list[str]]:
        """Rooms by floor: floor 0 is core, a room stands one floor above the highest it imports."""
        graph = {r: set() for r in self.rooms}
        for a, b in self.room_edges():
            graph[a].add(b)
        comps = _sccs(graph)
        comp_of = {r: i for i, c in enumerate(comps) for r in c}
        level: dict[int, int] = {}

        def depth(i: int) -> int:
            if i not in level:
                level[i] = -1  # a guard; the condensation has no circles
                deps = {comp_of[b] for r in comps[i] for b in graph[r]} - {i}
                level[i] = 1 + max((depth(j) for j in deps), default=-1)
            return level[i]

        floors: dict[int, list[str]] = defaultdict(list)
        for i, c in enumerate(comps):
            floors[depth(i)].append(" <-> ".join(sorted(c)))
        return [sorted(floors[k]) for k in sorted(floors)]

    def long_modules(self) -> list[tuple[str, int]]:
        return sorted(((m, n) for m, n in self.lines.items() if n > MAX_LINES), key=lambda t: -t[1])


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def room_of(module: str, rooms: Iterable[str]) -> str:
    """The room of a dotted module name: its subpackage, or ``core``."""
    parts = module.split(".")
    if len(parts) >= 2 and parts[1] in rooms:
        return parts[1]
    return CORE


def _module_name(src: Path, path: Path) -> str:
    rel = path.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    base = base if is_package else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


class _Visitor(ast.NodeVisitor):
    def __init__(self, module: str, is_package: bool, known: set[str]) -> None:
        self.module, self.is_package, self.known = module, is_package, known
        self.edges: list[Edge] = []
        self._kind = ["top"]

    def _add(self, target: str, line: int, names: tuple[str, ...]) -> None:
        if target == ROOT or target.startswith(ROOT + "."):
            while target not in self.known and "." in target:
                target = target.rsplit(".", 1)[0]
            self.edges.append(Edge(self.module, target, line, names, self._kind[-1]))

    def _nested(self, node: ast.AST, kind: str) -> None:
        self._kind.append(kind)
        self.generic_visit(node)
        self._kind.pop()

    def visit_FunctionDef(self, node: ast.FunctionDef) -> None:
        self._nested(node, "function")

    visit_AsyncFunctionDef = visit_FunctionDef  # type: ignore[assignment]

    def visit_If(self, node: ast.If) -> None:
        test = ast.unparse(node.test)
        if test in ("TYPE_CHECKING", "typing.TYPE_CHECKING"):
            self._kind.append("type-checking")
            for child in node.body:
                self.visit(child)
            self._kind.pop()
            for child in node.orelse:
                self.visit(child)
        else:
            self.generic_visit(node)

    def visit_Import(self, node: ast.Import) -> None:
        for alias in node.names:
            self._add(alias.name, node.lineno, ())

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        base = _resolve(self.module, self.is_package, node)
        for alias in node.names:
            sub = f"{base}.{alias.name}"
            if sub in self.known:  # ``from skisnow.micro import _scherge2021``: the module
                self._add(sub, node.lineno, ())
            else:
                self._add(base, node.lineno, (alias.name,))

    def visit_Call(self, node: ast.Call) -> None:
        f = ast.unparse(node.func)
        if f in ("importlib.import_module", "import_module") and node.args:
            arg = node.args[0]
            if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                self._add(arg.value, node.lineno, ())
        self.generic_visit(node)


def _lazy_map(tree: ast.Module) -> dict[str, tuple[str, int]]:
    """name -> (module, line) of a module-level ``_LAZY`` dict (literal keys, ``**`` of
    ``dict.fromkeys((names...), "module")``)."""
    out: dict[str, tuple[str, int]] = {}

    def take(node: ast.expr) -> None:
        if isinstance(node, ast.Dict):
            for k, v in zip(node.keys, node.values, strict=True):
                if k is None:
                    take(v)
                elif isinstance(k, ast.Constant) and isinstance(v, ast.Constant):
                    out[k.value] = (v.value, v.lineno)
        elif isinstance(node, ast.Call) and ast.unparse(node.func) == "dict.fromkeys":
            keys, value = node.args
            assert isinstance(keys, ast.Tuple | ast.List) and isinstance(value, ast.Constant)
            for k in keys.elts:
                assert isinstance(k, ast.Constant)
                out[k.value] = (value.value, value.lineno)
        else:
            raise ValueError(f"line {node.lineno}: a _LAZY entry this tool cannot read")

    for stmt in tree.body:
        targets = (
            stmt.targets
            if isinstance(stmt, ast.Assign)
            else [stmt.target]
            if isinstance(stmt, ast.AnnAssign)
            else []
        )
        if any(isinstance(t, ast.Name) and t.id == "_LAZY" for t in targets):
            assert stmt.value is not None
            take(stmt.value)
    return out


def _compat_text(doc: str) -> str:
    """The paragraphs of a docstring that say "kept for compatibility"."""
    return "\n\n".join(p for p in re.split(r"\n\s*\n", doc) if _COMPAT.search(p))


def _declared(doc: str, rooms: list[str]) -> set[str] | None:
    m = _MAY_IMPORT.search(doc)
    if m is None:
        return None
    words = set(re.findall(r"[A-Za-z_][A-Za-z0-9_.]*", m.group(1)))
    names = {w.removeprefix(ROOT + ".") for w in words}
    unknown = {n for n in names if n not in rooms and n not in ("core", "only", "nothing")}
    if unknown:
        raise ValueError(f"May import: names {sorted(unknown)} that are not rooms")
    return {n for n in names if n in rooms}


def analyse(src: Path) -> Graph:
    """Read every module below ``src/skisnow`` and return its import :class:`Graph`."""
    pkg = src / ROOT
    paths = sorted(p for p in pkg.rglob("*.py") if "__pycache__" not in p.parts)
    modules = {_module_name(src, p): p for p in paths}
    subpackages = (p.name for p in pkg.iterdir() if (p / "__init__.py").is_file())
    rooms = [*sorted(subpackages), CORE]
    known = set(modules)
    edges: list[Edge] = []
    compat: list[Compat] = []
    declared: dict[str, set[str] | None] = {}
    lines: dict[str, int] = {}
    for name, path in modules.items():
        text = path.read_text(encoding="utf-8")
        lines[name] = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        tree = ast.parse(text, filename=str(path))
        is_package = path.name == "__init__.py"
        v = _Visitor(name, is_package, known)
        v.visit(tree)
        edges.extend(v.edges)
        if is_package and name != ROOT:
            room = room_of(name, rooms)
            doc = ast.get_docstring(tree) or ""
            declared[room] = _declared(doc, rooms)
            allowed = _compat_text(doc)
            for attr, (target, line) in _lazy_map(tree).items():
                if room_of(target, rooms) == room:
                    edges.append(Edge(name, target, line, (attr,), "lazy-map"))
                else:
                    documented = re.search(rf"\b{re.escape(attr)}\b", allowed) is not None
                    compat.append(Compat(room, attr, target, documented))
    return Graph(modules, lines, edges, compat, declared, rooms)


def _sccs(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components (Tarjan), each sorted, in a stable order."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    sys.setrecursionlimit(max(10_000, sys.getrecursionlimit()))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _where(g: Graph, e: Edge) -> str:
    what = f" ({', '.join(e.names)})" if e.names else ""
    kind = "" if e.kind == "top" else f" [{e.kind}]"
    return f"{g.modules[e.source].name}:{e.line} {e.source} -> {e.target}{what}{kind}"


def report(g: Graph) -> str:
    """The printed report of :func:`analyse`'s graph."""
    out: list[str] = []
    add = out.append
    room_lines: dict[str, int] = defaultdict(int)
    room_mods: dict[str, int] = defaultdict(int)
    for m, n in g.lines.items():
        room_lines[g.room_of(m)] += n
        room_mods[g.room_of(m)] += 1
    total = sum(room_lines.values())
    add(f"Rooms ({len(g.rooms)}; {total} lines in {len(g.modules)} modules)")
    for r in sorted(g.rooms, key=lambda r: -room_lines[r]):
        add(
            f"  {r:<11} {room_lines[r]:>6} lines {room_mods[r]:>3} modules"
            f" {100 * room_lines[r] / total:5.1f} %"
        )
    add("")
    add("Floors (bottom first; a room stands above every room it imports)")
    room_deps: dict[str, set[str]] = defaultdict(set)
    for a, b in g.room_edges():
        room_deps[a].add(b)
    for i, floor in enumerate(g.floors()):
        parts = []
        for r in floor:
            deps = sorted(set().union(*(room_deps[x] for x in r.split(" <-> "))) - {CORE})
            parts.append(f"{r} [{', '.join(deps) or '-'}]")
        add(f"  {i}: " + "; ".join(parts))
    add("")
    undeclared = g.undeclared()
    against = g.against_plan()
    add(f"Arrows against the declared 'May import:' lines ({len(against)})")
    if undeclared:
        add(f"  rooms without a 'May import:' line: {', '.join(undeclared)}")
    for a, b, e in against:
        if g.declared.get(a) is not None:
            add(f"  {a} -> {b}: {_where(g, e)}")
    add("")
    add(f"Compatibility re-exports (_LAZY names sent to another room: {len(g.compat)})")
    by_room: dict[tuple[str, str, bool], list[str]] = defaultdict(list)
    for c in g.compat:
        by_room[c.room, c.target, c.documented].append(c.name)
    for (room, target, documented), names in sorted(by_room.items()):
        flag = "" if documented else "  NOT DOCUMENTED AS COMPATIBILITY"
        add(f"  {room} -> {target}: {', '.join(sorted(names))}{flag}")
    through = g.through_compat()
    add(f"Imports inside src through a compatibility re-export ({len(through)})")
    for e in through:
        add(f"  {_where(g, e)}")
    add("")
    circles = g.room_circles()
    add(f"Circles between rooms ({len(circles)})")
    edges = g.room_edges()
    for c in circles:
        add("  " + " <-> ".join(c))
        for a in c:
            for b in c:
                for e in edges.get((a, b), []):
                    add(f"    {a} -> {b}: {_where(g, e)}")
    mcircles = g.module_circles()
    add(f"Circles between the modules of one room ({len(mcircles)})")
    for c in mcircles:
        add("  " + " <-> ".join(c))
        for e in g.edges:
            if e.source in c and e.target in c and e.source != e.target:
                add(f"    {_where(g, e)}")
    add("")
    private = g.private_imports()
    add(f"Cross-room private imports ({len(private)})")
    for e in private:
        add(f"  {_where(g, e)}")
    add("")
    long = g.long_modules()
    add(f"Modules over {MAX_LINES} lines ({len(long)})")
    for m, n in long:
        add(f"  {n:>5} {m}")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).resolve().parents[1] / "src"
    parser.add_argument("--src", type=Path, default=default, help="the src/ folder to read")
    args = parser.parse_args(argv)
    print(report(analyse(args.src)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
