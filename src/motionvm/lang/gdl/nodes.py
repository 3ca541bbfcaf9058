"""The GDL abstract syntax tree: frozen, slotted dataclasses, a `pos` on every node.

The parser builds these from one file; `check` resolves names against the whole
application and records what it found in side tables; the RTS executes procedure
bodies. Keywords are stored upper case, identifiers as written (GDL names are
case-insensitive, so compare `Name.key`).
"""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.source.files import SourcePos

# ---------------------------------------------------------------- names and files


@dataclass(frozen=True, slots=True)
class Name:
    """An identifier as written; `key` is its case-folded form used for lookups."""

    pos: SourcePos
    text: str

    @property
    def key(self) -> str:
        return self.text.lower()


@dataclass(frozen=True, slots=True)
class GdlFile:
    """One source file: one or more modules."""

    pos: SourcePos
    modules: tuple[Module, ...]


@dataclass(frozen=True, slots=True)
class Module:
    """`MODULE name; declarations procedures END$MODULE;`"""

    pos: SourcePos
    name: Name
    uses: tuple[UseDecl, ...]
    objects: tuple[ObjectDecl, ...]
    procedures: tuple[Procedure, ...]


# ---------------------------------------------------------------- declarations


@dataclass(frozen=True, slots=True)
class UseDecl:
    """`USE TYPE name, name;` makes objects of another module visible here."""

    pos: SourcePos
    type_kw: str
    names: tuple[Name, ...]


@dataclass(frozen=True, slots=True)
class ObjectDecl:
    """`TYPE name [ PARAM = value, ... ];`"""

    pos: SourcePos
    type_kw: str
    name: Name
    params: tuple[ParamAssign, ...]


@dataclass(frozen=True, slots=True)
class ParamAssign:
    """`PARAM$KEYWORD = value` inside a declaration's brackets."""

    pos: SourcePos
    keyword: str
    value: ParamValue


@dataclass(frozen=True, slots=True)
class IntValue:
    """An integer parameter value, sign included."""

    pos: SourcePos
    value: int


@dataclass(frozen=True, slots=True)
class KeywordValue:
    """A keyword parameter value: ON/OFF, a set constant, PRESENT/ABSENT or a type name."""

    pos: SourcePos
    word: str


@dataclass(frozen=True, slots=True)
class NameValue:
    """An object name given as a parameter value (parent or referenced object)."""

    pos: SourcePos
    name: Name


@dataclass(frozen=True, slots=True)
class StringValue:
    """One or two adjacent strings: first and second display language."""

    pos: SourcePos
    first: str
    second: str | None


ParamValue = IntValue | KeywordValue | NameValue | StringValue

# ---------------------------------------------------------------- procedures


@dataclass(frozen=True, slots=True)
class Procedure:
    """`PROCEDURE name; DECLARE { activators }; BEGIN body END$PROCEDURE;`"""

    pos: SourcePos
    name: Name
    activators: tuple[ActivatorEntry, ...]
    body: tuple[Instr, ...]


@dataclass(frozen=True, slots=True)
class ActivatorRef:
    """`KW OF object` or `KW OF object{N}` in an activator list."""

    pos: SourcePos
    keyword: str
    obj: Name
    index: int | None


@dataclass(frozen=True, slots=True)
class GlobalActivator:
    """A global activator such as `ANY$DIAGN$STATUS`."""

    pos: SourcePos
    keyword: str


ActivatorEntry = ActivatorRef | GlobalActivator

# ---------------------------------------------------------------- instructions


@dataclass(frozen=True, slots=True)
class ObjectRef:
    """`name` or `name{expr}`; no index on an array means the whole array."""

    pos: SourcePos
    name: Name
    index: Expr | None


@dataclass(frozen=True, slots=True)
class StateRef:
    """`KW OF object_ref`: a state variable (of one element, or of a whole array)."""

    pos: SourcePos
    keyword: str
    obj: ObjectRef


@dataclass(frozen=True, slots=True)
class Assign:
    """`state_ref = expression;`"""

    pos: SourcePos
    target: StateRef
    value: Expr


@dataclass(frozen=True, slots=True)
class OperatorCall:
    """`OPKW OF object_ref (args);`"""

    pos: SourcePos
    keyword: str
    obj: ObjectRef
    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class If:
    """`IF cond THEN ... [ELSE ...] END$IF;`"""

    pos: SourcePos
    cond: Expr
    then: tuple[Instr, ...]
    orelse: tuple[Instr, ...]


@dataclass(frozen=True, slots=True)
class While:
    """`WHILE cond DO ... END$WHILE;`"""

    pos: SourcePos
    cond: Expr
    body: tuple[Instr, ...]


@dataclass(frozen=True, slots=True)
class Return:
    """`RETURN;` ends the current procedure execution."""

    pos: SourcePos


Instr = Assign | OperatorCall | If | While | Return

# ---------------------------------------------------------------- expressions


@dataclass(frozen=True, slots=True)
class IntLit:
    """An integer constant (unsigned; a minus sign is a Unary node)."""

    pos: SourcePos
    value: int


@dataclass(frozen=True, slots=True)
class DigitalLit:
    """`ON` (True) or `OFF` (False)."""

    pos: SourcePos
    value: bool


@dataclass(frozen=True, slots=True)
class SetLit:
    """A set constant keyword such as `ENABLED`."""

    pos: SourcePos
    word: str


@dataclass(frozen=True, slots=True)
class StrLit:
    """A string constant."""

    pos: SourcePos
    value: str


@dataclass(frozen=True, slots=True)
class NameLit:
    """An object name used as a value of name type."""

    pos: SourcePos
    name: Name


@dataclass(frozen=True, slots=True)
class Unary:
    """`-x`, `+x` or `NOT x`; op is '-', '+' or 'NOT'."""

    pos: SourcePos
    op: str
    operand: Expr


@dataclass(frozen=True, slots=True)
class Binary:
    """Arithmetic, relation or boolean operator; op is the delimiter or AND/OR."""

    pos: SourcePos
    op: str
    left: Expr
    right: Expr


Expr = IntLit | DigitalLit | SetLit | StrLit | NameLit | StateRef | Unary | Binary
