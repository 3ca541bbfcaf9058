"""Walks over any language's syntax tree, for what tools see inside a program.

Every language's AST is made of dataclasses with a `pos: SourcePos` (STYLE: one AST file
per language), so one walker serves all: `nodes(tree)` yields every node in source
order, `statement_lines(tree, kinds, path)` is a file's line table.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

from motionvm.lang.interface import LineTable


def nodes(tree: object) -> Iterator[object]:
    """Every dataclass node under `tree` (itself included), depth first, in field order."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, list | tuple):
            stack.extend(reversed(node))
            continue
        if not dataclasses.is_dataclass(node) or isinstance(node, type):
            continue
        yield node
        children = [getattr(node, f.name) for f in dataclasses.fields(node) if f.name != "pos"]
        stack.extend(reversed(children))


def statement_lines(
    tree: object, kinds: tuple[type, ...], path: str, branch: type | None = None
) -> LineTable:
    """The lines of `path` where a node of one of `kinds` (the statements) starts, and
    those where a `branch` node (the `if` statement) starts."""
    lines = set()
    branches = set()
    for node in nodes(tree):
        if isinstance(node, kinds):
            pos = node.pos  # type: ignore[attr-defined]
            if pos is not None and pos.file == path:
                lines.add(pos.line)
                if branch is not None and isinstance(node, branch):
                    branches.add(pos.line)
    return LineTable(path, frozenset(lines), frozenset(branches))
