"""The open documents: each one's language, its check diagnostics and its index, computed
once per version of its text."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from motionvm.lang import Language, Source, SourceIndex, language_named, language_of
from motionvm.session import RunSpec, SessionError, check
from motionvm.source.diagnostics import Diagnostic


@dataclass
class Document:
    """One version of an open document."""

    uri: str
    path: str
    """Its file's path (diagnostics and the index name it)."""
    language: Language
    text: str
    version: int | None
    _index: SourceIndex | None = field(default=None, repr=False)

    @property
    def lines(self) -> list[str]:
        """Its lines as the languages count them (at each "\\n"): LSP positions are on these."""
        return self.text.split("\n")

    @property
    def index(self) -> SourceIndex:
        """The names of this version, made on first use."""
        if self._index is None:
            self._index = self.language.index(self.path, self.text)
        return self._index

    def diagnostics(self) -> list[Diagnostic]:
        """What `motionvm check FILE` reports for this text: the same diagnostics, in its
        order (an included header's too)."""
        found: list[Diagnostic] = []
        try:
            check(RunSpec([Source(self.path, self.text)]), lambda _line: None, found)
        except SessionError:
            return []  # no file `check` would take (a scheme other than file:)
        return found


def language_for(path: str, language_id: str | None) -> Language | None:
    """The language of a document: by its file's suffix, else by the editor's id."""
    found = language_of(path)
    if found is None and language_id:
        try:
            found = language_named(language_id)
        except KeyError:
            return None
    return found


def same_file(a: str, b: str) -> bool:
    return os.path.normcase(os.path.abspath(a)) == os.path.normcase(os.path.abspath(b))
