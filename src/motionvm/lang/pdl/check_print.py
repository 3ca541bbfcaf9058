"""PDL checker, printl/prints/retprintl: argument count and format string (manual §2.4).

Up to 8 arguments; conversions follow C printf; `%s` takes the longs that hold a string,
4 characters each, so with `%s` the argument count is only bounded from below. A
conversion whose type does not fit its argument is a warning.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.printfmt import (
    FLOAT_CONVERSIONS,
    INT_CONVERSIONS,
    Conversion,
    count_arguments,
    parse_format,
)
from motionvm.lang.pdl.symbols import MAX_PRINT_ARGS, VarSym
from motionvm.source.files import SourcePos

if TYPE_CHECKING:
    from motionvm.lang.pdl.check_base import Operands


def check_print(sc: Operands, s: n.Print) -> None:
    """At most 8 arguments, a well-formed format, one argument per conversion."""
    for a in s.args:
        k = sc.kind(a)
        if k == "string":
            sc.err(a.pos, "a string cannot be an argument; put the text in the format")
    if len(s.args) > MAX_PRINT_ARGS:
        sc.err(
            s.args[MAX_PRINT_ARGS].pos,
            f"'{s.command}' takes at most {MAX_PRINT_ARGS} arguments, got {len(s.args)}",
        )
    parts, issues = parse_format(s.format.value)
    fpos = s.format.pos
    for issue in issues:
        sc.err(SourcePos(fpos.file, fpos.line, fpos.col + 1 + issue.offset), issue.message)
    if issues:
        return
    count, has_s = count_arguments(parts)
    if (not has_s and count != len(s.args)) or (has_s and len(s.args) < count):
        sc.err(
            fpos,
            f"the format has {count} conversion{'s' if count != 1 else ''} but "
            f"{len(s.args)} argument{'s' if len(s.args) != 1 else ''} "
            f"{'is' if len(s.args) == 1 else 'are'} given",
        )
        return
    if has_s:
        return
    convs = [p for p in parts if isinstance(p, Conversion)]
    for conv, a in zip(convs, s.args):
        k = _kind_quiet(sc, a)
        if conv.conv in FLOAT_CONVERSIONS and k == "int" and not isinstance(a, n.IntConst):
            sc.sink.warning(a.pos, f"'{conv.text}' shows a float but the argument is an integer")
        elif conv.conv in INT_CONVERSIONS and k == "float":
            sc.sink.warning(
                a.pos, f"'{conv.text}' shows an integer but the argument is a float (use %g)"
            )


def _kind_quiet(sc: Operands, op: n.Operand) -> str | None:
    """The kind of an already checked operand, without reporting anything again."""
    sym = sc.c.syms.resolved.get(id(op))
    if isinstance(op, n.FloatConst):
        return "float"
    if isinstance(op, n.IntConst):
        return "int"
    if isinstance(op, (n.VarRef, n.Deref)) and isinstance(sym, VarSym):
        if sym.pointer and isinstance(op, n.VarRef):
            return "ptr"
        return {"float": "float", "long": "int", "short": "int"}.get(sym.type)
    return None
