"""PDL checker, procedure calls: the argument rules of manual §1.3 (spec/PDL.md §9.1).

The number of arguments and each argument's type must match the declaration; there
are no default arguments and no overloading. Arguments pass by value; a pointer
parameter takes `&var` (or a pointer of the same type), an `instate` parameter a state.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.source.suggest import did_you_mean

if TYPE_CHECKING:
    from motionvm.lang.pdl.check_stmt import StatementChecker


def _param_text(p: n.Param) -> str:
    return f"{p.type} {'*' if p.pointer else ''}{p.name}"


def check_proc_call(sc: StatementChecker, s: n.ProcCall) -> None:
    """Report an undeclared procedure, a wrong argument count or a mismatched argument."""
    syms = sc.c.syms
    proc = syms.procs.get(s.name)
    if proc is None:
        if s.name in sc.c.scope.labels():
            sc.err(s.pos, f"'{s.name}' is a label: use 'call {s.name};'")
        else:
            sc.err(s.pos, f"procedure '{s.name}' is not declared before this call; define it "
                   f"above or add a prototype 'proc {s.name}(...);'"
                   + did_you_mean(s.name, syms.procs))
        for a in s.args:
            sc.kind(a)
        return
    syms.resolved[id(s)] = proc
    if proc.called_at is None:
        proc.called_at = s.pos
    kinds = [sc.kind(a, "arg") for a in s.args]
    if len(s.args) != len(proc.params):
        sc.err(s.pos, f"'{s.name}' takes {len(proc.params)} argument"
               f"{'s' if len(proc.params) != 1 else ''}, got {len(s.args)} (declared at "
               f"{proc.pos.line}:{proc.pos.col})")
        return
    for i, (a, k, p) in enumerate(zip(s.args, kinds, proc.params)):
        if k is None:
            continue
        problem = _mismatch(sc, a, k, p)
        if problem:
            sc.err(a.pos, f"argument {i + 1} of '{s.name}' does not fit parameter "
                   f"'{_param_text(p)}': {problem}")


def _mismatch(sc: StatementChecker, a: n.Operand, k: str, p: n.Param) -> str:
    """'' if argument `a` (of kind `k`) may be passed to `p`, else why not."""
    if p.type == "instate":
        if k == "state" or (k == "addr" and isinstance(a, n.AngleRef)):
            return ""
        if k == "int" and isinstance(a, n.VarRef):
            return ""  # a variable holding a state address
        return f"it needs a state, '<state>' or a variable holding a state address, not " \
               f"{_what(a, k)}"
    if p.pointer:
        want = f"ptr:{p.type}"
        if k == want:
            return ""
        return f"it needs '&' of a {'float' if p.type == 'float' else 'long or short'} " \
               f"variable, not {_what(a, k)}"
    if p.type == "long":
        if k == "int":
            return ""
        return f"it needs a long/short value or an integer constant, not {_what(a, k)}"
    if k == "float" or isinstance(a, n.IntConst):
        return ""
    return f"it needs a float value or a constant, not {_what(a, k)}"


def _what(a: n.Operand, k: str) -> str:
    if isinstance(a, n.FloatConst):
        return f"the float constant {a.value:g}"
    if isinstance(a, n.IntConst):
        return f"the integer constant {a.value}"
    text = {"int": "an integer", "float": "a float", "ptr:long": "a long pointer",
            "ptr:float": "a float pointer", "state": "a state", "addr": "an address constant",
            "string": "a string"}.get(k, "this value")
    if isinstance(a, (n.VarRef, n.Deref)):
        return f"'{a.name}' ({text})"
    return text

