"""The PDL abstract syntax tree: frozen, slotted dataclasses, a `pos` on every node.

The parser builds these; the checker records what names mean in `symbols.Symbols`.
"""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.source.files import SourcePos


@dataclass(frozen=True, slots=True)
class IntConst:
    """An integer constant, already reduced to its signed 32-bit value."""

    pos: SourcePos
    value: int


@dataclass(frozen=True, slots=True)
class FloatConst:
    pos: SourcePos
    value: float


@dataclass(frozen=True, slots=True)
class StringConst:
    """A string literal; in an assignment it packs 4 characters per long."""

    pos: SourcePos
    value: str


@dataclass(frozen=True, slots=True)
class VarRef:
    """`name`, `name[index]` or `name[index+]` (auto-increment after the transfer).

    `index` is an IntConst or a VarRef without index (a short/long variable).
    """

    pos: SourcePos
    name: str
    index: IntConst | VarRef | None = None
    auto_inc: bool = False


@dataclass(frozen=True, slots=True)
class Deref:
    """`*ptr` or `*ptr[index]` (indirection first, then indexing)."""

    pos: SourcePos
    name: str
    index: IntConst | VarRef | None = None


@dataclass(frozen=True, slots=True)
class AddressOf:
    """`&var` or `&var[index]`."""

    pos: SourcePos
    target: VarRef


@dataclass(frozen=True, slots=True)
class AngleRef:
    """`<name>`: a state or label address, or the state whose address a variable holds."""

    pos: SourcePos
    name: str


@dataclass(frozen=True, slots=True)
class Neg:
    """`-var` (assignment form 4)."""

    pos: SourcePos
    operand: VarRef | Deref


@dataclass(frozen=True, slots=True)
class BinOp:
    """`left op right`, exactly one operator (form 6); op in + - * / % & | @."""

    pos: SourcePos
    op: str
    left: Operand
    right: Operand


@dataclass(frozen=True, slots=True)
class FuncCall:
    """A built-in function (form 7): max, min, abs, ..., memsum."""

    pos: SourcePos
    func: str
    args: tuple[Operand, ...]


@dataclass(frozen=True, slots=True)
class InitList:
    """`{c0, c1, ...}`: constants written to consecutive elements (form 2)."""

    pos: SourcePos
    values: tuple[IntConst | FloatConst, ...]


@dataclass(frozen=True, slots=True)
class SttoVar:
    """`sttovar condition`: 1 if the condition holds, else 0."""

    pos: SourcePos
    cond: Cond


@dataclass(frozen=True, slots=True)
class SizeOf:
    """`sizeof(name)`: the declared element count (not bytes)."""

    pos: SourcePos
    name: str


# ---------------------------------------------------------------- conditions


@dataclass(frozen=True, slots=True)
class StateTest:
    """A state used as a condition: `name` (a state) or `<name>` (state held by a variable)."""

    pos: SourcePos
    ref: VarRef | AngleRef


@dataclass(frozen=True, slots=True)
class BitTest:
    """`var->bit` (an extension): bit `bit` of an integer variable as a condition."""

    pos: SourcePos
    var: VarRef
    bit: int


@dataclass(frozen=True, slots=True)
class Relation:
    """`left op right`; op in = <> < > <= >= TOUT."""

    pos: SourcePos
    op: str
    left: Operand
    right: Operand


@dataclass(frozen=True, slots=True)
class Not:
    pos: SourcePos
    operand: Cond


@dataclass(frozen=True, slots=True)
class Logic:
    """`t0 op0 t1 op1 t2 ...`: `&` and `|` evaluated left to right, equal precedence."""

    pos: SourcePos
    terms: tuple[Cond, ...]
    ops: tuple[str, ...]


# ---------------------------------------------------------------- declarations


@dataclass(frozen=True, slots=True)
class DeclItem:
    """One declared name: `[*]name[[size]]`; size None means a scalar (1 element)."""

    pos: SourcePos
    name: str
    size: int | None = None
    pointer: bool = False


@dataclass(frozen=True, slots=True)
class VarDecl:
    """`#long|#short|#float [_ro] [_lp(lo,hi)] item, ...;` — one statement, consecutive storage."""

    pos: SourcePos
    type: str  # 'long' | 'short' | 'float'
    items: tuple[DeclItem, ...]
    read_only: bool = False
    limits: tuple[IntConst | FloatConst, IntConst | FloatConst] | None = None


@dataclass(frozen=True, slots=True)
class Param:
    """A procedure parameter: `long x`, `float *p`, `instate s`."""

    pos: SourcePos
    type: str  # 'long' | 'float' | 'instate'
    name: str
    pointer: bool = False


@dataclass(frozen=True, slots=True)
class ProcProto:
    """`proc name(params);`"""

    pos: SourcePos
    name: str
    params: tuple[Param, ...]


@dataclass(frozen=True, slots=True)
class ProcDef:
    """`proc name(params) do body end;`"""

    pos: SourcePos
    name: str
    params: tuple[Param, ...]
    body: tuple[Stmt, ...]


@dataclass(frozen=True, slots=True)
class TaskDirective:
    """`#task/n;`: task n starts here at drive reset."""

    pos: SourcePos
    task: int


@dataclass(frozen=True, slots=True)
class Label:
    pos: SourcePos
    name: str


# ---------------------------------------------------------------- statements


@dataclass(frozen=True, slots=True)
class Assign:
    """`target op value;` with op '=' or a compound operator ('+=', ..., '@=')."""

    pos: SourcePos
    target: VarRef | Deref
    op: str
    value: Value


@dataclass(frozen=True, slots=True)
class StateAssign:
    """`state = condition;` (form 8)."""

    pos: SourcePos
    state: VarRef
    cond: Cond


@dataclass(frozen=True, slots=True)
class IncDec:
    """`target++;` or `target--;`"""

    pos: SourcePos
    target: VarRef | Deref
    op: str


@dataclass(frozen=True, slots=True)
class Goto:
    """`goto label;` or `goto label[index];` (index counts code units)."""

    pos: SourcePos
    label: str
    index: IntConst | VarRef | None = None


@dataclass(frozen=True, slots=True)
class CallLabel:
    """`call label;`"""

    pos: SourcePos
    label: str


@dataclass(frozen=True, slots=True)
class ProcCall:
    """`name(args);`"""

    pos: SourcePos
    name: str
    args: tuple[Operand, ...]


@dataclass(frozen=True, slots=True)
class Simple:
    """An operand-less command: halt, ret, exitproc, lock, unlock."""

    pos: SourcePos
    command: str


@dataclass(frozen=True, slots=True)
class Delay:
    """`wait n;` (50 µs units) or `sleep n;` (1 ms units)."""

    pos: SourcePos
    command: str  # 'wait' | 'sleep'
    amount: IntConst | VarRef


@dataclass(frozen=True, slots=True)
class Kill:
    """`kill n;`"""

    pos: SourcePos
    task: IntConst | VarRef


@dataclass(frozen=True, slots=True)
class SetState:
    """`seton|setoff|toggle state;` or with `<var>`."""

    pos: SourcePos
    command: str
    target: VarRef | AngleRef


@dataclass(frozen=True, slots=True)
class Print:
    """`printl|prints|retprintl [/mode1 [/mode2]] ("format", args...);`"""

    pos: SourcePos
    command: str
    mode1: int
    mode2: int
    format: StringConst
    args: tuple[Operand, ...]


@dataclass(frozen=True, slots=True)
class Loop:
    """`loop(n) do body end;` — n = 0 means 65536."""

    pos: SourcePos
    count: IntConst | VarRef
    body: tuple[Stmt, ...]


@dataclass(frozen=True, slots=True)
class If:
    """`if (c) cmd;` (single, else_body None) or `if (c) do ... [else do ...] end;`."""

    pos: SourcePos
    cond: Cond
    then_body: tuple[Stmt, ...]
    else_body: tuple[Stmt, ...] | None = None
    single: bool = False


@dataclass(frozen=True, slots=True)
class While:
    pos: SourcePos
    cond: Cond
    body: tuple[Stmt, ...]


@dataclass(frozen=True, slots=True)
class Till:
    pos: SourcePos
    cond: Cond


@dataclass(frozen=True, slots=True)
class Program:
    """A whole program after preprocessing: top-level items in source order."""

    pos: SourcePos
    items: tuple[Item, ...]


Operand = IntConst | FloatConst | VarRef | Deref | AddressOf | AngleRef | StringConst
Value = Operand | Neg | BinOp | FuncCall | InitList | SttoVar | SizeOf
Cond = StateTest | BitTest | Relation | Not | Logic
Command = Simple | Delay | Kill | SetState | Print | Goto | CallLabel | ProcCall
Stmt = Label | VarDecl | Assign | StateAssign | IncDec | Command | Loop | If | While | Till
Item = Stmt | TaskDirective | ProcProto | ProcDef
