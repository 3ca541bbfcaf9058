"""Small pieces shared by the statement lowering modules: source positions on generated
nodes, the loop context stack entries, and the budgeted back-edge every loop ends with."""

from __future__ import annotations

import ast
from dataclasses import dataclass, field

from motionvm.lang.hmpl.lvalues import name


@dataclass
class LoopCtx:
    kind: str  # 'loop' | 'switch'
    cont: list = field(default_factory=list)  # statements a `continue` runs (loops)
    flag: str = ""  # switch: temp set when a `continue` leaves the switch
    flag_used: bool = False


# A loop charges the task's budget in units of CHUNK back-edges, counting down a local
# (much cheaper per iteration than a global); the kernel refills `_budget` each cycle.
CHUNK = 64


def countdown_init(counter: str) -> ast.stmt:
    return ast.Assign(targets=[name(counter, True)], value=ast.Constant(CHUNK))


def backedge(counter: str) -> list[ast.stmt]:
    """`counter -= 1; if counter < 0: counter = CHUNK; _budget -= CHUNK; if _budget < 0: yield`."""
    dec = ast.AugAssign(target=name(counter, True), op=ast.Sub(), value=ast.Constant(1))
    charge = ast.AugAssign(target=name("_budget", True), op=ast.Sub(), value=ast.Constant(CHUNK))
    over = ast.Compare(left=name("_budget"), ops=[ast.Lt()], comparators=[ast.Constant(0)])
    refill = [
        ast.Assign(targets=[name(counter, True)], value=ast.Constant(CHUNK)),
        charge,
        ast.If(test=over, body=[ast.Expr(value=ast.Yield(value=None))], orelse=[]),
    ]
    test = ast.Compare(left=name(counter), ops=[ast.Lt()], comparators=[ast.Constant(0)])
    return [dec, ast.If(test=test, body=refill, orelse=[])]


_AST = ast.AST
_EXPR_CONTEXT = (ast.Load, ast.Store, ast.Del)


def at(stmts: list[ast.stmt], pos) -> list[ast.stmt]:
    """Give every generated node without a location the user's position `pos`.

    Subtrees that already carry a location were placed by an inner statement and are
    skipped, so each node is visited about once however deep the nesting.
    """
    line, col = pos.line, max(0, pos.col - 1)
    stack: list[ast.AST] = list(stmts)
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        if "lineno" in node._attributes:
            if getattr(node, "lineno", None) is not None:
                continue
            node.lineno = node.end_lineno = line
            node.col_offset = node.end_col_offset = col
        for value in node.__dict__.values():
            if type(value) is list:
                for v in value:
                    if isinstance(v, _AST) and not isinstance(v, _EXPR_CONTEXT):
                        push(v)
            elif isinstance(value, _AST) and not isinstance(value, _EXPR_CONTEXT):
                push(value)
    return stmts
