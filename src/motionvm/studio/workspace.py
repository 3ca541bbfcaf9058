"""The studio's files: their texts as edited in the page, their diagnostics, saving.

A file's diagnostics are what `motionvm check FILE` reports for its current text, through
the session's `check` (the languages are reached only through `motionvm.lang`). The run
uses the edited texts (`sources`), saved or not.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from motionvm.lang import language_of, suffix_list
from motionvm.session import RunSpec, SessionError, Source, check
from motionvm.source.diagnostics import Diagnostic


class WorkspaceError(ValueError):
    """A file the studio cannot open or save (the message says why)."""


@dataclass
class OpenFile:
    path: str
    """Absolute path."""
    text: str
    saved: str
    """The text on disk (as last read or written)."""

    @property
    def language(self) -> str:
        lang = language_of(self.path)
        return lang.language_id if lang is not None else ""

    @property
    def dirty(self) -> bool:
        return self.text != self.saved


class Workspace:
    """The run's files, in the order given (that order places HMPL tasks)."""

    def __init__(self, paths: list[str]) -> None:
        self.files: dict[str, OpenFile] = {}
        for p in paths:
            self.open(p)

    def open(self, path: str) -> OpenFile:
        full = os.path.abspath(path)
        if full in self.files:
            return self.files[full]
        if language_of(full) is None:
            raise WorkspaceError(f"{path}: not a program file (expected {suffix_list()})")
        try:
            text = Path(full).read_text(encoding="utf-8")
        except OSError as exc:
            raise WorkspaceError(f"{path}: {exc.strerror or exc}") from None
        except UnicodeDecodeError:
            raise WorkspaceError(f"{path}: not UTF-8 text") from None
        self.files[full] = OpenFile(full, text, text)
        return self.files[full]

    def get(self, path: str) -> OpenFile:
        found = self.files.get(os.path.abspath(path))
        if found is None:
            raise WorkspaceError(f"{path}: not a file of this studio")
        return found

    def edit(self, path: str, text: str) -> OpenFile:
        f = self.get(path)
        f.text = text
        return f

    def save(self, path: str) -> OpenFile:
        f = self.get(path)
        try:
            Path(f.path).write_text(f.text, encoding="utf-8")
        except OSError as exc:
            raise WorkspaceError(f"{path}: cannot save: {exc.strerror or exc}") from None
        f.saved = f.text
        return f

    def sources(self) -> list[Source]:
        """The run's sources: an edited file's text, else the file."""
        return [Source(f.path, f.text if f.dirty else None) for f in self.files.values()]

    def describe(self) -> list[dict]:
        return [
            {
                "path": f.path,
                "name": os.path.basename(f.path),
                "language": f.language,
                "dirty": f.dirty,
            }  # fmt: skip
            for f in self.files.values()
        ]


def diagnostics(path: str, text: str) -> list[dict]:
    """The diagnostics of `text` as the file `path`, for the editor (lines and columns
    from 1; another file's, an included header's, are listed with their file)."""
    found: list[Diagnostic] = []
    try:
        check(RunSpec([Source(path, text)]), lambda _line: None, found)
    except SessionError as exc:
        return [{"file": path, "line": 1, "col": 1, "severity": "error", "message": str(exc)}]
    return [
        {
            "file": d.pos.file,
            "line": d.pos.line,
            "col": d.pos.col,
            "severity": d.severity,
            "message": d.message,
        }  # fmt: skip
        for d in found
    ]
