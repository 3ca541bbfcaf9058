"""The HMPL abstract syntax tree: slotted dataclasses, a `pos` on every node.

Nodes are never changed once the parser has built them (`dataclasses.replace` makes a
changed copy), but they are not frozen: a frozen dataclass's constructor costs twice as
much, and a compile builds some 20,000 of them. They hash by value, as frozen ones did.

The parser builds these; the checker annotates them in side tables keyed by node
identity; the lowering turns them into Python `ast`. Nothing else lives here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from motionvm.source.files import SourcePos

# ---------------------------------------------------------------- types


@dataclass(slots=True, unsafe_hash=True)
class TypeRef:
    """A written type: base name plus pointer depth.

    `base` is canonical: 'void', 'char', 'int8_t', 'uint8_t', 'int16_t', 'uint16_t',
    'int32_t', 'uint32_t', 'int64_t', 'uint64_t', 'float', 'double', 'Timer', 'Data_t',
    'struct TAG', 'union TAG', or a typedef name. `char` stays 'char' (signed 8-bit).
    `is_const` records a leading or trailing `const` (accepted, enforced on assignment).
    """

    pos: SourcePos
    base: str
    pointers: int = 0
    is_const: bool = False
    struct_def: StructDef | None = None  # set when the type spells out `struct {...}`


@dataclass(slots=True, unsafe_hash=True)
class StructDef:
    """`struct TAG { fields }` or `union TAG { fields }`; tag may be '' (anonymous)."""

    pos: SourcePos
    kind: str  # 'struct' | 'union'
    tag: str
    fields: tuple[VarDecl, ...]


@dataclass(slots=True, unsafe_hash=True)
class Typedef:
    """`typedef TYPE NAME[dims];`"""

    pos: SourcePos
    name: str
    type: TypeRef
    dims: tuple[Expr | None, ...] = ()


# ---------------------------------------------------------------- declarations


@dataclass(slots=True, unsafe_hash=True)
class InitList:
    """A brace initializer `{a, b, {c, d}}`."""

    pos: SourcePos
    items: tuple[Expr | InitList | Designated, ...]


@dataclass(slots=True, unsafe_hash=True)
class Designated:
    """`.field = value` or `[index] = value` inside a brace initializer (C99)."""

    pos: SourcePos
    field: str | None
    index: Expr | None
    value: Expr | InitList


@dataclass(slots=True, unsafe_hash=True)
class VarDecl:
    """One declared variable; `dims` holds one entry per `[...]`, None for `[]`.
    `is_static`: a `static` local (one object for the whole run)."""

    pos: SourcePos
    type: TypeRef
    name: str
    dims: tuple[Expr | None, ...] = ()
    init: Expr | InitList | None = None
    is_static: bool = False


@dataclass(slots=True, unsafe_hash=True)
class Param:
    """A function parameter; `int a[]` arrives with dims=(None,) and decays to a pointer."""

    pos: SourcePos
    type: TypeRef
    name: str
    dims: tuple[Expr | None, ...] = ()


@dataclass(slots=True, unsafe_hash=True)
class FuncDef:
    """A function definition (body) or prototype (body None); `autorun` marks `_AUTORUN_`.
    `block_scope`: a prototype inside a function (its name is visible in its block only;
    the parser puts it both in its DeclStmt and, for the checks against the definition,
    in the file's items)."""

    pos: SourcePos
    ret: TypeRef
    name: str
    params: tuple[Param, ...]
    body: Block | None
    autorun: bool = False
    block_scope: bool = False


@dataclass(slots=True, unsafe_hash=True)
class TranslationUnit:
    """One task's program after preprocessing: declarations and functions in order.
    `function_keys`: when the parser was asked, each function definition's key for kept
    checks (`check_memo.function_keys`, by `id` of the FuncDef)."""

    pos: SourcePos
    items: tuple[VarDecl | FuncDef | StructDef | Typedef | DeclStmt, ...]
    function_keys: dict | None = field(default=None, compare=False, repr=False)


# ---------------------------------------------------------------- statements


@dataclass(slots=True, unsafe_hash=True)
class Block:
    pos: SourcePos
    items: tuple[Stmt, ...]


@dataclass(slots=True, unsafe_hash=True)
class DeclStmt:
    """`int a = 1, b[3];` — one statement declaring several variables (and, inside a
    function, the prototypes of `int f(int);` as block-scope FuncDefs, and typedefs)."""

    pos: SourcePos
    decls: tuple[VarDecl | FuncDef | Typedef, ...]


@dataclass(slots=True, unsafe_hash=True)
class ExprStmt:
    pos: SourcePos
    expr: Expr


@dataclass(slots=True, unsafe_hash=True)
class If:
    pos: SourcePos
    cond: Expr
    then: Stmt
    else_: Stmt | None = None


@dataclass(slots=True, unsafe_hash=True)
class While:
    pos: SourcePos
    cond: Expr
    body: Stmt


@dataclass(slots=True, unsafe_hash=True)
class DoWhile:
    pos: SourcePos
    body: Stmt
    cond: Expr


@dataclass(slots=True, unsafe_hash=True)
class For:
    """`for (init; cond; step) body`; init is a DeclStmt, ExprStmt or None."""

    pos: SourcePos
    init: DeclStmt | ExprStmt | None
    cond: Expr | None
    step: Expr | None
    body: Stmt


@dataclass(slots=True, unsafe_hash=True)
class Switch:
    pos: SourcePos
    expr: Expr
    body: Stmt


@dataclass(slots=True, unsafe_hash=True)
class Case:
    """`case VALUE:` label; the statements after it are siblings in the enclosing block."""

    pos: SourcePos
    value: Expr


@dataclass(slots=True, unsafe_hash=True)
class Default:
    pos: SourcePos


@dataclass(slots=True, unsafe_hash=True)
class Break:
    pos: SourcePos


@dataclass(slots=True, unsafe_hash=True)
class Continue:
    pos: SourcePos


@dataclass(slots=True, unsafe_hash=True)
class Return:
    pos: SourcePos
    value: Expr | None = None


@dataclass(slots=True, unsafe_hash=True)
class Empty:
    pos: SourcePos


@dataclass(slots=True, unsafe_hash=True)
class Goto:
    """`goto LABEL;` to a label of the same function (the manual's homing examples use it)."""

    pos: SourcePos
    label: str


@dataclass(slots=True, unsafe_hash=True)
class Label:
    """`LABEL:`; like Case, the statements after it are siblings in the enclosing block."""

    pos: SourcePos
    name: str


Stmt = (
    Block
    | DeclStmt
    | ExprStmt
    | If
    | While
    | DoWhile
    | For
    | Switch
    | Case
    | Default
    | Break
    | Continue
    | Return
    | Empty
    | Goto
    | Label
)

# ---------------------------------------------------------------- expressions


@dataclass(slots=True, unsafe_hash=True)
class IntLit:
    """Integer constant; `suffix` is the lower-cased C suffix ('', 'u', 'l', 'ul', 'll', 'ull');
    `decimal` is False for a hexadecimal, octal or binary one (C gives those the unsigned
    types too)."""

    pos: SourcePos
    value: int
    suffix: str = ""
    decimal: bool = True


@dataclass(slots=True, unsafe_hash=True)
class FloatLit:
    """Floating constant; `is_float` for an `f` suffix."""

    pos: SourcePos
    value: float
    is_float: bool = False


@dataclass(slots=True, unsafe_hash=True)
class CharLit:
    """Character constant 'a', already converted to its (signed char) int value."""

    pos: SourcePos
    value: int


@dataclass(slots=True, unsafe_hash=True)
class StrLit:
    """String literal; adjacent literals are concatenated; escapes decoded; no trailing NUL."""

    pos: SourcePos
    value: bytes


@dataclass(slots=True, unsafe_hash=True)
class Name:
    pos: SourcePos
    id: str


@dataclass(slots=True, unsafe_hash=True)
class Unary:
    """Prefix operator: '-', '+', '!', '~', '*' (deref), '&' (address), '++', '--'."""

    pos: SourcePos
    op: str
    operand: Expr


@dataclass(slots=True, unsafe_hash=True)
class Postfix:
    """Postfix '++' or '--'."""

    pos: SourcePos
    op: str
    operand: Expr


@dataclass(slots=True, unsafe_hash=True)
class Binary:
    """Binary operator incl. '&&' and '||': + - * / % << >> < > <= >= == != & | ^ && ||."""

    pos: SourcePos
    op: str
    left: Expr
    right: Expr


@dataclass(slots=True, unsafe_hash=True)
class Assign:
    """'=' or a compound '+=', '-=', '*=', '/=', '%=', '<<=', '>>=', '&=', '|=', '^='."""

    pos: SourcePos
    op: str
    target: Expr
    value: Expr
    parenthesized: bool = False  # written inside extra parentheses: `if ((n = f()))`


@dataclass(slots=True, unsafe_hash=True)
class Cond:
    """`cond ? then : else_`."""

    pos: SourcePos
    cond: Expr
    then: Expr
    else_: Expr


@dataclass(slots=True, unsafe_hash=True)
class Comma:
    pos: SourcePos
    items: tuple[Expr, ...]


@dataclass(slots=True, unsafe_hash=True)
class Call:
    """`func(args)`; `func` is a Name for every call HMPL allows."""

    pos: SourcePos
    func: Expr
    args: tuple[Expr, ...]


@dataclass(slots=True, unsafe_hash=True)
class Index:
    pos: SourcePos
    base: Expr
    index: Expr


@dataclass(slots=True, unsafe_hash=True)
class Member:
    """`base.name` or, with arrow, `base->name`."""

    pos: SourcePos
    base: Expr
    name: str
    arrow: bool = False


@dataclass(slots=True, unsafe_hash=True)
class Cast:
    pos: SourcePos
    type: TypeRef
    expr: Expr


@dataclass(slots=True, unsafe_hash=True)
class SizeOf:
    """`sizeof(TYPE)` (target is a TypeRef, dims for `sizeof(int[3])`) or `sizeof expr`."""

    pos: SourcePos
    target: TypeRef | Expr
    dims: tuple[Expr, ...] = ()


@dataclass(slots=True, unsafe_hash=True)
class CompoundLit:
    """`(TYPE){ initializers }` (C99): an unnamed object, an lvalue. `dims` as in VarDecl
    (`(int[]){1, 2}`: the first is None). Inside a function it is automatic (a local of
    the function, initialized each time the expression is evaluated), at file scope
    static."""

    pos: SourcePos
    type: TypeRef
    dims: tuple[Expr | None, ...]
    init: InitList


Expr = (
    IntLit
    | FloatLit
    | CharLit
    | StrLit
    | Name
    | Unary
    | Postfix
    | Binary
    | Assign
    | Cond
    | Comma
    | Call
    | Index
    | Member
    | Cast
    | SizeOf
    | CompoundLit
)
