"""Text dumps of the PDL front-end stages, for `motionvm dump` and as test fixtures.

`dump_grammar` collects the parser's `# BNF:` lines: the grammar for docs/lang/pdl.md.

`dump_tokens` prints one token per line, `LINE:COL kind text`; `dump_ast` prints the
tree indented by two spaces per level, each node as `Name @LINE:COL` with its scalar
fields on the same line and its child nodes below.
"""

from __future__ import annotations

import dataclasses
import inspect
import re

from motionvm.lang.pdl import parser
from motionvm.lang.pdl.lexer import Token
from motionvm.source.files import SourcePos


def dump_tokens(toks: list[Token]) -> str:
    """One line per token: position, kind and spelling (macro origin in brackets)."""
    lines = []
    for t in toks:
        extra = f"  [from {t.origin.name}]" if t.origin is not None else ""
        lines.append(f"{t.pos.line}:{t.pos.col} {t.kind} {t.text}{extra}".rstrip())
    return "\n".join(lines) + "\n"


def _is_node(x: object) -> bool:
    return dataclasses.is_dataclass(x) and not isinstance(x, (type, SourcePos))


def _scalar(v: object) -> str:
    if isinstance(v, str):
        return repr(v)
    return str(v)


def dump_ast(node: object) -> str:
    """The tree under `node` (usually a `nodes.Program`) as indented text."""
    out: list[str] = []
    _dump(node, 0, "", out)
    return "\n".join(out) + "\n"


def _dump(node: object, depth: int, label: str, out: list[str]) -> None:
    pad = "  " * depth
    if not _is_node(node):
        out.append(f"{pad}{label}{_scalar(node)}")
        return
    head = f"{pad}{label}{type(node).__name__}"
    pos = getattr(node, "pos", None)
    if isinstance(pos, SourcePos):
        head += f" @{pos.line}:{pos.col}"
    children: list[tuple[str, object]] = []
    for f in dataclasses.fields(node):  # type: ignore[arg-type]
        if f.name == "pos":
            continue
        v = getattr(node, f.name)
        if _is_node(v) or (isinstance(v, tuple) and any(_is_node(x) for x in v)):
            children.append((f.name, v))
        elif v is not None and v != () and v is not False:
            head += f" {f.name}={_scalar(v)}"
    out.append(head)
    for name, v in children:
        if isinstance(v, tuple):
            out.append(f"{pad}  {name}:")
            for x in v:
                _dump(x, depth + 2, "", out)
        else:
            _dump(v, depth + 1, f"{name}: ", out)


def dump_grammar() -> str:
    """Every `# BNF:` line of the parser, in source order, one rule per line."""
    source = inspect.getsource(parser)
    return "".join(m + "\n" for m in re.findall(r"^\s*# BNF: (.*)$", source, re.MULTILINE))
