"""The languages, behind one interface (`lang/interface.py`), and their registry.

Each `lang/<name>/` holds a front end (preprocess, lex, parse, check, lower to Python) and
its run side, a client of the controller's cycle; the languages never import each other.
Each exports one `Language` object from its `language.py`. This module is the registry:
the only module directly in `lang/` that imports the language packages. Everything above
`lang/` (session, API, command line, debugger, language server, studio) reaches a language
through `LANGUAGES` and the interface, never by importing a language package.

`LANGUAGES` is in run order: within one cycle HMPL tasks run before PDL drives, which run
before a GDL application; their compile diagnostics are reported in that order too.
"""

from __future__ import annotations

from pathlib import Path

from motionvm.lang.gdl.language import LANGUAGE as _GDL
from motionvm.lang.hmpl.language import LANGUAGE as _HMPL
from motionvm.lang.index import Completion, Occurrence, Signature, SourceIndex
from motionvm.lang.interface import (
    CallError,
    CompileRequest,
    CompileResult,
    DebugThread,
    Language,
    LanguageInputError,
    LanguageOption,
    LineTable,
    NameDoc,
    RunContext,
    RunSide,
    Source,
    Symbol,
)
from motionvm.lang.pdl.language import LANGUAGE as _PDL

LANGUAGES: tuple[Language, ...] = (_HMPL, _PDL, _GDL)
"""Every language, in run order."""

_BY_SUFFIX = {suffix: lang for lang in LANGUAGES for suffix in lang.suffixes}
_BY_NAME = {lang.name: lang for lang in LANGUAGES}
_BY_ID = {lang.language_id: lang for lang in LANGUAGES}


def language_of(path: str | Path) -> Language | None:
    """The language of a file by its suffix (None: not a program file)."""
    return _BY_SUFFIX.get(Path(path).suffix.lower())


def language_named(name: str) -> Language:
    """The language called `name` ("HMPL") or with editor id `name` ("hmpl"); KeyError."""
    found = _BY_NAME.get(name) or _BY_ID.get(name)
    if found is None:
        raise KeyError(name)
    return found


def suffixes() -> tuple[str, ...]:
    """Every program file suffix (".hmpl", ".pdl", ".gdl")."""
    return tuple(_BY_SUFFIX)


def suffix_list() -> str:
    """ ".hmpl, .pdl or .gdl", for messages."""
    all_ = suffixes()
    return ", ".join(all_[:-1]) + " or " + all_[-1]


__all__ = [
    "LANGUAGES",
    "CallError",
    "CompileRequest",
    "CompileResult",
    "Completion",
    "DebugThread",
    "Language",
    "LanguageInputError",
    "LanguageOption",
    "LineTable",
    "NameDoc",
    "Occurrence",
    "RunContext",
    "RunSide",
    "Signature",
    "Source",
    "SourceIndex",
    "Symbol",
    "language_named",
    "language_of",
    "suffix_list",
    "suffixes",
]
