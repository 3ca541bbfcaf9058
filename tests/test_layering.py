"""The layering rule, read from the imports of every module of the package.

Layers, lowest first: compiled_build (which build of the motion cycle the process
uses: it imports nothing of the package), source, runtime, drives, motion, io, comm, sim, lang, then
session, api, cli. A module imports only from its own layer or below — module-level
imports, function-local imports and `from motionvm import x` alike. The languages
(lang/hmpl, lang/pdl, lang/gdl) never import each other; modules directly in `lang/`
are shared by them. The package root only hands names on. No module imports one that
imports it back (`test_no_module_cycles`).
"""

from __future__ import annotations

import ast
import functools
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
    "debug",
    "api",
    "dap",
    "lsp",
    "studio",
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
            elif lang and RANK[my_layer] > RANK["lang"]:
                found.append(f"{where} (a language package: reach it through motionvm.lang)")
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
        ("from motionvm.lang import LANGUAGES\n", True),
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
        registry = module_name(path) == "motionvm.lang"  # lists the languages: left out
        for _line, target in imported_modules(path):
            other = pkg(target)
            if registry and other.startswith("lang."):
                continue
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


def module_imports(path: Path) -> list[tuple[int, str]]:
    """(line, module) of every motionvm module `path` imports, anywhere in it, naming the
    submodule itself for `from package import submodule` (`imported_modules` names the
    package): the edges of the module graph."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    me = module_name(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    known = known_modules()
    out: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names if a.name in known]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                target = f"{mod}.{a.name}" if f"{mod}.{a.name}" in known else mod
                if target in known:
                    out.append((node.lineno, target))
    return out


@functools.cache
def known_modules() -> dict[str, Path]:
    """Dotted name -> file of every module of the package."""
    return {module_name(p): p for p in modules()}


# Circles still to take apart: a circle found by the test must lie inside one of these
# sets of modules (it may shrink, never grow). None is left.
ALLOWED_CIRCLES: list[set[str]] = []


def module_graph() -> dict[str, dict[str, int]]:
    """module -> {module it imports: line}; the registry's imports of the languages
    (`motionvm/lang/__init__.py` -> `motionvm.lang.<language>...`) left out: the
    languages register there, and reach the registry only through their own modules."""
    graph: dict[str, dict[str, int]] = {}
    for me, path in known_modules().items():
        edges = graph.setdefault(me, {})
        for line, target in module_imports(path):
            if target == me:
                continue
            if me == "motionvm.lang" and layer_of(target)[1] is not None:
                continue
            edges.setdefault(target, line)
    return graph


def circles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, nexts = work[-1]
            for nxt in nexts:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph.get(nxt, ())))))
                    break
                if nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        x = stack.pop()
                        on_stack.discard(x)
                        comp.append(x)
                        if x == node:
                            break
                    if len(comp) > 1:
                        found.append(sorted(comp))
    return found


def test_no_module_cycles():
    """No module imports one that imports it back, directly or through others
    (module-level and function-local imports alike, `TYPE_CHECKING` ones too)."""
    graph = module_graph()
    bad = []
    for comp in circles(graph):
        if any(set(comp) <= allowed for allowed in ALLOWED_CIRCLES):
            continue
        members = set(comp)
        edges = [
            f"  {known_modules()[a].relative_to(PACKAGE.parent)}:{line}: {a} imports {b}"
            for a in comp
            for b, line in sorted(graph[a].items())
            if b in members
        ]
        bad.append("import circle of " + ", ".join(comp) + "\n" + "\n".join(edges))
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize(
    "graph, expected",
    [
        ({"a": {"b": 1}, "b": {"c": 1}, "c": {}}, []),
        ({"a": {"b": 1}, "b": {"a": 1}}, [["a", "b"]]),
        ({"a": {"b": 1}, "b": {"c": 1}, "c": {"a": 1}, "d": {"a": 1}}, [["a", "b", "c"]]),
    ],
)
def test_the_circle_finder(graph, expected):
    assert circles(graph) == expected


def test_from_package_import_submodule_is_an_edge_to_the_submodule():
    edges = dict((t, line) for line, t in module_imports(PACKAGE / "lang" / "pdl" / "lower.py"))
    assert "motionvm.lang.pdl.nodes" in edges  # `from motionvm.lang.pdl import nodes as n`
    assert "motionvm.lang.pdl" not in edges


def test_a_face_reaches_a_language_only_through_the_registry(monkeypatch):
    """The checker flags a module above `lang/` that imports a language package."""
    fake = PACKAGE / "api.py"
    monkeypatch.setattr(
        Path,
        "read_text",
        lambda self, encoding=None: (
            "from motionvm.lang.gdl.client import X\n" if self == fake else _read(self)
        ),
    )
    assert any("reach it through motionvm.lang" in v for v in violations())


LANGUAGE_WORDS = ("hmpl", "pdl", "gdl")


def language_identifiers(path: Path) -> list[str]:
    """Every identifier in `path` (names, attributes, definitions, parameters, keywords)
    that names a language (`hmpl`, `pdl` or `gdl` in it, any case), once per use."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found: list[str] = []
    for node in ast.walk(tree):
        names: list[str] = []
        if isinstance(node, ast.Name):
            names.append(node.id)
        elif isinstance(node, ast.Attribute):
            names.append(node.attr)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.append(node.name)
        elif isinstance(node, ast.arg):
            names.append(node.arg)
        elif isinstance(node, ast.keyword) and node.arg:
            names.append(node.arg)
        elif isinstance(node, ast.alias):
            names.append(node.asname or node.name.split(".")[-1])
        found += [n for n in names if any(w in n.lower() for w in LANGUAGE_WORDS)]
    return found


def test_the_session_and_the_command_line_hardly_name_a_language():
    """They loop over the languages of `motionvm.lang` instead of naming them."""
    files = [PACKAGE / "session.py", *sorted((PACKAGE / "cli").glob("*.py"))]
    named = {str(p.relative_to(PACKAGE)): language_identifiers(p) for p in files}
    total = sum(len(v) for v in named.values())
    assert total <= 10, {k: v for k, v in named.items() if v}
