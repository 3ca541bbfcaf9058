"""Readable, deterministic dumps of HMPL tokens and ASTs (`motionvm dump --stage tokens|ast`).

Positions print as `@LINE:COL`; the file name is shown where it changes (tokens) or
differs from the translation unit's file (AST). AST fields equal to their default
(None, False, '', empty tuple, 0) are left out to keep the dump short.
"""

from __future__ import annotations

import dataclasses

from motionvm.lang.hmpl.nodes import TranslationUnit
from motionvm.lang.hmpl.tokens import Token
from motionvm.source.files import SourcePos


def dump_tokens(tokens: list[Token]) -> str:
    """One token per line: `LINE:COL  KIND  TEXT  [VALUE]`, a `# file:` line where the file changes."""
    out: list[str] = []
    current = None
    for t in tokens:
        if t.pos.file != current:
            current = t.pos.file
            out.append(f"# file: {current}")
        line = f"{t.pos.line}:{t.pos.col}\t{t.kind}\t{t.text}"
        if t.kind in ("int", "float", "char", "string"):
            line += f"\t{t.value!r}"
            if t.suffix:
                line += f"\tsuffix={t.suffix}"
        out.append(line)
    return "\n".join(out) + "\n"


def dump_ast(tu: TranslationUnit) -> str:
    """The tree, one node per line, children indented by two spaces."""
    out: list[str] = []
    _node(tu, tu.pos.file, 0, "", out)
    return "\n".join(out) + "\n"


def _pos(pos: SourcePos, root_file: str) -> str:
    where = f"{pos.line}:{pos.col}"
    return f"@{where}" if pos.file == root_file else f"@{pos.file}:{where}"


def _is_node(v: object) -> bool:
    return dataclasses.is_dataclass(v) and not isinstance(v, type)


def _node(node: object, root: str, depth: int, label: str, out: list[str]) -> None:
    pad = "  " * depth
    scalars: list[str] = []
    children: list[tuple[str, object]] = []
    for f in dataclasses.fields(node):  # type: ignore[arg-type]
        if f.name == "pos":
            continue
        v = getattr(node, f.name)
        if f.default is not dataclasses.MISSING and v == f.default and not _is_node(v):
            continue
        if _is_node(v):
            children.append((f.name, v))
        elif isinstance(v, tuple):
            if not v:
                continue
            if all(x is None or not _is_node(x) for x in v):
                scalars.append(f"{f.name}={v!r}")
            else:
                children.append((f.name, v))
        else:
            scalars.append(f"{f.name}={v!r}")
    head = f"{pad}{label}{type(node).__name__} {_pos(node.pos, root)}"  # type: ignore[attr-defined]
    out.append(" ".join([head, *scalars]))
    for name, v in children:
        if isinstance(v, tuple):
            out.append(f"{pad}  {name}:")
            for x in v:
                if x is None:
                    out.append(f"{pad}    None")
                else:
                    _node(x, root, depth + 2, "", out)
        else:
            _node(v, root, depth + 1, f"{name}: ", out)
