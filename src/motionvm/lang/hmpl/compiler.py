"""The HMPL compiler driver: task files -> preprocessed, parsed, checked, lowered program."""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.hmpl import program_cache
from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib import implemented_builtins
from motionvm.lang.hmpl.parser import parse_file
from motionvm.lang.hmpl.program import CompiledProgram, ProgramCompiler, Unit
from motionvm.runtime.kernel import MAX_TASKS
from motionvm.source.cache import CompileCache
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourceFile, SourcePos

# memory map sizes [bytes]
STATIC_SIZE = 8 * 1024 * 1024
STACK_SIZE = 64 * 1024
N_TASKS = MAX_TASKS  # (the controller's task slots: runtime/kernel.py)


@dataclass(frozen=True, slots=True)
class TaskFile:
    task: int
    path: str
    text: str | None = None  # None: read the file


def new_memory() -> Memory:
    """A program memory: statics (incl. the 4 MB user table) then 64 task stacks."""
    mem = Memory(STATIC_SIZE + N_TASKS * STACK_SIZE)
    mem.reserve_static(STATIC_SIZE)
    return mem


def compile_tasks(
    files: list[TaskFile],
    sink: DiagnosticSink,
    mem: Memory | None = None,
    *,
    bytecode: bool = True,
    cache: CompileCache | None = None,
) -> tuple[CompiledProgram | None, Memory]:
    """Compile every task file into one program; None (and errors in `sink`) on failure.

    `bytecode` false (`motionvm check`) stops after the generated Python tree: every
    diagnostic is found before it, so the program's `codes` stay empty. With a `cache`
    (and bytecode, in a fresh memory) an unchanged program is read from it, and a newly
    compiled one stored in it (`program_cache.py`)."""
    if cache is not None and bytecode and mem is None:
        return _compile_cached(files, sink, cache)
    return run_deep(_compile_tasks, files, sink, mem, bytecode, None)


def _compile_cached(
    files: list[TaskFile], sink: DiagnosticSink, cache: CompileCache
) -> tuple[CompiledProgram | None, Memory]:
    key = program_cache.program_key(files)
    if key is None:  # a file cannot be read: the compile reports it
        return run_deep(_compile_tasks, files, sink, None, True, None)
    mem = new_memory()
    prog = program_cache.load(cache, key, files, sink, mem)
    if prog is None:
        mem.release()
        first = len(sink.items)
        included: list[SourceFile] = []
        prog, mem = run_deep(_compile_tasks, files, sink, None, True, included)
        if prog is None:
            return None, mem
        program_cache.store(cache, key, prog, mem, sink.items[first:], included)
    return program_cache.with_rebuild(prog, lambda: compile_tasks(files, DiagnosticSink())[0]), mem


def _compile_tasks(
    files: list[TaskFile],
    sink: DiagnosticSink,
    mem: Memory | None,
    bytecode: bool,
    included: list[SourceFile] | None,
) -> tuple[CompiledProgram | None, Memory]:
    mem = mem or new_memory()
    try:
        return _compile_units(files, sink, mem, bytecode, included)
    except RecursionError:  # pragma: no cover - the parser's limits keep well below
        if not sink.has_errors:
            sink.error(SourcePos(files[0].path, 1, 1), "program nested too deeply for the compiler")
        return None, mem


def _compile_units(
    files: list[TaskFile],
    sink: DiagnosticSink,
    mem: Memory,
    bytecode: bool,
    included: list[SourceFile] | None,
) -> tuple[CompiledProgram | None, Memory]:
    units: list[Unit] = []
    # (the survivors go to the oldest generation, which is collected rarely: a run
    # does not leave its large memory to the collector, `HmplRuntime.close()` frees it)
    with gc_held():
        for f in files:
            tu = parse_file(
                f.path,
                task_id=f.task,
                sink=sink,
                text=f.text,
                included=included,
                function_keys=not bytecode,  # `check`: kept function checks
            )
            if tu is not None:
                units.append(Unit(f.task, f.path, tu))
        if sink.has_errors:
            return None, mem
        pc = ProgramCompiler(mem, sink, implemented_builtins(), bytecode=bytecode)
        return pc.compile(units), mem
