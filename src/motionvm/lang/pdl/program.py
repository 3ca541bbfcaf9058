"""PDL from source text to a loadable program in one call: front end, then lowering.

sink = DiagnosticSink()
program = compile_pdl("prog.pdl", sink=sink)      # None if there were errors
drive = Drive(program)                             # drive_rt
drive.run(until=2.0)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.pdl.front import front_end
from motionvm.lang.pdl.lower import PdlProgram, lower_program
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourceFile

if TYPE_CHECKING:
    from motionvm.source.cache import CompileCache


def compile_pdl(
    path: str,
    *,
    sink: DiagnosticSink,
    text: str | None = None,
    cache: CompileCache | None = None,
) -> PdlProgram | None:
    """The compiled program of `path` (or of `text` under that name); None on any error.

    With a `cache` an unchanged program is read from it, and a newly compiled one stored
    in it (`program_cache.py`). Runs with room for deep recursion (long conditions, deep
    nests: `run_deep`)."""
    if cache is None:
        return run_deep(_compile_pdl, path, sink, text, None)
    return run_deep(_compile_cached, path, sink, text, cache)


def _compile_cached(
    path: str, sink: DiagnosticSink, text: str | None, cache: CompileCache
) -> PdlProgram | None:
    from motionvm.lang.pdl import program_cache

    key = program_cache.program_key(path, text)
    if key is None:  # the file cannot be read: the compile reports it
        return run_deep(_compile_pdl, path, sink, text, None)
    prog = program_cache.load(
        cache, key, path, text, sink, lambda: compile_pdl(path, sink=DiagnosticSink(), text=text)
    )
    if prog is None:
        first = len(sink.items)
        included: list[SourceFile] = []
        prog = run_deep(_compile_pdl, path, sink, text, included)
        if prog is not None:
            program_cache.store(cache, key, prog, sink.items[first:], included)
    return prog


def _compile_pdl(
    path: str, sink: DiagnosticSink, text: str | None, included: list[SourceFile] | None
) -> PdlProgram | None:
    with gc_held():
        result = front_end(path, sink=sink, text=text, included=included)
        if result is None:
            return None
        return lower_program(path, result.symbols)
