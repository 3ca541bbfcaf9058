"""PDL from source text to a loadable program in one call: front end, then lowering.

sink = DiagnosticSink()
program = compile_pdl("prog.pdl", sink=sink)      # None if there were errors
drive = Drive(program)                             # drive_rt
drive.run(until=2.0)
"""

from __future__ import annotations

from motionvm.lang.pdl.front import front_end
from motionvm.lang.pdl.lower import PdlProgram, lower_program
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink


def compile_pdl(path: str, *, sink: DiagnosticSink, text: str | None = None) -> PdlProgram | None:
    """The compiled program of `path` (or of `text` under that name); None on any error.

    Runs with room for deep recursion (long conditions, deep nests: `run_deep`)."""
    return run_deep(_compile_pdl, path, sink, text)


def _compile_pdl(path: str, sink: DiagnosticSink, text: str | None) -> PdlProgram | None:
    result = front_end(path, sink=sink, text=text)
    if result is None:
        return None
    return lower_program(path, result.symbols)
