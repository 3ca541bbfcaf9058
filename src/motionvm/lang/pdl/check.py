"""PDL checker: names, declarations, procedures, labels and the manual's limits.

One pass in source order, as the drive's single-pass compiler: variables and
procedures must be declared before use (prototypes exist for that), labels may be
used before they are defined. Types of operands and statement forms are checked in
`check_stmt.py`; this module owns declarations and the program-wide limits (the
name scope is in `check_base.py`).
"""

from __future__ import annotations

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl import sysvars
from motionvm.lang.pdl.check_base import Scope
from motionvm.lang.pdl.check_stmt import StatementChecker
from motionvm.lang.pdl.symbols import (
    BYTES_PER_CODE_UNIT,
    MAX_LABEL_NAME,
    MAX_PROC_NAME,
    MAX_VAR_NAME,
    PORTABLE_VAR_NAME,
    PROGRAM_MEMORY_BYTES,
    USER_MEMORY_WORDS,
    LabelSym,
    ProcSym,
    Symbols,
    VarSym,
    code_units,
    data_bytes,
)
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean


class Checker:
    """Checks one parsed program; errors go to the sink, the result is `self.syms`."""

    def __init__(self, program: n.Program, sink: DiagnosticSink) -> None:
        self.sink = sink
        self.syms = Symbols(program)
        self.scope = Scope(self.syms)
        self._memory_reported = False
        self._size_reported = False
        self.block_depth = 0
        self.stmts = StatementChecker(self)

    # ------------------------------------------------------------ driver

    def run(self) -> Symbols:
        program = self.syms.program
        self._collect_labels(program.items, self.syms.labels, top=True)
        for item in program.items:
            self.item(item)
        self._check_program_size(program.items)
        for proc in self.syms.procs.values():
            if not proc.defined and proc.called_at is not None:
                self.sink.error(
                    proc.pos,
                    f"procedure '{proc.name}' is declared but never "
                    "defined (a prototype needs a 'proc ... do ... end;' too)",
                )
        return self.syms

    def item(self, item: n.Item) -> None:
        if isinstance(item, n.VarDecl):
            self.var_decl(item)
        elif isinstance(item, n.TaskDirective):
            self.task_directive(item)
        elif isinstance(item, n.ProcProto):
            self.proc_header(item, defining=False)
        elif isinstance(item, n.ProcDef):
            self.proc_def(item)
        elif not isinstance(item, n.Label):
            self.stmts.statement(item)

    def block(self, items: tuple[n.Item, ...]) -> None:
        self.block_depth += 1
        try:
            for item in items:
                self.item(item)
        finally:
            self.block_depth -= 1

    # ------------------------------------------------------------ labels

    def _collect_labels(
        self, items: tuple[n.Item, ...], table: dict[str, LabelSym], top: bool
    ) -> None:
        for i, item in enumerate(items):
            if isinstance(item, n.Label):
                if len(item.name) > MAX_LABEL_NAME:
                    self.sink.error(
                        item.pos,
                        f"label name '{item.name}' has {len(item.name)} "
                        f"characters; at most {MAX_LABEL_NAME}",
                    )
                old = table.get(item.name)
                if old is not None:
                    self.sink.error(
                        item.pos,
                        f"label '{item.name}' is already defined at {old.pos.line}:{old.pos.col}",
                    )
                else:
                    table[item.name] = LabelSym(item.name, item.pos, items, i)
            elif isinstance(item, n.ProcDef) and top:
                self._collect_labels(
                    item.body, self.syms.proc_labels.setdefault(item.name, {}), top=False
                )
            elif isinstance(item, n.If):
                self._collect_labels(item.then_body, table, top)
                if item.else_body is not None:
                    self._collect_labels(item.else_body, table, top)
            elif isinstance(item, (n.Loop, n.While)):
                self._collect_labels(item.body, table, top)

    def label(self, name: str, pos: SourcePos, what: str) -> LabelSym | None:
        """The label a goto/call names, reporting unknown or out-of-procedure labels."""
        table = self.scope.labels()
        found = table.get(name)
        if found is not None:
            return found
        proc = self.scope.proc
        if proc is not None and name in self.syms.labels:
            self.sink.error(
                pos,
                f"label '{name}' is outside procedure '{proc.name}'; a "
                "procedure can only use its own labels",
            )
        elif name in self.syms.procs:
            self.sink.error(pos, f"'{name}' is a procedure, not a label: call it as '{name}(...);'")
        else:
            self.sink.error(
                pos, f"undefined label '{name}' in '{what}'" + did_you_mean(name, table)
            )
        return None

    # ------------------------------------------------------------ declarations

    def var_decl(self, decl: n.VarDecl) -> None:
        proc = self.scope.proc
        if proc is not None and decl.type == "short":
            self.sink.error(decl.pos, "procedures cannot have short local variables (use #long)")
        if decl.limits is not None:
            lo, hi = decl.limits
            if lo.value > hi.value:
                self.sink.error(
                    lo.pos, f"_lp limits are reversed: low {lo.value} is above high {hi.value}"
                )
        start = self.syms.user_bytes
        elem = 2 if decl.type == "short" else 4
        for item in decl.items:
            size = item.size or 1
            if item.pointer and decl.type == "short":
                self.sink.error(
                    item.pos,
                    "there are no short pointers: declare '#long "
                    f"*{item.name}' (a long pointer can point to short variables)",
                )
            if not self.declare_name(item.name, item.pos):
                continue
            width = 4 if item.pointer else elem
            if proc is not None:
                sym = VarSym(
                    item.name,
                    decl.type,
                    size,
                    "local",
                    item.pos,
                    item.pointer,
                    decl.read_only,
                    len(proc.locals),
                )
                proc.locals[item.name] = sym
            else:
                sym = VarSym(
                    item.name,
                    decl.type,
                    size,
                    "global",
                    item.pos,
                    item.pointer,
                    decl.read_only,
                    self.syms.user_bytes,
                )
                self.syms.globals[item.name] = sym
                self.syms.user_bytes += size * width
            self.syms.resolved[id(item)] = sym
        if proc is None:
            self.syms.user_bytes = (self.syms.user_bytes + 3) // 4 * 4
            words = self.syms.user_bytes // 4
            if words > USER_MEMORY_WORDS and not self._memory_reported:
                self._memory_reported = True
                self.sink.error(
                    decl.pos,
                    f"user variables need {words:,} long words; the drive "
                    f"has {USER_MEMORY_WORDS:,} (this declaration starts at word "
                    f"{start // 4:,})",
                )

    def declare_name(self, name: str, pos: SourcePos, kind: str = "variable") -> bool:
        """Check a new variable or parameter name; False if it cannot be declared."""
        if len(name) > MAX_VAR_NAME:
            self.sink.error(
                pos, f"{kind} name '{name}' has {len(name)} characters; at most {MAX_VAR_NAME}"
            )
            return False
        if len(name) > PORTABLE_VAR_NAME:
            self.sink.warning(
                pos,
                f"{kind} name '{name}' has {len(name)} characters; manual "
                f"§2.5.2 allows only {PORTABLE_VAR_NAME} (§1 allows "
                f"{MAX_VAR_NAME})",
            )
        sv = sysvars.lookup(name)
        if sv is not None:
            what = "state" if sv.kind == "state" else "variable"
            self.sink.error(
                pos, f"'{name}' is the name of the system {what} '{sv.name}'; choose another name"
            )
            return False
        proc = self.scope.proc
        table = proc.locals if proc is not None else self.syms.globals
        old = table.get(name)
        if old is not None:
            where = f" at {old.pos.line}:{old.pos.col}" if old.pos else ""
            self.sink.error(pos, f"'{name}' is already declared{where}")
            return False
        if name in self.syms.procs:
            self.sink.error(pos, f"'{name}' is already the name of a procedure")
            return False
        return True

    def task_directive(self, item: n.TaskDirective) -> None:
        if self.scope.proc is not None or self.block_depth:
            self.sink.error(
                item.pos, "'#task' must be at the top level, outside procedures and blocks"
            )
            return
        if not 0 <= item.task <= 3:
            self.sink.error(item.pos, f"task number {item.task} is out of range 0..3")
            return
        old = self.syms.tasks.get(item.task)
        if old is not None:
            self.sink.error(
                item.pos, f"'#task/{item.task}' is already given at {old.line}:{old.col}"
            )
            return
        self.syms.tasks[item.task] = item.pos

    # ------------------------------------------------------------ procedures

    def proc_header(self, item: n.ProcProto | n.ProcDef, defining: bool) -> ProcSym | None:
        name = item.name
        if len(name) > MAX_PROC_NAME:
            self.sink.error(
                item.pos,
                f"procedure name '{name}' has {len(name)} characters; at most {MAX_PROC_NAME}",
            )
        if sysvars.lookup(name) is not None or name in self.syms.globals:
            self.sink.error(item.pos, f"'{name}' is already the name of a variable")
            return None
        seen: set[str] = set()
        for p in item.params:
            if p.name in seen:
                self.sink.error(p.pos, f"parameter '{p.name}' appears twice")
            seen.add(p.name)
        old = self.syms.procs.get(name)
        if old is None:
            sym = ProcSym(name, item.params, item.pos, defined=defining)
            self.syms.procs[name] = sym
            self.syms.resolved[id(item)] = sym
            return sym
        if _signature(old.params) != _signature(item.params):
            self.sink.error(
                item.pos,
                f"'proc {name}({_signature_text(item.params)})' does not "
                f"match its declaration at {old.pos.line}:{old.pos.col}: "
                f"'proc {name}({_signature_text(old.params)})'",
            )
        if defining and old.defined:
            self.sink.error(
                item.pos, f"procedure '{name}' is already defined at {old.pos.line}:{old.pos.col}"
            )
            return None
        if defining:
            old.defined = True
            old.params = item.params
        self.syms.resolved[id(item)] = old
        return old

    def proc_def(self, item: n.ProcDef) -> None:
        sym = self.proc_header(item, defining=True)
        if sym is None:
            sym = ProcSym(item.name, item.params, item.pos, defined=True)
        sym.locals = {}
        outer_depth = self.block_depth
        self.scope.proc = sym
        self.block_depth = 0
        try:
            for i, p in enumerate(item.params):
                if p.name in sym.locals:
                    continue  # reported by proc_header
                if self.declare_name(p.name, p.pos, "parameter"):
                    sym.locals[p.name] = VarSym(
                        p.name, p.type, 1, "param", p.pos, p.pointer, False, i
                    )
            for stmt in item.body:
                self.item(stmt)
        finally:
            self.scope.proc = None
            self.block_depth = outer_depth

    # ------------------------------------------------------------ limits

    def _check_program_size(self, items: tuple[n.Item, ...]) -> None:
        total = 0
        for item in items:
            total += code_units(item) * BYTES_PER_CODE_UNIT + _data_bytes_deep(item)
            if total > PROGRAM_MEMORY_BYTES and not self._size_reported:
                self._size_reported = True
                self.sink.error(
                    item.pos,
                    f"the program needs more than {PROGRAM_MEMORY_BYTES:,} "
                    "bytes (128 KB) of drive program memory from here on",
                )
        self.syms.program_bytes = total


def _data_bytes_deep(item: n.Item) -> int:
    total = data_bytes(item)
    for body in _bodies(item):
        total += sum(_data_bytes_deep(s) for s in body)
    return total


def _bodies(item: n.Item) -> list[tuple[n.Item, ...]]:
    if isinstance(item, n.If):
        return [item.then_body] + ([item.else_body] if item.else_body is not None else [])
    if isinstance(item, (n.Loop, n.While, n.ProcDef)):
        return [item.body]
    return []


def _signature(params: tuple[n.Param, ...]) -> tuple[tuple[str, bool], ...]:
    return tuple((p.type, p.pointer) for p in params)


def _signature_text(params: tuple[n.Param, ...]) -> str:
    return ", ".join(f"{p.type}{' *' if p.pointer else ''}" for p in params)


def check(program: n.Program, sink: DiagnosticSink) -> Symbols:
    """Check a parsed program; returns what was learnt, errors are in `sink`."""
    return Checker(program, sink).run()
