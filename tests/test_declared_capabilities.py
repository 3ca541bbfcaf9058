"""The run side reaches other parts through declared capabilities only.

Every capability a cycle client, a scope source or an axis may offer is declared with
its default (runtime/clients.py, runtime/scope.py), so the controller, the jump planner
and the scope read attributes, never probe for one by name (`getattr(obj, "name",
default)`, `hasattr(obj, "name")`). (That no module imports one that imports it back
is test_layering.py's `test_no_module_cycles`.)
"""

from __future__ import annotations

import ast
from pathlib import Path

import motionvm

PACKAGE = Path(motionvm.__file__).parent
DECLARED = ("sim", "runtime")
"""The layers that read the capabilities of others: no probe by a literal name."""


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
