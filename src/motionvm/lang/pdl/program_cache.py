"""Compiled PDL programs in the compile cache (`source/cache.py`): key, entry, read back.

The key covers every input the compiler reads before the first `#include`: the
compiler's own files and motionvm's version (`package_digest`), the program's path (the
code's file name) and its text. An entry lists the files its `#include`s read with the
digest of their text; it is used only while each still reads the same. It holds the
`PdlProgram` as data (its code object marshalled, without the generated Python tree:
`python_source` compiles the file again when asked) and the warnings of the compile,
reported again on every use.
"""

from __future__ import annotations

import dataclasses
import marshal
from collections.abc import Callable

from motionvm.lang.pdl.lower import PdlProgram
from motionvm.source.cache import (
    CompileCache,
    digest,
    include_digests,
    includes_unchanged,
    package_digest,
)
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink
from motionvm.source.files import SourceFile

FORMAT = "pdl-1"
"""The entry's layout; a new layout gets a new name."""
_COMPILER = (("lang/pdl", "source", "runtime", "data"), ("", "lang"))
"""The package folders whose files make the compiler, and those whose own modules do."""


def program_key(path: str, text: str | None) -> str | None:
    """The cache key of compiling `path` (or `text` under that name); None if unreadable."""
    source = SourceFile.text_of(path, text)
    if source is None:
        return None
    return digest(FORMAT, package_digest(*_COMPILER), path, source)


def load(
    cache: CompileCache,
    key: str,
    path: str,
    text: str | None,
    sink: DiagnosticSink,
    rebuild: Callable[[], PdlProgram | None],
) -> PdlProgram | None:
    """The program stored under `key` (its warnings added to `sink`); None if there is
    none or an include changed. `rebuild` compiles it again for its Python tree."""
    entry = cache.load(key)
    if not isinstance(entry, dict) or entry.get("format") != FORMAT:
        return None
    try:
        if not includes_unchanged(entry["includes"]):
            return None
        fields = dict(entry["program"])
        code = marshal.loads(entry["code"])
        diagnostics = list(entry["diagnostics"])
        prog = PdlProgram(code=code, module=None, **fields)
    except (KeyError, TypeError, ValueError, EOFError):
        return None
    if not all(isinstance(d, Diagnostic) for d in diagnostics):
        return None

    def module():
        again = rebuild()
        return None if again is None else again.module

    prog.rebuild = module
    if text is not None:  # for carets and fault reports, as the preprocessor would
        SourceFile.register(path, text)
    sink.items.extend(diagnostics)
    return prog


def store(
    cache: CompileCache,
    key: str,
    prog: PdlProgram,
    diagnostics: list[Diagnostic],
    included: list[SourceFile],
) -> None:
    """Store a compiled program (and the warnings of its compile) under `key`."""
    fields = {
        f.name: getattr(prog, f.name)
        for f in dataclasses.fields(prog)
        if f.name not in ("code", "module", "rebuild")
    }
    entry = {
        "format": FORMAT,
        "includes": include_digests(included),
        "diagnostics": diagnostics,
        "program": fields,
        "code": marshal.dumps(prog.code),
    }
    cache.store(key, entry)
