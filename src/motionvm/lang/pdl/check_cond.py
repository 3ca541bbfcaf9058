"""PDL checker, conditions: states, `<var>`, relations, TOUT and bit tests (manual §2.2.8).

A bare name in a condition must be a state; a short/long variable holding a state
address is written `<var>`; relations compare numbers; TOUT takes an integer start
time on the left and an integer duration on the right.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.symbols import describe, sym_kind_text

if TYPE_CHECKING:
    from motionvm.lang.pdl.check_base import Operands


def check_cond(sc: Operands, c: n.Cond) -> None:
    """Report names and operands that do not fit a condition."""
    if isinstance(c, n.Logic):
        for t in c.terms:
            check_cond(sc, t)
    elif isinstance(c, n.Not):
        check_cond(sc, c.operand)
    elif isinstance(c, n.StateTest):
        _state_test(sc, c)
    elif isinstance(c, n.BitTest):
        k = sc.kind(c.var)
        if k is not None and k != "int":
            sc.err(c.var.pos, f"'->' tests a bit of a short/long variable, not {describe(k)}")
        if not 0 <= c.bit <= 31:
            sc.err(c.pos, f"bit {c.bit} is out of range 0..31")
    elif isinstance(c, n.Relation):
        _relation(sc, c)


def _state_test(sc: Operands, c: n.StateTest) -> None:
    ref = c.ref
    if isinstance(ref, n.AngleRef):
        sc.angle(ref, "state")
        return
    sym = sc.var(ref, ref.name)
    if sym is None:
        return
    if sym.type == "instate":
        sc.err(ref.pos, f"'{ref.name}' holds a state reference; write '<{ref.name}>'")
    elif sym.type != "state":
        sc.err(
            ref.pos,
            f"'{ref.name}' is {sym_kind_text(sym)}, not a state: compare it "
            f"('{ref.name}<>0') or write '<{ref.name}>' if it holds a state address",
        )


def _relation(sc: Operands, c: n.Relation) -> None:
    lk, rk = sc.kind(c.left, "value"), sc.kind(c.right, "value")
    for side, k in ((c.left, lk), (c.right, rk)):
        if k in ("string",) or isinstance(side, n.AddressOf):
            sc.err(side.pos, f"'{c.op}' compares numbers, not {describe(k)}")
            return
    if c.op == "TOUT":
        if not isinstance(c.left, (n.VarRef, n.Deref)) or lk not in ("int", None):
            sc.err(
                c.left.pos, "the left operand of TOUT is a short/long variable holding a start time"
            )
        if rk not in ("int", None) or isinstance(c.right, n.AngleRef):
            sc.err(
                c.right.pos,
                "the right operand of TOUT is an integer variable or "
                "constant (a duration in fclk ticks)",
            )
