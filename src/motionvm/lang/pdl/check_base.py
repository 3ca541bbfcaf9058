"""What the PDL checker's parts see of each other: the name scope, and the two small
interfaces the statement checker and the call/condition/printl checkers are handed.

`Checker` (check.py) owns declarations and scopes and drives the pass; it hands itself
to `StatementChecker` (check_stmt.py) as a `Declarations`; the statement checker hands
itself to `check_calls.py`, `check_cond.py` and `check_print.py` as an `Operands`. Both
interfaces live here, below all of them, so that no checker module imports another that
imports it back.
"""

from __future__ import annotations

from typing import Protocol

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl import sysvars
from motionvm.lang.pdl.symbols import LabelSym, ProcSym, Symbols, VarSym
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos


class Scope:
    """Name lookup: procedure locals, then globals, then the drive's system names."""

    def __init__(self, syms: Symbols) -> None:
        self.syms = syms
        self.proc: ProcSym | None = None
        self._system: dict[str, VarSym] = {}

    def lookup(self, name: str) -> VarSym | None:
        if self.proc is not None and name in self.proc.locals:
            return self.proc.locals[name]
        if name in self.syms.globals:
            return self.syms.globals[name]
        sv = sysvars.lookup(name)
        if sv is None:
            return None
        sym = self._system.get(sv.name)
        if sym is None:
            sym = VarSym(
                sv.name, sv.kind, sv.size, "system", None, False, sv.read_only, sv.address, sv
            )
            self._system[sv.name] = sym
        return sym

    def visible_names(self) -> list[str]:
        names = list(self.syms.globals) + sysvars.names()
        if self.proc is not None:
            names += list(self.proc.locals)
        return names

    def labels(self) -> dict[str, LabelSym]:
        if self.proc is not None:
            return self.syms.proc_labels.setdefault(self.proc.name, {})
        return self.syms.labels


class Declarations(Protocol):
    """What the statement checker uses of the checker (`check.Checker`)."""

    sink: DiagnosticSink
    syms: Symbols
    scope: Scope

    def label(self, name: str, pos: SourcePos, what: str) -> LabelSym | None:
        """The label a goto/call names, reporting an unknown one."""

    def block(self, items: tuple[n.Item, ...]) -> None:
        """Check the items of a nested block."""


class Operands(Protocol):
    """What the call, condition and printl checkers use of the statement checker
    (`check_stmt.StatementChecker`)."""

    c: Declarations
    sink: DiagnosticSink

    def err(self, pos: SourcePos, msg: str) -> None:
        """Report an error at `pos`."""

    def var(self, node, name: str) -> VarSym | None:
        """The variable `name` names at `node`, reporting one that does not resolve."""

    def kind(self, op, ctx: str = "value") -> str | None:
        """The kind of an operand (check_stmt.py), reporting names that do not resolve."""

    def angle(self, op: n.AngleRef, ctx: str) -> str | None:
        """`<name>`: 'addr' for a state or label in a value context, else 'state'."""
