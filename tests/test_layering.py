"""The layering rule, read from the imports of every module of the package.

Layers, lowest first: compiled_build (which build of the motion cycle the process
uses: it imports nothing of the package), source, runtime, drives, motion, io, comm, sim, lang, then
session, api, cli. A module imports only from its own layer or below — module-level
imports, function-local imports and `from motionvm import x` alike. The languages
(lang/hmpl, lang/pdl, lang/gdl) never import each other; modules directly in `lang/`
are shared by them. The package root only hands names on.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import motionvm

PACKAGE = Path(motionvm.__file__).parent
LAYERS = [
    "compiled_build",
    "source",
    "runtime",
    "drives",
    "motion",
    "io",
    "comm",
    "sim",
    "lang",
    "session",
    "api",
    "cli",
    "__main__",
]
RANK = {name: i for i, name in enumerate(LAYERS)}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def imported_modules(path: Path) -> list[tuple[int, str]]:
    """(line, dotted name) of every motionvm module `path` imports, anywhere in it."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    me = module_name(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    out: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names if a.name.startswith("motionvm")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if not mod.startswith("motionvm"):
                continue
            if mod == "motionvm":  # `from motionvm import x`: x is a submodule or a root name
                out += [(node.lineno, f"motionvm.{a.name}") for a in node.names]
            else:
                out.append((node.lineno, mod))
    return out


def layer_of(dotted: str) -> tuple[str, str | None]:
    """(layer, language or None) of a dotted module name inside the package."""
    parts = dotted.split(".")[1:]
    if not parts:
        return "root", None
    top = parts[0]
    if top == "lang" and len(parts) >= 2 and (PACKAGE / "lang" / parts[1]).is_dir():
        return "lang", parts[1]
    return top, None


def violations() -> list[str]:
    found: list[str] = []
    for path in modules():
        me = module_name(path)
        my_layer, my_lang = layer_of(me)
        if my_layer == "root":
            continue
        assert my_layer in RANK, f"{me}: a package outside the layering: add it to LAYERS"
        for line, target in imported_modules(path):
            layer, lang = layer_of(target)
            if layer == "root" or layer not in RANK:
                continue  # the root's names (__version__) and plain names
            where = f"{path.relative_to(PACKAGE.parent)}:{line}: {me} imports {target}"
            if RANK[layer] > RANK[my_layer]:
                found.append(f"{where} (a higher layer)")
            elif my_lang and lang and lang != my_lang:
                found.append(f"{where} (another language)")
    return found


def test_every_import_respects_the_layers():
    assert violations() == []


def test_the_package_root_only_hands_names_on():
    tree = ast.parse((PACKAGE / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        assert isinstance(node, (ast.Expr, ast.Assign, ast.Import, ast.ImportFrom)), ast.dump(node)


@pytest.mark.parametrize(
    "source, bad",
    [
        ("from motionvm.lang.hmpl.rtapi import X\n", True),
        ("def f():\n    from motionvm.session import Session\n", True),
        ("from motionvm import api\n", True),
        ("import motionvm.cli\n", True),
        ("from motionvm.runtime.clock import Clock\n", False),
        ("from motionvm.motion import kernel\n", False),
    ],
)
def test_the_checker_sees_every_form_of_import(tmp_path, monkeypatch, source, bad):
    """The checker itself: a module of the `motion` layer importing upwards is caught."""
    fake = PACKAGE / "motion" / "_layering_probe.py"
    monkeypatch.setattr(
        Path,
        "read_text",
        lambda self, encoding=None: source if self == fake else _read(self),
    )
    me = module_name(fake)
    hits = [
        t
        for _line, t in imported_modules(fake)
        if RANK.get(layer_of(t)[0], -1) > RANK[layer_of(me)[0]]
    ]
    assert bool(hits) is bad


_REAL_READ = Path.read_text


def _read(path: Path) -> str:
    return _REAL_READ(path, encoding="utf-8")


def test_no_import_circle_between_packages():
    """The package-level graph (lang/hmpl, lang/pdl, lang/gdl counted apart) has no cycle."""
    graph: dict[str, set[str]] = {}

    def pkg(dotted: str) -> str:
        layer, lang = layer_of(dotted)
        return f"lang.{lang}" if lang else layer

    for path in modules():
        me = pkg(module_name(path))
        for _line, target in imported_modules(path):
            other = pkg(target)
            if other != me and (other in RANK or other.startswith("lang.")):
                graph.setdefault(me, set()).add(other)
    seen: dict[str, int] = {}

    def visit(node: str, stack: list[str]) -> None:
        seen[node] = 1
        for nxt in sorted(graph.get(node, ())):
            if seen.get(nxt) == 1:
                pytest.fail("import circle: " + " -> ".join([*stack, node, nxt]))
            if nxt not in seen:
                visit(nxt, [*stack, node])
        seen[node] = 2

    for node in sorted(graph):
        if node not in seen:
            visit(node, [])
