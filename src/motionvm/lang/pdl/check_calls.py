"""PDL checker, calls: procedures (manual §1.3) and built-in functions.

The number of arguments and each argument's type must match the declaration; there
are no default arguments and no overloading. Arguments pass by value; a pointer
parameter takes `&var` (or a pointer of the same type), an `instate` parameter a state.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.symbols import VarSym, describe
from motionvm.source.suggest import did_you_mean

ONE_ARG_FUNCS = ("abs", "unsign", "sign", "sin", "cos", "sqrt")
INTEGER_LAST_ARG = {
    "shift": "shift count",
    "bitset": "bit number",
    "bitclr": "bit number",
    "bittog": "bit number",
    "memcpy": "element count",
    "memset": "element count",
    "memmin": "element count",
    "memmax": "element count",
    "memsum": "element count",
}

if TYPE_CHECKING:
    from motionvm.lang.pdl.check_base import Operands


CALL_LIKE_KEYWORDS = ("sleep", "wait", "till", "halt", "printl", "prints", "retprintl", "tout",
                      "kill", "lock", "unlock", "seton", "setoff", "toggle", "sttovar", "sizeof")  # fmt: skip
"""Keywords written like a call (`sleep(5);`): a misspelt one parses as a procedure call."""


def _param_text(p: n.Param) -> str:
    return f"{p.type} {'*' if p.pointer else ''}{p.name}"


def check_proc_call(sc: Operands, s: n.ProcCall) -> None:
    """Report an undeclared procedure, a wrong argument count or a mismatched argument."""
    syms = sc.c.syms
    proc = syms.procs.get(s.name)
    if proc is None:
        if s.name in sc.c.scope.labels():
            sc.err(s.pos, f"'{s.name}' is a label: use 'call {s.name};'")
        else:
            sc.err(
                s.pos,
                f"procedure '{s.name}' is not declared before this call; define it "
                f"above or add a prototype 'proc {s.name}(...);'"
                + did_you_mean(s.name, [*syms.procs, *CALL_LIKE_KEYWORDS]),
            )
        for a in s.args:
            sc.kind(a)
        return
    syms.resolved[id(s)] = proc
    if proc.called_at is None:
        proc.called_at = s.pos
    kinds = [sc.kind(a, "arg") for a in s.args]
    if len(s.args) != len(proc.params):
        sc.err(
            s.pos,
            f"'{s.name}' takes {len(proc.params)} argument"
            f"{'s' if len(proc.params) != 1 else ''}, got {len(s.args)} (declared at "
            f"{proc.pos.line}:{proc.pos.col})",
        )
        return
    for i, (a, k, p) in enumerate(zip(s.args, kinds, proc.params)):
        if k is None:
            continue
        problem = _mismatch(sc, a, k, p)
        if problem:
            sc.err(
                a.pos,
                f"argument {i + 1} of '{s.name}' does not fit parameter "
                f"'{_param_text(p)}': {problem}",
            )


def _mismatch(sc: Operands, a: n.Operand, k: str, p: n.Param) -> str:
    """'' if argument `a` (of kind `k`) may be passed to `p`, else why not."""
    if p.type == "instate":
        if k == "state" or (k == "addr" and isinstance(a, n.AngleRef)):
            return ""
        if k == "int" and isinstance(a, n.VarRef):
            return ""  # a variable holding a state address
        return (
            f"it needs a state, '<state>' or a variable holding a state address, not {_what(a, k)}"
        )
    if p.pointer:
        want = f"ptr:{p.type}"
        if k == want:
            return ""
        return (
            f"it needs '&' of a {'float' if p.type == 'float' else 'long or short'} "
            f"variable, not {_what(a, k)}"
        )
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
    text = {
        "int": "an integer",
        "float": "a float",
        "ptr:long": "a long pointer",
        "ptr:float": "a float pointer",
        "state": "a state",
        "addr": "an address constant",
        "string": "a string",
    }.get(k, "this value")
    if isinstance(a, (n.VarRef, n.Deref)):
        return f"'{a.name}' ({text})"
    return text


def check_func_call(
    sc: Operands, f: n.FuncCall, tk: str | None, target: n.VarRef | n.Deref
) -> None:
    """Argument count, variables-first rule and types of a built-in function (§2.3)."""
    want = 1 if f.func in ONE_ARG_FUNCS else 2
    kinds = [sc.kind(a) for a in f.args]
    if len(f.args) != want:
        sc.err(
            f.pos, f"'{f.func}' takes {want} argument{'s' if want > 1 else ''}, got {len(f.args)}"
        )
        return
    for i, (a, k) in enumerate(zip(f.args, kinds)):
        last = i == len(f.args) - 1
        if isinstance(a, (n.IntConst, n.FloatConst)) and not last:
            sc.err(
                a.pos,
                f"argument {i + 1} of '{f.func}' must be a variable; only the "
                "last argument may be a constant",
            )
        elif not isinstance(a, (n.IntConst, n.FloatConst, n.VarRef)):
            sc.err(
                a.pos,
                f"arguments of '{f.func}' are variables or constants, not "
                f"{describe(k) if k else 'this'}",
            )
        elif k is not None and k not in ("int", "float"):
            sc.err(a.pos, f"argument {i + 1} of '{f.func}' must be a number, not {describe(k)}")
    count_name = INTEGER_LAST_ARG.get(f.func)
    if count_name and kinds[1] == "float":
        sc.err(f.args[1].pos, f"the {count_name} of '{f.func}' must be an integer")
    if f.func in ("shift", "bitset", "bitclr", "bittog") and kinds[0] == "float":
        sc.err(f.args[0].pos, f"'{f.func}' works on integers; the argument is float")
    if f.func in ("memcpy", "memset") and tk is not None and kinds[0] in ("int", "float"):
        tsym = sc.c.syms.resolved.get(id(target))
        asym = sc.c.syms.resolved.get(id(f.args[0]))
        if isinstance(tsym, VarSym) and isinstance(asym, VarSym) and tsym.type != asym.type:
            sc.err(
                f.pos,
                f"'{f.func}' does not convert types: the target is {tsym.type} "
                f"and '{asym.name}' is {asym.type}",
            )
