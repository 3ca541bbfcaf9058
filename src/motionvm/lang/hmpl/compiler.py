"""The HMPL compiler driver: task files -> preprocessed, parsed, checked, lowered program."""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib import implemented_builtins
from motionvm.lang.hmpl.lexer import gc_paused
from motionvm.lang.hmpl.parser import parse_file
from motionvm.lang.hmpl.program import CompiledProgram, ProgramCompiler, Unit
from motionvm.source.diagnostics import DiagnosticSink

# memory map sizes [bytes]
STATIC_SIZE = 8 * 1024 * 1024
STACK_SIZE = 64 * 1024
N_TASKS = 64


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
    files: list[TaskFile], sink: DiagnosticSink, mem: Memory | None = None
) -> tuple[CompiledProgram | None, Memory]:
    """Compile every task file into one program; None (and errors in `sink`) on failure."""
    mem = mem or new_memory()
    units: list[Unit] = []
    for f in files:
        tu = parse_file(f.path, task_id=f.task, sink=sink, text=f.text)
        if tu is not None:
            units.append(Unit(f.task, f.path, tu))
    if sink.has_errors:
        return None, mem
    pc = ProgramCompiler(mem, sink, implemented_builtins())
    with gc_paused():  # lowering builds many acyclic AST nodes; the collector only slows it
        return pc.compile(units), mem
