"""PDL checker, statements: operand kinds, assignment forms, conditions, calls, printl.

Operand kinds: 'int' (long/short value or integer constant), 'float', 'ptr:long' and
'ptr:float' (pointers and `&var`), 'state' (a state's 0/1), 'addr' (the constant
`<state>` or `<label>`), 'string'; None after an error was reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.check_calls import check_func_call, check_proc_call
from motionvm.lang.pdl.check_cond import check_cond
from motionvm.lang.pdl.check_print import check_print
from motionvm.lang.pdl.symbols import (
    MAX_INIT_VALUES,
    VarSym,
    describe,
    sym_kind_text,
)
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

if TYPE_CHECKING:
    from motionvm.lang.pdl.check_base import Declarations

INT_ONLY_OPS = ("%", "&", "|", "@", "%=", "&=", "|=", "@=")


class StatementChecker:
    """The statement half of the checker; shares scopes and the sink with `Checker`."""

    def __init__(self, checker: Declarations) -> None:
        self.c = checker
        self.sink = checker.sink
        self.reported: set[tuple[str, str]] = set()

    def err(self, pos: SourcePos, msg: str) -> None:
        self.sink.error(pos, msg)

    # ------------------------------------------------------------ names

    def var(self, node: n.VarRef | n.Deref | n.AngleRef, name: str) -> VarSym | None:
        sym = self.c.scope.lookup(name)
        if sym is None:
            syms = self.c.syms
            if name in syms.procs:
                self.err(node.pos, f"'{name}' is a procedure, not a variable")
            elif name in self.c.scope.labels():
                self.err(node.pos, f"'{name}' is a label, not a variable")
            else:
                key = (self.c.scope.proc.name if self.c.scope.proc else "", name)
                if key not in self.reported:  # one message per name and scope
                    self.reported.add(key)
                    self.err(
                        node.pos,
                        f"undeclared variable '{name}'"
                        + did_you_mean(name, self.c.scope.visible_names()),
                    )
            return None
        self.c.syms.resolved[id(node)] = sym
        return sym

    def index(self, idx: n.IntConst | n.VarRef | None) -> None:
        if idx is None or isinstance(idx, n.IntConst):
            if isinstance(idx, n.IntConst) and idx.value < 0:
                self.err(idx.pos, "an index cannot be negative")
            return
        sym = self.var(idx, idx.name)
        if sym is not None and not sym.is_int:
            self.err(
                idx.pos,
                f"index '{idx.name}' must be a short or long variable, not {sym_kind_text(sym)}",
            )

    def kind(self, op: n.Operand | n.Value, ctx: str = "value") -> str | None:
        """The kind of an operand, reporting names that do not resolve."""
        if isinstance(op, n.IntConst):
            return "int"
        if isinstance(op, n.FloatConst):
            return "float"
        if isinstance(op, n.StringConst):
            return "string"
        if isinstance(op, n.VarRef):
            sym = self.var(op, op.name)
            self.index(op.index)
            if sym is None:
                return None
            if sym.type in ("state", "instate"):
                if op.index is not None:
                    self.err(op.pos, f"the state '{op.name}' cannot be indexed")
                return "state"
            return (
                f"ptr:{'float' if sym.type == 'float' else 'long'}"
                if sym.pointer
                else ("float" if sym.type == "float" else "int")
            )
        if isinstance(op, n.Deref):
            sym = self.var(op, op.name)
            self.index(op.index)
            if sym is None:
                return None
            if not sym.pointer:
                self.err(
                    op.pos,
                    f"'{op.name}' is not a pointer; '*' applies only to variables "
                    "declared with '*'",
                )
                return None
            return "float" if sym.type == "float" else "int"
        if isinstance(op, n.AddressOf):
            sym = self.var(op.target, op.target.name)
            self.index(op.target.index)
            if sym is None:
                return None
            if sym.type in ("state", "instate"):
                self.err(
                    op.pos,
                    f"'&{op.target.name}': a state has no variable address; "
                    f"'<{op.target.name}>' is its state address",
                )
                return None
            return "ptr:float" if sym.type == "float" else "ptr:long"
        if isinstance(op, n.AngleRef):
            return self.angle(op, ctx)
        return None

    def angle(self, op: n.AngleRef, ctx: str) -> str | None:
        """`<name>`: 'addr' for a state or label in a value context, else 'state'."""
        sym = self.c.scope.lookup(op.name)
        if sym is not None:
            self.c.syms.resolved[id(op)] = sym
            if sym.type == "state":
                return "addr" if ctx == "value" else "state"
            if sym.type == "instate" or sym.is_int:
                return "state"
            self.err(
                op.pos,
                f"'<{op.name}>': '{op.name}' is {sym_kind_text(sym)}; only a "
                "short/long variable can hold a state address",
            )
            return None
        label = self.c.scope.labels().get(op.name)
        if label is not None:
            self.c.syms.resolved[id(op)] = label
            if ctx != "value":
                self.err(op.pos, f"'<{op.name}>' is a label address, not a state")
                return None
            return "addr"
        self.err(
            op.pos,
            f"'<{op.name}>': '{op.name}' is not a state, label or variable"
            + did_you_mean(op.name, self.c.scope.visible_names()),
        )
        return None

    # ------------------------------------------------------------ statements

    def statement(self, s: n.Item) -> None:
        getattr(self, "visit_" + type(s).__name__)(s)

    def target(self, t: n.VarRef | n.Deref) -> str | None:
        k = self.kind(t, "target")
        if isinstance(t, n.VarRef):
            sym = self.c.syms.resolved.get(id(t))
            if isinstance(sym, VarSym):
                if sym.type in ("state", "instate"):
                    self.err(
                        t.pos,
                        f"'{t.name}' is a state: change it with seton/setoff/toggle "
                        f"or '{t.name} = condition;'",
                    )
                    return None
                if sym.read_only and sym.scope == "system":
                    self.err(t.pos, f"the system variable '{sym.name}' is read-only")
                    return None
        return k

    def visit_Assign(self, s: n.Assign) -> None:
        tk = self.target(s.target)
        v = s.value
        if s.op != "=":
            vk = self.kind(v)
            if vk in ("string", "addr", "state") or isinstance(v, n.AddressOf):
                self.err(v.pos, f"'{s.op}' needs a number on the right, not {describe(vk)}")
            elif s.op in INT_ONLY_OPS and "float" in (tk, vk):
                self.err(
                    s.pos,
                    f"'{s.op}' works on integers only; "
                    f"{'the target' if tk == 'float' else 'the right-hand side'} is float",
                )
            elif tk and tk.startswith("ptr:") and s.op not in ("+=", "-="):
                self.err(s.pos, f"'{s.op}' cannot be applied to a pointer")
            return
        if isinstance(v, n.InitList):
            if len(v.values) > MAX_INIT_VALUES:
                self.err(
                    v.pos,
                    f"an initialiser holds at most {MAX_INIT_VALUES} values; this one "
                    f"has {len(v.values)} (split it: 'a[{MAX_INIT_VALUES}] = {{...}};')",
                )
            if tk and tk.startswith("ptr:"):
                self.err(v.pos, "an initialiser cannot be assigned to a pointer")
            return
        if isinstance(v, n.StringConst):
            sym = self.c.syms.resolved.get(id(s.target))
            if tk is not None and (
                tk != "int"
                or (isinstance(sym, VarSym) and sym.type != "long")
                or isinstance(s.target, n.Deref)
            ):
                self.err(
                    v.pos,
                    "a string can only be assigned to a long variable or array "
                    "(4 characters per element)",
                )
            return
        if isinstance(v, n.SttoVar):
            check_cond(self, v.cond)
            if tk is not None and tk not in ("int", "float"):
                self.err(
                    s.pos,
                    f"'sttovar' stores 0 or 1 into a long, short or float, not {describe(tk)}",
                )
            return
        if isinstance(v, n.SizeOf):
            sym = self.c.scope.lookup(v.name)
            if sym is None or sym.type in ("state", "instate"):
                self.err(
                    v.pos,
                    f"'sizeof({v.name})': '{v.name}' is not a variable"
                    + ("" if sym else did_you_mean(v.name, self.c.scope.visible_names())),
                )
            else:
                self.c.syms.resolved[id(v)] = sym
            return
        if isinstance(v, n.FuncCall):
            check_func_call(self, v, tk, s.target)
            return
        if isinstance(v, n.Neg):
            k = self.kind(v.operand)
            if k is not None and k not in ("int", "float"):
                self.err(v.pos, f"'-' needs a number, not {describe(k)}")
            return
        if isinstance(v, n.BinOp):
            vk = self.binop(v)
        else:
            vk = self.kind(v)
        self.assign_compat(s, tk, vk)

    def assign_compat(self, s: n.Assign, tk: str | None, vk: str | None) -> None:
        if tk is None or vk is None:
            return
        if vk == "string":
            return
        if vk == "state":
            if isinstance(s.value, n.VarRef):
                self.err(
                    s.value.pos,
                    f"'{s.value.name}' is a state, not a value: write "
                    f"'v = sttovar {s.value.name};' to store it as 0 or 1",
                )
            return
        if tk.startswith("ptr:"):
            if vk.startswith("ptr:") and vk != tk:
                self.err(
                    s.value.pos,
                    f"{describe(tk)} cannot point to "
                    f"{'a float' if vk == 'ptr:float' else 'a long or short'} variable",
                )
            elif not vk.startswith("ptr:"):
                self.err(
                    s.value.pos,
                    f"a pointer is set from '&variable' or another pointer, not {describe(vk)}",
                )
            return
        if vk.startswith("ptr:") and tk == "float":
            self.err(s.value.pos, "an address cannot be stored in a float")

    def binop(self, b: n.BinOp) -> str | None:
        lk, rk = self.kind(b.left), self.kind(b.right)
        for side, k in ((b.left, lk), (b.right, rk)):
            if isinstance(side, n.AddressOf):
                self.err(
                    side.pos, "'&var' cannot be used in an operation; store it in a pointer first"
                )
                return None
            if k in ("string", "addr", "state"):
                self.err(side.pos, f"'{b.op}' needs numbers, not {describe(k)}")
                return None
        if lk is None or rk is None:
            return None
        if b.op in INT_ONLY_OPS and "float" in (lk, rk):
            self.err(b.pos, f"'{b.op}' works on integers only; an operand is float")
            return None
        if lk.startswith("ptr:"):
            if b.op not in ("+", "-") or rk != "int":
                self.err(b.pos, "pointer arithmetic is 'pointer + integer' or 'pointer - integer'")
                return None
            return lk
        if rk.startswith("ptr:"):
            self.err(b.pos, "a pointer can only be the left operand of '+' or '-'")
            return None
        return "float" if "float" in (lk, rk) else "int"

    def visit_StateAssign(self, s: n.StateAssign) -> None:
        self.kind(s.state)
        check_cond(self, s.cond)

    def visit_IncDec(self, s: n.IncDec) -> None:
        k = self.target(s.target)
        if k == "float":
            self.err(s.pos, f"'{s.op}' works on long or short variables, not float")

    def visit_Goto(self, s: n.Goto) -> None:
        label = self.c.label(s.label, s.pos, "goto")
        self.index(s.index)
        if label is not None:
            self.c.syms.resolved[id(s)] = label
        if label is None or not isinstance(s.index, n.IntConst):
            return
        problem = label.landing(s.index.value)
        if problem:
            self.err(s.index.pos, f"'goto {s.label}[{s.index.value}]' lands inside {problem}")

    def visit_CallLabel(self, s: n.CallLabel) -> None:
        label = self.c.label(s.label, s.pos, "call")
        if label is not None:
            self.c.syms.resolved[id(s)] = label

    def visit_ProcCall(self, s: n.ProcCall) -> None:
        check_proc_call(self, s)

    def visit_Simple(self, s: n.Simple) -> None:
        if s.command == "exitproc" and self.c.scope.proc is None:
            self.err(s.pos, "'exitproc' outside a procedure (use 'ret' or 'halt')")

    def visit_Delay(self, s: n.Delay) -> None:
        self.integer_operand(s.amount, f"'{s.command}'")

    def visit_Kill(self, s: n.Kill) -> None:
        self.integer_operand(s.task, "'kill'")
        if isinstance(s.task, n.IntConst) and not 0 <= s.task.value <= 3:
            self.err(s.task.pos, f"task number {s.task.value} is out of range 0..3")

    def integer_operand(self, op: n.Operand, what: str) -> None:
        if isinstance(op, n.Deref):
            self.kind(op)
            self.err(
                op.pos,
                f"{what} cannot take a pointer indirection; copy it first: "
                f"'t=*{op.name}; {what.strip(chr(39))} t;'",
            )
            return
        if not isinstance(op, (n.IntConst, n.VarRef)):
            self.kind(op)
            self.err(op.pos, f"{what} takes an integer constant or a short/long variable")
            return
        k = self.kind(op)
        if k is not None and k != "int":
            self.err(
                op.pos,
                f"{what} takes an integer constant or a short/long variable, not {describe(k)}",
            )

    def visit_SetState(self, s: n.SetState) -> None:
        k = self.kind(s.target, "state")
        sym = self.c.syms.resolved.get(id(s.target))
        if k is not None and k != "state" and isinstance(sym, VarSym):
            self.err(
                s.target.pos,
                f"'{s.command}' needs a state or '<var>'; '{sym.name}' is {sym_kind_text(sym)}",
            )

    def visit_Print(self, s: n.Print) -> None:
        check_print(self, s)

    def visit_Loop(self, s: n.Loop) -> None:
        self.integer_operand(s.count, "'loop'")
        if isinstance(s.count, n.IntConst) and not 0 <= s.count.value <= 65535:
            self.err(
                s.count.pos, f"loop count {s.count.value} is out of range 0..65535 (0 means 65536)"
            )
        self.c.block(s.body)

    def visit_If(self, s: n.If) -> None:
        check_cond(self, s.cond)
        self.c.block(s.then_body)
        if s.else_body is not None:
            self.c.block(s.else_body)

    def visit_While(self, s: n.While) -> None:
        check_cond(self, s.cond)
        self.c.block(s.body)

    def visit_Till(self, s: n.Till) -> None:
        check_cond(self, s.cond)
