"""The command line's modules import each other without a circle: the grammar
(cli/options.py) sits below the commands, and a command never imports the grammar back.
The package itself (cli/__init__.py, the dispatcher that every command may call) is left
out."""

from __future__ import annotations

import ast
from pathlib import Path

import motionvm.cli

CLI = Path(motionvm.cli.__file__).parent


def cli_imports(path: Path) -> set[str]:
    """The cli modules (by file stem) that `path` imports anywhere in it."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module.startswith("motionvm.cli."):
                found.add(node.module.split(".")[2])
            elif node.module == "motionvm.cli":
                found.update(a.name for a in node.names if (CLI / f"{a.name}.py").exists())
    return found


def test_no_module_of_the_cli_imports_itself_back():
    graph = {p.stem: cli_imports(p) for p in CLI.glob("*.py") if p.stem != "__init__"}

    def reaches(start: str, goal: str, seen: set[str]) -> bool:
        for nxt in graph.get(start, ()):
            if nxt == goal or (nxt not in seen and reaches(nxt, goal, seen | {nxt})):
                return True
        return False

    circles = sorted(m for m in graph if reaches(m, m, {m}))
    assert circles == []
