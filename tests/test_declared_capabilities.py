"""The run side reaches other parts through declared capabilities only, and its modules
import each other without circles.

Every capability a cycle client, a scope source or an axis may offer is declared with
its default (runtime/clients.py, runtime/scope.py), so the controller, the jump planner
and the scope read attributes, never probe for one by name (`getattr(obj, "name",
default)`, `hasattr(obj, "name")`). And the modules of `runtime/`, `drives/`, `motion/`
and `sim/` import each other (module-level or function-local imports alike) in one
direction only.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import motionvm

PACKAGE = Path(motionvm.__file__).parent
DECLARED = ("sim", "runtime")
"""The layers that read the capabilities of others: no probe by a literal name."""
ACYCLIC = ("runtime", "drives", "motion", "sim")
"""The layers whose modules import each other without circles."""


def _files(layers: tuple[str, ...]) -> list[Path]:
    return sorted(p for layer in layers for p in (PACKAGE / layer).rglob("*.py"))


def _probes(source: str) -> list[tuple[int, str]]:
    """(line, text) of each `getattr`/`hasattr` call of `source` with a literal name."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id in ("getattr", "hasattr") and len(node.args) >= 2
                and isinstance(node.args[1], ast.Constant)):  # fmt: skip
            out.append((node.lineno, ast.unparse(node)))
    return out


def test_no_probe_by_literal_name_in_the_controller_and_the_run_time():
    found = [f"{path.relative_to(PACKAGE)}:{line}: {text}"
             for path in _files(DECLARED) for line, text in _probes(path.read_text("utf-8"))]  # fmt: skip
    assert found == [], "declare the capability instead:\n" + "\n".join(found)


def test_the_probe_finder_finds_a_probe():
    source = "x = getattr(client, 'observes_motion', True)\ny = getattr(a, name)\nhasattr(b, 'c')\n"
    assert [line for line, _ in _probes(source)] == [1, 3]


def _module(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path, package: str) -> set[str]:
    """The modules of the package that `path` imports, anywhere in it."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text("utf-8"))):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("motionvm."))
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                name = f"{base}.{node.module}" if node.module else base
            else:
                name = node.module or ""
            if name.startswith("motionvm."):
                out.add(name)
                out.update(f"{name}.{a.name}" for a in node.names)
    return out


def _graph() -> dict[str, set[str]]:
    files = {_module(p): p for p in _files(ACYCLIC)}
    graph = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        graph[name] = {m for m in _imports(path, package) if m in files and m != name}
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
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
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_circles_in_the_run_side():
    # (a package's __init__ that hands on its modules' names is no circle of theirs)
    graph = _graph()
    for name in graph:
        if (PACKAGE.parent / name.replace(".", "/") / "__init__.py").exists():
            graph[name] = set()
    assert _circles(graph) == []


@pytest.mark.parametrize(
    ("graph", "circles"),
    [
        ({"a": {"b"}, "b": {"a"}, "c": set()}, [["a", "b"]]),
        ({"a": {"b"}, "b": {"c"}, "c": set()}, []),
    ],
)
def test_the_circle_finder(graph, circles):
    assert _circles(graph) == circles
