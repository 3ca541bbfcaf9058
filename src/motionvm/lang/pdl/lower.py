"""Lower a checked PDL program to one Python module of generator functions, and compile it.

    _main(T, pc)            the top level; a task is `_main` entered at the segment of
                            its `#task/n` or `_label` (see lower_body's dispatcher)
    _p_NAME(T, b, args...)  one generator per procedure, called with `yield from`;
                            it takes and returns the task's statement budget `b`

Names the generated code uses are those `drive_rt.runtime_namespace` provides: the
memory views `_M _H _F` (bound to locals `M H F`), system variables `_S`/`S`, states
`_ST`/`ST`, and helpers `_rnd _w32 _print _ldl ...`. Module-level names it defines:
`_vM8 = _M[8:end]` views for chunked loops, `_wbl` to write list-backed arrays back
(lower_chunk, lower_cache). The module is compiled with the
user's file name and line numbers, so a fault's traceback points at the PDL line; a
line of an `#include`d file k is encoded as `line + k * LINE_STRIDE` (decoded by
`PdlProgram.where`).

Before / after (top level; `M[1]` is x):

    x = x + 1;          def _main(T, pc):
    halt;                   M = _M; H = _H; F = _F; S = _S; ST = _ST
                            rs = []
                            b = yield 0
                            while True:
                                if pc <= 0:
                                    b -= 2
                                    try:
                                        M[1] = M[1] + 1
                                    except ValueError:
                                        M[1] = _w32(M[1] + 1)
                                    return
                                return
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass, field
from types import CodeType

from motionvm.lang.coverage import compile_module
from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.drive_sysvars import SYS_BASE
from motionvm.lang.pdl.lower_base import (
    assign,
    const,
    nm,
    storage_kind,
    subscript,
)
from motionvm.lang.pdl.lower_body import BodyLowerer
from motionvm.lang.pdl.rt_memory import FLOAT, SHORT, USER_BASE
from motionvm.lang.pdl.rt_print import PrintFormat, compile_format
from motionvm.lang.pdl.symbols import LabelSym, Symbols, VarSym, code_units
from motionvm.lang.placing import finish_locations
from motionvm.source.files import SourcePos

LINE_STRIDE = 100_000
_VIEWS = ("M", "H", "F", "S", "ST", "FS")


@dataclass
class GlobalVar:
    """A user variable as the host sees it (KMI): where it is and what it may hold."""

    name: str
    type: str
    size: int
    index: int
    """Word index (long/float/pointer) or half-word index (short) of element 0."""
    pointer: bool = False
    read_only: bool = False
    limits: tuple[float, float] | None = None


@dataclass
class PdlProgram:
    """A compiled PDL program, ready to be loaded into a drive."""

    path: str
    code: CodeType
    module: ast.Module | None
    """The generated Python tree; None when read from the compile cache (`rebuild`)."""
    entries: dict[str, int]
    """Top-level label -> segment (task entry point)."""
    tasks: dict[int, int]
    """`#task/n` -> segment."""
    label_addresses: dict[str, int]
    formats: list[PrintFormat]
    tables: dict[str, dict[int, int]]
    globals: dict[str, GlobalVar]
    files: list[str]
    kinds: list[tuple[int, int, int]] = field(default_factory=list)
    """(first word, word count, kind) of every global declaration, for the kind map."""
    rebuild: Callable[[], ast.Module | None] | None = field(default=None, repr=False, compare=False)
    """Compiles the program again for its tree (a program read from the compile cache)."""

    def python_source(self) -> str:
        """The generated Python (`motionvm dump --stage py`)."""
        module = self.module if self.module is not None or self.rebuild is None else self.rebuild()
        return "" if module is None else ast.unparse(module) + "\n"

    def where(self, lineno: int) -> tuple[str, int]:
        """(file, line) of a generated line number."""
        k, line = divmod(lineno, LINE_STRIDE)
        return (self.files[k] if k < len(self.files) else self.path), line


class ProgramLowering:
    """Lays out memory, lowers every body and assembles the module."""

    def __init__(
        self, path: str, syms: Symbols, promote: bool = True, chunk: bool | None = None
    ) -> None:
        self.path = path
        self.syms = syms
        self.sys_base = SYS_BASE
        self.files = [path]
        self.formats: list[PrintFormat] = []
        self.tables: dict[str, dict[int, int]] = {}
        self.keep: list[object] = []
        self._addresses = _label_addresses(syms.program.items)
        self.promote = promote
        """Keep global scalars in locals across loops (lower_cache); off for comparison runs."""
        self.chunk = promote if chunk is None else chunk
        """Run innermost loops in budget-sized chunks without provable checks (lower_chunk)."""
        self.views: dict[str, tuple[str, int, int]] = {}
        """Module-level memory views `_vM8 = _M[8:end]` the chunked loops index (lower_chunk)."""
        self.uses_lists = False
        """Some loop keeps an array in a list: `_wbl` writes one back (lower_cache)."""

    # ------------------------------------------------------------ services for the bodies

    def line_of(self, pos: object) -> int:
        assert isinstance(pos, SourcePos)
        if pos.file not in self.files:
            self.files.append(pos.file)
        return pos.line + self.files.index(pos.file) * LINE_STRIDE

    def global_index(self, sym: VarSym) -> int:
        if storage_kind(sym) == SHORT:
            return USER_BASE * 2 + sym.offset // 2
        return USER_BASE + sym.offset // 4

    @staticmethod
    def state_bit(sym: VarSym) -> int:
        assert sym.system is not None
        return sym.system.address

    def label_address(self, label: LabelSym, in_proc: bool) -> int:
        return self._addresses.get(id(label.block[label.index]), 0)

    def add_format(self, s: n.Print) -> int:
        pointers = tuple(self._is_pointer(a) for a in s.args)
        self.formats.append(compile_format(s.format.value, s.mode1, s.mode2, s.command, pointers))
        return len(self.formats) - 1

    def _is_pointer(self, op: n.Operand) -> bool:
        """`&var`, or a pointer variable read as such (not `*p`): a word address."""
        if isinstance(op, n.AddressOf):
            return True
        sym = self.syms.symbol_of(op) if isinstance(op, n.VarRef) else None
        return isinstance(sym, VarSym) and sym.pointer

    def table_name(self, body: BodyLowerer, label: str) -> str:
        name = f"_lt{len(self.tables)}_{label}"
        self.tables[name] = body.tables[label]
        return name

    @staticmethod
    def proc_pyname(name: str) -> str:
        return f"_p_{name}"

    # ------------------------------------------------------------ functions

    def _prologue(self) -> list[ast.stmt]:
        return [assign(nm(v, True), nm("_" + v)) for v in _VIEWS]

    def main(self) -> tuple[ast.FunctionDef, BodyLowerer]:
        body = BodyLowerer(self, None, None)
        items = tuple(
            i for i in self.syms.program.items if not isinstance(i, (n.ProcDef, n.ProcProto))
        )
        body.prepare_landings(self.syms.labels, items)
        body.body(items)
        body.uses_dispatch = True  # tasks enter at any label
        stmts = self._prologue() + [
            assign(nm("rs", True), ast.List([], ast.Load())),
            assign(nm("b", True), ast.Yield(const(0))),
        ]
        stmts += body.dispatcher()
        fn = _function("_main", ["T", "pc"], stmts, self.syms.program.pos.line)
        return fn, body

    def proc(self, d: n.ProcDef) -> ast.FunctionDef:
        sym = self.syms.procs[d.name]
        frame: dict[int, int] = {}
        kinds = bytearray()
        for v in sym.locals.values():
            frame[id(v)] = len(kinds)
            kinds += bytes([storage_kind(v) if v.type != "instate" else 1]) * v.size
        n_params = len(d.params)
        body = BodyLowerer(self, sym, frame)
        body.prepare_landings(self.syms.proc_labels.get(d.name, {}), d.body)
        body.body(d.body)
        stmts = self._prologue() + [
            assign(nm("bp", True), ast.Attribute(nm("T"), "sp", ast.Load())),
            assign(nm("d0", True), ast.Attribute(nm("T"), "depth", ast.Load())),
            ast.Expr(ast.Call(nm("_enter"), [nm("T"), const(bytes(kinds)), const(n_params)], [])),
        ]
        for i, (_p, v) in enumerate(zip(d.params, list(sym.locals.values())[:n_params])):
            view = "F" if storage_kind(v) == FLOAT and v.type != "instate" else "M"
            slot = ast.BinOp(nm("bp"), ast.Add(), const(frame[id(v)])) if frame[id(v)] else nm("bp")
            stmts.append(assign(subscript(view, slot, True), nm(f"a{i}")))
        if body.uses_dispatch:
            stmts.append(assign(nm("pc", True), const(0)))
        stmts.append(assign(nm("rs", True), ast.List([], ast.Load())))
        stmts += body.dispatcher()
        if not _contains_yield(stmts):
            stmts.append(ast.If(const(False), [ast.Expr(ast.Yield(None))], []))
        params = ["T", "b"] + [f"a{i}" for i in range(n_params)]
        return _function(self.proc_pyname(d.name), params, stmts, d.pos.line)

    def lower(self) -> PdlProgram:
        funcs = [self.proc(d) for d in self.syms.program.items if isinstance(d, n.ProcDef)]
        main, body = self.main()
        views = [
            assign(nm("_" + name, True),
                   subscript("_" + view, ast.Slice(const(base), const(end))))
            for name, (view, base, end) in sorted(self.views.items())
        ]  # fmt: skip
        module = finish_locations(ast.Module(views + funcs + [main], []))
        code = compile_module(module, self.path)
        globals_: dict[str, GlobalVar] = {}
        kinds: list[tuple[int, int, int]] = []
        for g in self.syms.globals.values():
            sk = storage_kind(g)
            index = self.global_index(g)
            limits = None
            globals_[g.name] = GlobalVar(
                g.name, g.type, g.size, index, g.pointer, g.read_only, limits
            )
            if sk == SHORT:
                kinds.append((index // 2, (index % 2 + g.size + 1) // 2, SHORT))
            else:
                kinds.append((index, g.size, sk))
        _set_limits(self.syms.program.items, globals_)
        return PdlProgram(
            path=self.path,
            code=code,
            module=module,
            entries=dict(body.label_seg),
            tasks=dict(body.task_seg),
            label_addresses={
                lab.name: self.label_address(lab, False) for lab in self.syms.labels.values()
            },
            formats=self.formats,
            tables=self.tables,
            globals=globals_,
            files=self.files,
            kinds=kinds,
        )


def _function(name: str, params: list[str], body: list[ast.stmt], line: int) -> ast.FunctionDef:
    args = ast.arguments(posonlyargs=[], args=[ast.arg(p) for p in params], kwonlyargs=[],
                         kw_defaults=[], defaults=[])  # fmt: skip
    fn = ast.FunctionDef(name, args, body, [], None)
    fn.lineno = line
    fn.col_offset = 0
    return fn


def _contains_yield(stmts: list[ast.stmt]) -> bool:
    return any(isinstance(x, (ast.Yield, ast.YieldFrom)) for s in stmts for x in ast.walk(s))


def _set_limits(items: tuple[n.Item, ...], globals_: dict[str, GlobalVar]) -> None:
    for item in items:
        if isinstance(item, n.VarDecl) and item.limits is not None:
            lo, hi = (float(c.value) for c in item.limits)
            for d in item.items:
                if d.name in globals_:
                    globals_[d.name].limits = (lo, hi)


def _label_addresses(items: tuple[n.Item, ...]) -> dict[int, int]:
    """Code-unit address of every label (keyed by id of the Label node)."""
    out: dict[int, int] = {}

    def walk(block: tuple[n.Item, ...], start: int) -> int:
        for item in block:
            if isinstance(item, n.Label):
                out[id(item)] = start
            elif isinstance(item, n.If):
                inner = walk(item.then_body, start + 1)
                if item.else_body is not None:
                    walk(item.else_body, inner + 1)
            elif isinstance(item, (n.Loop, n.While, n.ProcDef)):
                walk(item.body, start + 1)
            start += code_units(item)
        return start

    walk(items, 0)
    return out


def lower_program(
    path: str, syms: Symbols, promote: bool = True, chunk: bool | None = None
) -> PdlProgram:
    """Lower and compile a checked program (`promote`: scalars in locals across loops;
    `chunk`: innermost loops in budget-sized chunks, by default as `promote`)."""
    return ProgramLowering(path, syms, promote, chunk).lower()
