"""Compiled HMPL programs in the compile cache (`source/cache.py`): key, entry, rebuild.

The key covers every input the compiler reads before the first `#include`: the
compiler's own files and motionvm's version (`package_digest`), and of each task file,
in order, its task id (`_TASKID_`), its path (the code's file name) and its text. An
entry lists the files its `#include`s read with the digest of their text; it is used
only if each still reads the same. It holds what a run needs, as data: the tasks and
their functions' symbols, the system and global variables' symbols, the code objects
(marshalled), the memory the compiler laid out (statics, string literals, initial
images) and the warnings, reported again on every use. The generated Python tree is not
kept: `CompiledProgram.python_source` compiles the files again when asked.
"""

from __future__ import annotations

import dataclasses
import marshal
from collections.abc import Callable, Sequence
from typing import Any

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.program import CompiledProgram, TaskInfo
from motionvm.source.cache import CompileCache, digest, package_digest
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink
from motionvm.source.files import SourceFile

FORMAT = "hmpl-1"
"""The entry's layout; a new layout gets a new name."""
_COMPILER = (("lang/hmpl", "source", "runtime", "data"), ("", "lang"))
"""The package folders whose files make the compiler, and those whose own modules do."""


def _text(f: Any) -> str | None:
    """A task file's text as the compiler sees it (None: unreadable, not cached)."""
    if f.text is not None:
        return f.text.replace("\r\n", "\n").replace("\r", "\n")
    try:
        return SourceFile.read(f.path).text
    except OSError:
        return None


def program_key(files: Sequence[Any]) -> str | None:
    """The cache key of compiling `files` (`TaskFile`s); None if one cannot be read."""
    parts = [FORMAT, package_digest(*_COMPILER)]
    for f in files:
        text = _text(f)
        if text is None:
            return None
        parts += [str(f.task), f.path, text]
    return digest(*parts)


def load(
    cache: CompileCache, key: str, files: Sequence[Any], sink: DiagnosticSink, mem: Memory
) -> CompiledProgram | None:
    """The program stored under `key` with its memory laid out in `mem` (fresh) and its
    warnings added to `sink`; None if there is none or its includes changed."""
    entry = cache.load(key)
    if not isinstance(entry, dict) or entry.get("format") != FORMAT:
        return None
    try:
        for path, text_digest in entry["includes"]:
            try:
                if digest(SourceFile.read(path).text) != text_digest:
                    return None
            except OSError:
                return None
        codes = [(fname, marshal.loads(data)) for fname, data in entry["codes"]]
        mem.restore_static(entry["memory"])
        diagnostics = list(entry["diagnostics"])
        prog = CompiledProgram(entry["tasks"], [], codes, entry["sysvars"], entry["globals"])
    except (KeyError, TypeError, ValueError, EOFError):
        return None
    if not all(isinstance(d, Diagnostic) for d in diagnostics):
        return None
    for f in files:
        if f.text is not None:  # for carets and fault reports, as the parser would
            SourceFile.register(f.path, _text(f) or "")
    sink.items.extend(diagnostics)
    return prog


def store(
    cache: CompileCache,
    key: str,
    prog: CompiledProgram,
    mem: Memory,
    diagnostics: list[Diagnostic],
    included: list[SourceFile],
) -> None:
    """Store a compiled program (and the warnings of its compile) under `key`."""
    entry = {
        "format": FORMAT,
        "includes": [(sf.path, digest(sf.text)) for sf in included],
        "diagnostics": diagnostics,
        "tasks": _without_trees(prog.tasks),
        "sysvars": prog.sysvars,
        "globals": prog.globals_,
        "codes": [(fname, marshal.dumps(code)) for fname, code in prog.codes],
        "memory": mem.static_image(),
    }
    cache.store(key, entry)


def _without_trees(tasks: dict[int, TaskInfo]) -> dict[int, TaskInfo]:
    """The tasks with their functions' symbols copied without the syntax tree (a run
    does not use it); a symbol two tasks share stays one."""
    copies: dict[int, Any] = {}

    def strip(sym: Any) -> Any:
        c = copies.get(id(sym))
        if c is None:
            c = copies[id(sym)] = dataclasses.replace(sym, node=None)
        return c

    return {
        task: dataclasses.replace(
            info, functions={name: strip(sym) for name, sym in info.functions.items()}
        )
        for task, info in tasks.items()
    }


def with_rebuild(
    prog: CompiledProgram, rebuild: Callable[[], CompiledProgram | None]
) -> CompiledProgram:
    """`prog`, whose generated Python tree `rebuild` (a compile without the cache) makes."""

    def modules() -> list:
        again = rebuild()
        return again.modules if again is not None else []

    prog.rebuild = modules
    return prog
