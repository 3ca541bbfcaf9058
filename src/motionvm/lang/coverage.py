"""Coverage of machine programs: counters compiled into the generated code of every language.

Tracing each line with `sys.settrace` costs 2.6x to 5.5x the CPU time of a run (every
Python call of the simulator pays for it), so coverage is compiled in instead: while a
`Coverage` collector is active (`collecting`, around a session's compile), each
language compiles its lowered module through `compile_module`, which inserts a probe
`_mv_cov[K] += 1` in front of the first Python statement of each user line in every
statement list, and counts each arm of an `if` statement of the user's
(`LineTable.branches`) with the probe of the arm's first line, or one of its own:

    if v_k == 1:                  ->   if v_k == 1:
        g_total = g_total + 10             _mv_cov[3] += 1      # line 8, and arm 0
                                           g_total = g_total + 10
                                       else:
                                           _mv_cov[4] += 1      # arm 1 (no else in the source)

The `if` line itself needs no probe: its hits are the sum of its arms'. A loop of an
`if` and one statement so costs one increment per iteration.

What counts, in every language alike: a line's hits are the times a statement starting
on it began (a loop's own line once each time the loop starts, its body's lines once
per iteration); a statement the lowering spreads over several Python statements of the
same line counts once, and Python statements that carry the line of the statement they
sit in (a loop's bookkeeping) never count. Only the lines of the language's line table
(the lines a breakpoint can stop at) are probed, and only those that got a probe are
reported: a line the compiler removed is no executable line. Branches are the two arms
of each `if` (BRDA block 0, branch 0: the condition held, branch 1: it did not).

The counters of a run are one list (`Coverage.counts`); `bind` puts it into the
namespace the generated code runs in. `Coverage.data()` gives plain, mergeable data
(`merge`) for the reports (lang/coverage_report.py).
"""

from __future__ import annotations

import ast
import contextlib
import contextvars
import os
import weakref
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

COUNTS_NAME = "_mv_cov"
"""The name of the counter list in the generated code's namespace."""

_ACTIVE: contextvars.ContextVar[Coverage | None] = contextvars.ContextVar(
    "motionvm_coverage", default=None
)
_BOUND: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""Instrumented code object -> the counter list its probes increment."""

_NOT_PROBED = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Global, ast.Nonlocal)


@dataclass
class _FileProbes:
    """The probes of one file: its lines' counters and its `if` arms'."""

    lines: dict[int, list[int]] = field(default_factory=dict)
    branches: dict[int, list[tuple[int, int]]] = field(default_factory=dict)
    """line -> (counter of arm 0, counter of arm 1) of each `if` on it, in order."""


class Coverage:
    """The counters of one run's programs (see the module docstring)."""

    def __init__(self, table_of: Callable[[str], object]) -> None:
        """`table_of(path)`: the `LineTable` of a file (the language interface's)."""
        self.table_of = table_of
        self.counts: list[int] = []
        self.files: dict[str, _FileProbes] = {}

    def _probe(self) -> int:
        self.counts.append(0)
        return len(self.counts) - 1

    def instrument(self, module: ast.Module, path: str) -> ast.Module:
        """Insert the probes of `path`'s lines into `module` (in place; returned)."""
        try:
            table = self.table_of(path)
        except Exception:  # noqa: BLE001 — a file whose lines cannot be listed has no probe
            return module
        probes = self.files.setdefault(_absolute(path), _FileProbes())
        self._statements(module.body, None, table.lines, table.branches, probes)
        return module

    def _statements(self, body: list, parent: int | None, lines, branches, probes) -> None:
        """Probe the statement list `body`, whose enclosing statement is on line `parent`
        (None: a function's or the module's body)."""
        out: list = []
        last = parent
        ifs_seen: set[int] = set()
        for stmt in body:
            line = getattr(stmt, "lineno", None)
            if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef)):
                self._statements(stmt.body, None, lines, branches, probes)
                out.append(stmt)
                last = line
                continue
            branch = (isinstance(stmt, ast.If) and line in branches and line != parent
                      and line not in ifs_seen)  # fmt: skip
            if (line is not None and line != last and line != parent and line in lines
                    and not isinstance(stmt, _NOT_PROBED)):  # fmt: skip
                if branch:  # the line's hits are its arms' (each counts one entry)
                    probes.lines.setdefault(line, [])
                else:
                    k = self._probe()
                    probes.lines.setdefault(line, []).append(k)
                    out.append(_increment(k, stmt))
                branch_counts_line = branch
            else:
                branch_counts_line = False
            if line is not None:
                last = line
            if branch:
                ifs_seen.add(line)
                self._statements(stmt.body, line, lines, branches, probes)
                self._statements(stmt.orelse, line, lines, branches, probes)
                arms = (self._arm(stmt.body, stmt), self._arm(stmt.orelse, stmt))
                probes.branches.setdefault(line, []).append(arms)
                if branch_counts_line:
                    probes.lines[line].extend(arms)
            else:
                for name in ("body", "orelse", "finalbody"):
                    inner = getattr(stmt, name, None)
                    if isinstance(inner, list) and inner and isinstance(inner[0], ast.stmt):
                        self._statements(inner, line, lines, branches, probes)
                for handler in getattr(stmt, "handlers", ()):
                    self._statements(handler.body, line, lines, branches, probes)
                for case in getattr(stmt, "cases", ()):
                    self._statements(case.body, line, lines, branches, probes)
            out.append(stmt)
        body[:] = out

    def _arm(self, body: list, at: ast.stmt) -> int:
        """The counter of entries into the arm `body` of an `if`: the probe of its first
        statement's line when it opens the arm (it counts exactly the entries), else a
        probe of its own put first."""
        if body:
            k = _probe_index(body[0])
            if k is not None:
                return k
        k = self._probe()
        body.insert(0, _increment(k, at))
        return k

    def data(self) -> dict:
        """{file: {"lines": {line: hits}, "branches": {line: [[arm 0, arm 1], ...]}}} of
        the run so far: plain data (`merge`, lang/coverage_report.py)."""
        counts = self.counts
        out = {}
        for path, probes in self.files.items():
            lines = {line: sum(counts[k] for k in ks) for line, ks in probes.lines.items()}
            branches = {
                line: [[counts[a], counts[b]] for a, b in arms]
                for line, arms in probes.branches.items()
            }
            out[path] = {"lines": lines, "branches": branches}
        return out


def _increment(k: int, at: ast.AST) -> ast.stmt:
    """`_mv_cov[k] += 1`, placed at `at`'s line."""
    node = ast.AugAssign(
        ast.Subscript(ast.Name(COUNTS_NAME, ast.Load()), ast.Constant(k), ast.Store()),
        ast.Add(),
        ast.Constant(1),
    )
    line, col = at.lineno, getattr(at, "col_offset", 0) or 0
    for part in ast.walk(node):  # an empty range at the statement's start
        part.lineno, part.col_offset = line, col  # type: ignore[attr-defined]
        part.end_lineno, part.end_col_offset = line, col  # type: ignore[attr-defined]
    return node


def _probe_index(stmt: ast.stmt) -> int | None:
    """K if `stmt` is a probe `_mv_cov[K] += 1`, else None."""
    if isinstance(stmt, ast.AugAssign) and isinstance(stmt.target, ast.Subscript):
        value = stmt.target.value
        if isinstance(value, ast.Name) and value.id == COUNTS_NAME:
            return stmt.target.slice.value  # type: ignore[attr-defined]
    return None


def _absolute(path: str) -> str:
    return os.path.abspath(path) if not path.startswith("<") else path


def merge(into: dict, data: dict) -> dict:
    """Add the coverage `data` (`Coverage.data()`) to `into` (returned): hits and arm
    counts are summed, file by file and line by line."""
    for path, d in data.items():
        mine = into.setdefault(path, {"lines": {}, "branches": {}})
        for line, hits in d["lines"].items():
            line = int(line)
            mine["lines"][line] = mine["lines"].get(line, 0) + hits
        for line, arms in d["branches"].items():
            line = int(line)
            have = mine["branches"].get(line)
            if have is None or len(have) != len(arms):
                mine["branches"][line] = [list(a) for a in arms]
            else:
                for a, b in zip(have, arms):
                    a[0] += b[0]
                    a[1] += b[1]
    return into


@contextlib.contextmanager
def collecting(cov: Coverage | None) -> Iterator[None]:
    """Compile with `cov`'s probes (None: without) inside the block."""
    token = _ACTIVE.set(cov)
    try:
        yield
    finally:
        _ACTIVE.reset(token)


def active() -> bool:
    """Whether a compile now instruments (a language's compile cache then stands aside)."""
    return _ACTIVE.get() is not None


def compile_module(module: ast.Module, filename: str):
    """`compile(module, filename, "exec")`, with the probes of the active collector."""
    cov = _ACTIVE.get()
    if cov is None:
        return compile(module, filename, "exec")
    code = compile(cov.instrument(module, filename), filename, "exec")
    _BOUND[code] = cov.counts
    return code


def bind(namespace: dict, code) -> None:
    """Put the counters `code`'s probes increment into `namespace` (nothing if `code` was
    compiled without probes)."""
    counts = _BOUND.get(code)
    if counts is not None:
        namespace[COUNTS_NAME] = counts
