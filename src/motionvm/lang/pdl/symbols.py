"""What the PDL checker learns about names, and the code-size model the limits use.

`Symbols` is the checker's result: every user variable with its storage, procedures,
labels, `#task` entry points, and for each name-bearing node (keyed by `id(node)`)
the symbol it resolved to. The lowering reads it instead of resolving names again.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.sysvars import SysVar
from motionvm.source.files import SourcePos

MAX_VAR_NAME = 17
"""User-variable name length (manual §1; §2.5.2 says 15)."""

PORTABLE_VAR_NAME = 15
MAX_LABEL_NAME = 24
MAX_PROC_NAME = 24
USER_MEMORY_WORDS = 16_000
"""User-variable memory [32-bit long words] (manual §1)."""

PROGRAM_MEMORY_BYTES = 128 * 1024
BYTES_PER_CODE_UNIT = 4
"""[P] One code unit is one 32-bit word of drive program memory."""

MAX_INIT_VALUES = 7
MAX_PRINT_ARGS = 8


@dataclass(slots=True)
class VarSym:
    """A variable visible to PDL code.

    type: 'long' | 'short' | 'float' | 'state' | 'instate'. `scope`: 'global', 'local',
    'param' or 'system'. `offset` is the first byte in user memory (globals) or the
    slot number in the procedure frame (params and locals). A pointer's `type` is the
    type it points to.
    """

    name: str
    type: str
    size: int
    scope: str
    pos: SourcePos | None = None
    pointer: bool = False
    read_only: bool = False
    offset: int = 0
    system: SysVar | None = None

    @property
    def is_int(self) -> bool:
        return self.type in ("long", "short") and not self.pointer


@dataclass(slots=True)
class ProcSym:
    """A procedure: its parameters, where it was declared and whether it has a body."""

    name: str
    params: tuple[n.Param, ...]
    pos: SourcePos
    defined: bool = False
    called_at: SourcePos | None = None
    locals: dict[str, VarSym] = field(default_factory=dict)
    labels: dict[str, SourcePos] = field(default_factory=dict)


@dataclass(slots=True)
class LabelSym:
    """A label and the statement list it sits in (for indirect-goto offsets)."""

    name: str
    pos: SourcePos
    block: tuple[n.Item, ...]
    index: int

    def landing(self, offset: int) -> str:
        """'' if `label[offset]` starts a statement (or leaves this block), else where it lands."""
        start = 0
        for item in self.block[self.index + 1 :]:
            units = code_units(item)
            if start == offset and units:
                return ""
            if start < offset < start + units:
                return (
                    f"the statement at line {item.pos.line} ({units} code units starting at "
                    f"{self.name}[{start}])"
                )
            start += units
        return ""


@dataclass(slots=True)
class Symbols:
    """The checker's result for one program."""

    program: n.Program
    globals: dict[str, VarSym] = field(default_factory=dict)
    procs: dict[str, ProcSym] = field(default_factory=dict)
    labels: dict[str, LabelSym] = field(default_factory=dict)
    proc_labels: dict[str, dict[str, LabelSym]] = field(default_factory=dict)
    tasks: dict[int, SourcePos] = field(default_factory=dict)
    resolved: dict[int, object] = field(default_factory=dict)
    user_bytes: int = 0
    program_bytes: int = 0

    def symbol_of(self, node: object) -> object:
        """The VarSym, ProcSym, LabelSym or SysVar a node's name resolved to, or None."""
        return self.resolved.get(id(node))


def describe(kind: str | None) -> str:
    """'an integer', 'a float pointer', ... for an operand kind (see check_stmt)."""
    return {
        "int": "an integer",
        "float": "a float",
        "ptr:long": "a long pointer",
        "ptr:float": "a float pointer",
        "state": "a state",
        "addr": "an address constant",
        "string": "a string",
    }.get(kind or "", "a value")


def sym_kind_text(sym: VarSym) -> str:
    """'a long variable', 'a float pointer', 'a state' for messages."""
    if sym.pointer:
        return f"a {sym.type} pointer"
    if sym.type in ("state", "instate"):
        return "a state"
    return f"a {sym.type} variable"


def code_units(item: n.Item) -> int:
    """Size of a statement in drive code units (the manual gives none: ours).

    goto and exitproc are 1 unit, printl/prints/retprintl with k arguments 2 + k, so
    `goto label[i]` can step over tables of them as the manual's examples do.
    """
    if isinstance(item, (n.Label, n.VarDecl, n.TaskDirective, n.ProcProto)):
        return 0
    if isinstance(item, n.Print):
        return 2 + len(item.args)
    if isinstance(item, n.ProcCall):
        return 1 + len(item.args)
    if isinstance(item, n.If):
        units = 1 + sum(code_units(s) for s in item.then_body)
        if item.else_body is not None:
            units += 1 + sum(code_units(s) for s in item.else_body)
        return units
    if isinstance(item, (n.Loop, n.While)):
        return 2 + sum(code_units(s) for s in item.body)
    if isinstance(item, n.ProcDef):
        return 1 + sum(code_units(s) for s in item.body)
    return 1


def data_bytes(item: n.Item) -> int:
    """Bytes of constant data a statement stores besides its code (format strings)."""
    if isinstance(item, n.Print):
        return (len(item.format.value.encode("latin-1", "replace")) + 4) // 4 * 4
    if isinstance(item, n.Assign) and isinstance(item.value, n.StringConst):
        return (len(item.value.value) + 3) // 4 * 4
    return 0
