"""PDL checker, statements: operand kinds, assignment forms, conditions, calls, printl.

Operand kinds: 'int' (long/short value or integer constant), 'float', 'ptr:long' and
'ptr:float' (pointers and `&var`), 'state' (a state's 0/1), 'addr' (the constant
`<state>` or `<label>`), 'string'; None after an error was reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.check_calls import check_proc_call
from motionvm.lang.pdl.printfmt import FLOAT_CONVERSIONS, INT_CONVERSIONS, Conversion
from motionvm.lang.pdl.printfmt import count_arguments, parse_format
from motionvm.lang.pdl.symbols import MAX_INIT_VALUES, MAX_PRINT_ARGS, VarSym, code_units
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

if TYPE_CHECKING:
    from motionvm.lang.pdl.check import Checker

INT_ONLY_OPS = ("%", "&", "|", "@", "%=", "&=", "|=", "@=")
ONE_ARG_FUNCS = ("abs", "unsign", "sign", "sin", "cos", "sqrt")
INTEGER_LAST_ARG = {"shift": "shift count", "bitset": "bit number", "bitclr": "bit number",
                    "bittog": "bit number", "memcpy": "element count", "memset": "element count",
                    "memmin": "element count", "memmax": "element count",
                    "memsum": "element count"}


def _describe(kind: str | None) -> str:
    return {"int": "an integer", "float": "a float", "ptr:long": "a long pointer",
            "ptr:float": "a float pointer", "state": "a state", "addr": "an address constant",
            "string": "a string"}.get(kind or "", "a value")


class StatementChecker:
    """The statement half of the checker; shares scopes and the sink with `Checker`."""

    def __init__(self, checker: Checker) -> None:
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
                    self.err(node.pos, f"undeclared variable '{name}'"
                             + did_you_mean(name, self.c.scope.visible_names()))
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
            self.err(idx.pos, f"index '{idx.name}' must be a short or long variable, not "
                     f"{_sym_kind_text(sym)}")

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
            return f"ptr:{'float' if sym.type == 'float' else 'long'}" if sym.pointer else (
                "float" if sym.type == "float" else "int")
        if isinstance(op, n.Deref):
            sym = self.var(op, op.name)
            self.index(op.index)
            if sym is None:
                return None
            if not sym.pointer:
                self.err(op.pos, f"'{op.name}' is not a pointer; '*' applies only to variables "
                         "declared with '*'")
                return None
            return "float" if sym.type == "float" else "int"
        if isinstance(op, n.AddressOf):
            sym = self.var(op.target, op.target.name)
            self.index(op.target.index)
            if sym is None:
                return None
            if sym.type in ("state", "instate"):
                self.err(op.pos, f"'&{op.target.name}': a state has no variable address; "
                         f"'<{op.target.name}>' is its state address")
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
            self.err(op.pos, f"'<{op.name}>': '{op.name}' is {_sym_kind_text(sym)}; only a "
                     "short/long variable can hold a state address")
            return None
        label = self.c.scope.labels().get(op.name)
        if label is not None:
            self.c.syms.resolved[id(op)] = label
            if ctx != "value":
                self.err(op.pos, f"'<{op.name}>' is a label address, not a state")
                return None
            return "addr"
        self.err(op.pos, f"'<{op.name}>': '{op.name}' is not a state, label or variable"
                 + did_you_mean(op.name, self.c.scope.visible_names()))
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
                    self.err(t.pos, f"'{t.name}' is a state: change it with seton/setoff/toggle "
                             f"or '{t.name} = condition;'")
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
                self.err(v.pos, f"'{s.op}' needs a number on the right, not {_describe(vk)}")
            elif s.op in INT_ONLY_OPS and "float" in (tk, vk):
                self.err(s.pos, f"'{s.op}' works on integers only; "
                         f"{'the target' if tk == 'float' else 'the right-hand side'} is float")
            elif tk and tk.startswith("ptr:") and s.op not in ("+=", "-="):
                self.err(s.pos, f"'{s.op}' cannot be applied to a pointer")
            return
        if isinstance(v, n.InitList):
            if len(v.values) > MAX_INIT_VALUES:
                self.err(v.pos, f"an initialiser holds at most {MAX_INIT_VALUES} values; this one "
                         f"has {len(v.values)} (split it: 'a[{MAX_INIT_VALUES}] = {{...}};')")
            if tk and tk.startswith("ptr:"):
                self.err(v.pos, "an initialiser cannot be assigned to a pointer")
            return
        if isinstance(v, n.StringConst):
            sym = self.c.syms.resolved.get(id(s.target))
            if tk is not None and (tk != "int" or (isinstance(sym, VarSym) and sym.type != "long")
                                   or isinstance(s.target, n.Deref)):
                self.err(v.pos, "a string can only be assigned to a long variable or array "
                         "(4 characters per element)")
            return
        if isinstance(v, n.SttoVar):
            self.cond(v.cond)
            if tk is not None and tk not in ("int", "float"):
                self.err(s.pos, f"'sttovar' stores 0 or 1 into a long, short or float, not "
                         f"{_describe(tk)}")
            return
        if isinstance(v, n.SizeOf):
            sym = self.c.scope.lookup(v.name)
            if sym is None or sym.type in ("state", "instate"):
                self.err(v.pos, f"'sizeof({v.name})': '{v.name}' is not a variable"
                         + ("" if sym else did_you_mean(v.name, self.c.scope.visible_names())))
            else:
                self.c.syms.resolved[id(v)] = sym
            return
        if isinstance(v, n.FuncCall):
            self.func_call(v, tk, s.target)
            return
        if isinstance(v, n.Neg):
            k = self.kind(v.operand)
            if k is not None and k not in ("int", "float"):
                self.err(v.pos, f"'-' needs a number, not {_describe(k)}")
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
                self.err(s.value.pos, f"'{s.value.name}' is a state, not a value: write "
                         f"'v = sttovar {s.value.name};' to store it as 0 or 1")
            return
        if tk.startswith("ptr:"):
            if vk.startswith("ptr:") and vk != tk:
                self.err(s.value.pos, f"{_describe(tk)} cannot point to "
                         f"{'a float' if vk == 'ptr:float' else 'a long or short'} variable")
            elif not vk.startswith("ptr:"):
                self.err(s.value.pos, f"a pointer is set from '&variable' or another pointer, "
                         f"not {_describe(vk)}")
            return
        if vk.startswith("ptr:") and tk == "float":
            self.err(s.value.pos, "an address cannot be stored in a float")

    def binop(self, b: n.BinOp) -> str | None:
        lk, rk = self.kind(b.left), self.kind(b.right)
        for side, k in ((b.left, lk), (b.right, rk)):
            if isinstance(side, n.AddressOf):
                self.err(side.pos, "'&var' cannot be used in an operation; store it in a "
                         "pointer first")
                return None
            if k in ("string", "addr", "state"):
                self.err(side.pos, f"'{b.op}' needs numbers, not {_describe(k)}")
                return None
        if lk is None or rk is None:
            return None
        if b.op in INT_ONLY_OPS and "float" in (lk, rk):
            self.err(b.pos, f"'{b.op}' works on integers only; an operand is float")
            return None
        if lk.startswith("ptr:"):
            if b.op not in ("+", "-") or rk != "int":
                self.err(b.pos, "pointer arithmetic is 'pointer + integer' or 'pointer - "
                         "integer'")
                return None
            return lk
        if rk.startswith("ptr:"):
            self.err(b.pos, "a pointer can only be the left operand of '+' or '-'")
            return None
        return "float" if "float" in (lk, rk) else "int"

    def func_call(self, f: n.FuncCall, tk: str | None, target: n.VarRef | n.Deref) -> None:
        want = 1 if f.func in ONE_ARG_FUNCS else 2
        kinds = [self.kind(a) for a in f.args]
        if len(f.args) != want:
            self.err(f.pos, f"'{f.func}' takes {want} argument{'s' if want > 1 else ''}, got "
                     f"{len(f.args)}")
            return
        for i, (a, k) in enumerate(zip(f.args, kinds)):
            last = i == len(f.args) - 1
            if isinstance(a, (n.IntConst, n.FloatConst)) and not last:
                self.err(a.pos, f"argument {i + 1} of '{f.func}' must be a variable; only the "
                         "last argument may be a constant")
            elif not isinstance(a, (n.IntConst, n.FloatConst, n.VarRef)):
                self.err(a.pos, f"arguments of '{f.func}' are variables or constants, not "
                         f"{_describe(k) if k else 'this'}")
            elif k is not None and k not in ("int", "float"):
                self.err(a.pos, f"argument {i + 1} of '{f.func}' must be a number, not "
                         f"{_describe(k)}")
        count_name = INTEGER_LAST_ARG.get(f.func)
        if count_name and kinds[1] == "float":
            self.err(f.args[1].pos, f"the {count_name} of '{f.func}' must be an integer")
        if f.func in ("shift", "bitset", "bitclr", "bittog") and kinds[0] == "float":
            self.err(f.args[0].pos, f"'{f.func}' works on integers; the argument is float")
        if f.func in ("memcpy", "memset") and tk is not None and kinds[0] in ("int", "float"):
            tsym = self.c.syms.resolved.get(id(target))
            asym = self.c.syms.resolved.get(id(f.args[0]))
            if isinstance(tsym, VarSym) and isinstance(asym, VarSym) and tsym.type != asym.type:
                self.err(f.pos, f"'{f.func}' does not convert types: the target is {tsym.type} "
                         f"and '{asym.name}' is {asym.type}")

    def visit_StateAssign(self, s: n.StateAssign) -> None:
        self.kind(s.state)
        self.cond(s.cond)

    def visit_IncDec(self, s: n.IncDec) -> None:
        k = self.target(s.target)
        if k == "float":
            self.err(s.pos, f"'{s.op}' works on long or short variables, not float")

    def visit_Goto(self, s: n.Goto) -> None:
        label = self.c.label(s.label, s.pos, "goto")
        self.index(s.index)
        if label is None or not isinstance(s.index, n.IntConst):
            return
        offset, target = 0, s.index.value
        for item in label.block[label.index + 1:]:
            units = code_units(item)
            if offset == target and units:
                return
            if offset < target < offset + units:
                self.err(s.index.pos, f"'goto {s.label}[{target}]' lands inside the statement at "
                         f"line {item.pos.line} ({units} code units starting at "
                         f"{s.label}[{offset}])")
                return
            offset += units

    def visit_CallLabel(self, s: n.CallLabel) -> None:
        self.c.label(s.label, s.pos, "call")

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
            self.err(op.pos, f"{what} cannot take a pointer indirection; copy it first: "
                     f"'t=*{op.name}; {what.strip(chr(39))} t;'")
            return
        if not isinstance(op, (n.IntConst, n.VarRef)):
            self.kind(op)
            self.err(op.pos, f"{what} takes an integer constant or a short/long variable")
            return
        k = self.kind(op)
        if k is not None and k != "int":
            self.err(op.pos, f"{what} takes an integer constant or a short/long variable, not "
                     f"{_describe(k)}")

    def visit_SetState(self, s: n.SetState) -> None:
        k = self.kind(s.target, "state")
        sym = self.c.syms.resolved.get(id(s.target))
        if k is not None and k != "state" and isinstance(sym, VarSym):
            self.err(s.target.pos, f"'{s.command}' needs a state or '<var>'; '{sym.name}' is "
                     f"{_sym_kind_text(sym)}")

    def visit_Print(self, s: n.Print) -> None:
        for a in s.args:
            k = self.kind(a)
            if k == "string":
                self.err(a.pos, "a string cannot be an argument; put the text in the format")
        if len(s.args) > MAX_PRINT_ARGS:
            self.err(s.args[MAX_PRINT_ARGS].pos, f"'{s.command}' takes at most {MAX_PRINT_ARGS} "
                     f"arguments, got {len(s.args)}")
        parts, issues = parse_format(s.format.value)
        fpos = s.format.pos
        for issue in issues:
            self.err(SourcePos(fpos.file, fpos.line, fpos.col + 1 + issue.offset), issue.message)
        if issues:
            return
        count, has_s = count_arguments(parts)
        if (not has_s and count != len(s.args)) or (has_s and len(s.args) < count):
            self.err(fpos, f"the format has {count} conversion{'s' if count != 1 else ''} but "
                     f"{len(s.args)} argument{'s' if len(s.args) != 1 else ''} "
                     f"{'is' if len(s.args) == 1 else 'are'} given")
            return
        if has_s:
            return
        convs = [p for p in parts if isinstance(p, Conversion)]
        for conv, a in zip(convs, s.args):
            k = self.kind_quiet(a)
            if conv.conv in FLOAT_CONVERSIONS and k == "int" and not isinstance(a, n.IntConst):
                self.sink.warning(a.pos, f"'{conv.text}' shows a float but the argument is an "
                                  "integer")
            elif conv.conv in INT_CONVERSIONS and k == "float":
                self.sink.warning(a.pos, f"'{conv.text}' shows an integer but the argument is a "
                                  "float (use %g)")

    def kind_quiet(self, op: n.Operand) -> str | None:
        sym = self.c.syms.resolved.get(id(op))
        if isinstance(op, n.FloatConst):
            return "float"
        if isinstance(op, n.IntConst):
            return "int"
        if isinstance(op, (n.VarRef, n.Deref)) and isinstance(sym, VarSym):
            if sym.pointer and isinstance(op, n.VarRef):
                return "ptr"
            return {"float": "float", "long": "int", "short": "int"}.get(sym.type)
        return None

    def visit_Loop(self, s: n.Loop) -> None:
        self.integer_operand(s.count, "'loop'")
        if isinstance(s.count, n.IntConst) and not 0 <= s.count.value <= 65535:
            self.err(s.count.pos, f"loop count {s.count.value} is out of range 0..65535 "
                     "(0 means 65536)")
        self.c.block(s.body)

    def visit_If(self, s: n.If) -> None:
        self.cond(s.cond)
        self.c.block(s.then_body)
        if s.else_body is not None:
            self.c.block(s.else_body)

    def visit_While(self, s: n.While) -> None:
        self.cond(s.cond)
        self.c.block(s.body)

    def visit_Till(self, s: n.Till) -> None:
        self.cond(s.cond)

    # ------------------------------------------------------------ conditions

    def cond(self, c: n.Cond) -> None:
        if isinstance(c, n.Logic):
            for t in c.terms:
                self.cond(t)
        elif isinstance(c, n.Not):
            self.cond(c.operand)
        elif isinstance(c, n.StateTest):
            self.state_test(c)
        elif isinstance(c, n.BitTest):
            k = self.kind(c.var)
            if k is not None and k != "int":
                self.err(c.var.pos, f"'->' tests a bit of a short/long variable, not "
                         f"{_describe(k)}")
            if not 0 <= c.bit <= 31:
                self.err(c.pos, f"bit {c.bit} is out of range 0..31")
        elif isinstance(c, n.Relation):
            self.relation(c)

    def state_test(self, c: n.StateTest) -> None:
        ref = c.ref
        if isinstance(ref, n.AngleRef):
            self.angle(ref, "state")
            return
        sym = self.var(ref, ref.name)
        if sym is None:
            return
        if sym.type == "instate":
            self.err(ref.pos, f"'{ref.name}' holds a state reference; write '<{ref.name}>'")
        elif sym.type != "state":
            self.err(ref.pos, f"'{ref.name}' is {_sym_kind_text(sym)}, not a state: compare it "
                     f"('{ref.name}<>0') or write '<{ref.name}>' if it holds a state address")

    def relation(self, c: n.Relation) -> None:
        lk, rk = self.kind(c.left, "value"), self.kind(c.right, "value")
        for side, k in ((c.left, lk), (c.right, rk)):
            if k in ("string",) or isinstance(side, n.AddressOf):
                self.err(side.pos, f"'{c.op}' compares numbers, not {_describe(k)}")
                return
        if c.op == "TOUT":
            if not isinstance(c.left, (n.VarRef, n.Deref)) or lk not in ("int", None):
                self.err(c.left.pos, "the left operand of TOUT is a short/long variable "
                         "holding a start time")
            if rk not in ("int", None) or isinstance(c.right, n.AngleRef):
                self.err(c.right.pos, "the right operand of TOUT is an integer variable or "
                         "constant (a duration in fclk ticks)")


def _sym_kind_text(sym: VarSym) -> str:
    if sym.pointer:
        return f"a {sym.type} pointer"
    if sym.type in ("state", "instate"):
        return "a state"
    return f"a {sym.type} variable"
