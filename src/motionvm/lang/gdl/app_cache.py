"""Compiled GDL applications in the compile cache (`source/cache.py`): key, entry, read back.

The key covers every input of the compile: the compiler's own files and motionvm's
version (`package_digest`) and, in link order, each file's path (the code's file name)
and text (GDL has no `#include`: every file of an application is given). An entry
holds the checked `App` as data (objects, procedures with their syntax trees, which
name places in run-time messages and give `--emit-python` its tree), the code object of
each file's procedures (marshalled) and the warnings of the compile, reported again on
every use.
"""

from __future__ import annotations

import dataclasses
import marshal
from collections.abc import Mapping, Sequence
from types import CodeType

from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.lower import load_app_code
from motionvm.source.cache import CompileCache, digest, package_digest
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink
from motionvm.source.files import SourceFile

FORMAT = "gdl-1"
"""The entry's layout; a new layout gets a new name."""
_COMPILER = (("lang/gdl", "source", "runtime", "data"), ("", "lang"))
"""The package folders whose files make the compiler, and those whose own modules do."""


def _normal(text: str) -> str:
    return text.replace("\r\n", "\n").replace("\r", "\n") if "\r" in text else text


def app_key(paths: Sequence[str], texts: Mapping[str, str]) -> str | None:
    """The cache key of compiling `paths` (`texts`: contents given by path); None if a
    file cannot be read."""
    parts = [FORMAT, package_digest(*_COMPILER)]
    for path in paths:
        text = SourceFile.text_of(path, texts.get(path))
        if text is None:
            return None
        parts += [path, _normal(text)]
    return digest(*parts)


def load(
    cache: CompileCache, key: str, texts: Mapping[str, str], sink: DiagnosticSink
) -> App | None:
    """The application stored under `key`, its procedures ready to run and its warnings
    added to `sink`; None if there is none."""
    entry = cache.load(key)
    if not isinstance(entry, dict) or entry.get("format") != FORMAT:
        return None
    try:
        app = entry["app"]
        codes = [(path, marshal.loads(data)) for path, data in entry["codes"]]
        diagnostics = list(entry["diagnostics"])
    except (KeyError, TypeError, ValueError, EOFError):
        return None
    if not isinstance(app, App) or not all(isinstance(d, Diagnostic) for d in diagnostics):
        return None
    if not all(isinstance(c, CodeType) for _path, c in codes):
        return None
    app.functions = load_app_code(app, codes)
    for path, text in texts.items():  # for carets and fault reports, as the parser would
        SourceFile.register(path, _normal(text))
    sink.items.extend(diagnostics)
    return app


def store(
    cache: CompileCache,
    key: str,
    app: App,
    codes: list[tuple[str, CodeType]],
    diagnostics: list[Diagnostic],
) -> None:
    """Store a compiled application (and the warnings of its compile) under `key`."""
    entry = {
        "format": FORMAT,
        "app": dataclasses.replace(app, functions={}),
        "codes": [(path, marshal.dumps(code)) for path, code in codes],
        "diagnostics": diagnostics,
    }
    cache.store(key, entry)
