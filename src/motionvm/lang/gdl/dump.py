"""Dumps of the GDL stages for `motionvm dump --stage tokens|ast FILE` and for tests.

Tokens: one per line, `LINE:COL KIND TEXT`. AST: an indented tree of node class names
and fields, positions left out except the line of each instruction and declaration.
"""

from __future__ import annotations

import dataclasses

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.parser import parse_tokens
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourceFile

_LINE_NODES = (
    n.Module,
    n.UseDecl,
    n.ObjectDecl,
    n.Procedure,
    n.Assign,
    n.OperatorCall,
    n.If,
    n.While,
    n.Return,
)


def dump_tokens(path: str, sink: DiagnosticSink) -> str:
    """The tokens of one file."""
    toks = tokenize(path, SourceFile.read(path).text, sink)
    lines = []
    for t in toks:
        shown = repr(t.value) if t.kind == "string" else t.text
        lines.append(f"{t.pos.line}:{t.pos.col} {t.kind} {shown}".rstrip())
    return "\n".join(lines) + "\n"


def format_node(node: object, indent: int = 0) -> list[str]:
    """An AST node as indented lines: `Class` then `field: value` or nested nodes."""
    pad = "  " * indent
    if isinstance(node, n.Name):
        return [f"{pad}{node.text}"]
    if not dataclasses.is_dataclass(node):
        return [f"{pad}{node!r}"]
    head = type(node).__name__
    if isinstance(node, _LINE_NODES):
        head += f" @{node.pos.line}"  # type: ignore[attr-defined]
    fields = [f for f in dataclasses.fields(node) if f.name != "pos"]
    values = [getattr(node, f.name) for f in fields]
    if all(not isinstance(v, tuple) and not dataclasses.is_dataclass(v) for v in values):
        inline = " ".join(f"{f.name}={v!r}" for f, v in zip(fields, values, strict=True))
        return [f"{pad}{head} {inline}".rstrip()]
    out = [pad + head]
    for f in dataclasses.fields(node):
        if f.name == "pos":
            continue
        value = getattr(node, f.name)
        if isinstance(value, tuple):
            if not value:
                continue
            out.append(f"{pad}  {f.name}:")
            for item in value:
                out += format_node(item, indent + 2)
        elif dataclasses.is_dataclass(value):
            sub = format_node(value, indent + 2)
            if len(sub) == 1:
                out.append(f"{pad}  {f.name}: {sub[0].strip()}")
            else:
                out.append(f"{pad}  {f.name}:")
                out += sub
        elif value is not None:
            out.append(f"{pad}  {f.name}: {value!r}")
    return out


def dump_ast(path: str, sink: DiagnosticSink) -> str:
    """The AST of one file (whatever parsed, even with errors in `sink`)."""
    toks = tokenize(path, SourceFile.read(path).text, sink)
    return "\n".join(format_node(parse_tokens(toks, path, sink))) + "\n"
