"""The PDL front end in one call: preprocess, parse, check; diagnostics to a sink.

sink = DiagnosticSink()
program = compile_front("prog.pdl", sink=sink)
if program is None:
    print("\\n".join(render_diagnostic(d) for d in sink.items))
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from motionvm.lang.pdl import nodes
from motionvm.lang.pdl.check import check
from motionvm.lang.pdl.parser import parse
from motionvm.lang.pdl.preprocess import preprocess
from motionvm.lang.pdl.symbols import Symbols
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos

RECURSION_LIMIT = 20_000
"""Enough Python frames for 200 nested blocks and 200 nested parentheses."""


@dataclass(frozen=True, slots=True)
class FrontResult:
    """A checked program and what the checker learnt about its names."""

    program: nodes.Program
    symbols: Symbols


@contextmanager
def _deep_recursion() -> Iterator[None]:
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, RECURSION_LIMIT))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)


def front_end(
    path: str,
    *,
    sink: DiagnosticSink,
    text: str | None = None,
    included: list[SourceFile] | None = None,
) -> FrontResult | None:
    """Preprocess, parse and check `path` (or `text` under that name); None on any error.
    `included` receives every file an `#include` read."""
    try:
        with _deep_recursion():
            try:
                toks = preprocess(path, sink, text, included)
            except OSError as e:
                sink.error(SourcePos(path, 1, 1), f"cannot read '{path}': {e.strerror or e}")
                return None
            pp_errors = len(sink.errors())
            program, lost = parse(toks, sink)
            # Check after repaired parse errors too (more messages per run), but not after
            # skipped input or preprocessing errors: missing declarations would cascade.
            if lost or pp_errors:
                return None
            symbols = check(program, sink)
    except TooManyErrors:
        return None
    if sink.has_errors:
        return None
    return FrontResult(program, symbols)


def compile_front(
    path: str, *, sink: DiagnosticSink, text: str | None = None
) -> nodes.Program | None:
    """The checked AST of a PDL file, or None with the errors in `sink`."""
    result = front_end(path, sink=sink, text=text)
    return result.program if result is not None else None
