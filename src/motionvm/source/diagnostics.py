"""Compiler diagnostics: one format for every language, `path:line:col: error: message`."""

from __future__ import annotations

import re
from dataclasses import dataclass

from motionvm.source.files import SourceFile, SourcePos

MAX_ERRORS_PER_FILE = 20
SHOWN_WIDTH = 160
"""Longest source line shown under a message [characters]; a longer one is cut to a
window around the caret, marked with `...`."""
QUOTED_WIDTH = 64
"""Longest name or token a headline quotes whole [characters]; a longer one (a 100,000
character identifier) is shown by its ends and its length. A path (with a `/` or `\\`)
is always quoted whole."""
_LONG_QUOTED = re.compile(rf"'([^'\s/\\]{{{QUOTED_WIDTH + 1},}})'")


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One compile message with the place it points at."""

    pos: SourcePos
    message: str
    severity: str = "error"  # "error" | "warning" | "note"

    def headline(self) -> str:
        """`FILE:LINE:COL: SEVERITY: MESSAGE`, a quoted name or token longer than
        QUOTED_WIDTH shortened to its ends (`'aaaaaaaaaaaa...aaaaaa' (100000 characters)`)."""
        message = _LONG_QUOTED.sub(_shorten, self.message)
        return f"{self.pos.file}:{self.pos.line}:{self.pos.col}: {self.severity}: {message}"


def _shorten(m: re.Match[str]) -> str:
    word = m.group(1)
    return f"'{word[:12]}...{word[-6:]}' ({len(word)} characters)"


def render_diagnostic(d: Diagnostic) -> str:
    """The headline, then the source line and a caret under the column."""
    out = [d.headline()]
    sf = SourceFile.lookup(d.pos.file)
    if sf is not None:
        text = sf.line(d.pos.line)
        if text:
            shown, col = _window(text.replace("\t", " "), max(0, d.pos.col - 1))
            out.append(shown)
            out.append(" " * col + "^")
    return "\n".join(out)


def _window(line: str, col: int) -> tuple[str, int]:
    """`line` cut to about SHOWN_WIDTH characters around column `col` (from 0), and the
    caret's column in what is shown."""
    if len(line) <= SHOWN_WIDTH:
        return line, col
    start = max(0, min(col - SHOWN_WIDTH // 2, len(line) - SHOWN_WIDTH))
    end = start + SHOWN_WIDTH
    head = "..." if start > 0 else ""
    tail = "..." if end < len(line) else ""
    return head + line[start:end] + tail, col - start + len(head)


def in_order(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """`diagnostics` as a reader wants them: each file's messages by position (line,
    column), the files in the order they first appear; a note stays right after the
    message it belongs to (the one before it). Stable: messages at one place keep their
    order."""
    groups: list[list[Diagnostic]] = []
    for d in diagnostics:
        if d.severity == "note" and groups:
            groups[-1].append(d)
        else:
            groups.append([d])
    files: dict[str, int] = {}
    for g in groups:
        files.setdefault(g[0].pos.file, len(files))
    groups.sort(key=lambda g: (files[g[0].pos.file], g[0].pos.line, g[0].pos.col))
    return [d for g in groups for d in g]


class CompileError(Exception):
    """Raised to abandon a compilation; carries every diagnostic collected so far."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        super().__init__(diagnostics[0].headline() if diagnostics else "compile error")
        self.diagnostics = diagnostics


class TooManyErrors(Exception):
    """Raised by a sink once it holds MAX_ERRORS_PER_FILE errors of one file."""


class DiagnosticSink:
    """Collects diagnostics, at most MAX_ERRORS_PER_FILE errors per file."""

    def __init__(self) -> None:
        self.items: list[Diagnostic] = []
        self._per_file: dict[str, int] = {}

    def error(self, pos: SourcePos, message: str) -> None:
        n = self._per_file.get(pos.file, 0)
        if n >= MAX_ERRORS_PER_FILE:
            raise TooManyErrors()
        self._per_file[pos.file] = n + 1
        self.items.append(Diagnostic(pos, message))
        if n + 1 >= MAX_ERRORS_PER_FILE:
            raise TooManyErrors()

    def warning(self, pos: SourcePos, message: str) -> None:
        self.items.append(Diagnostic(pos, message, "warning"))

    def note(self, pos: SourcePos, message: str) -> None:
        self.items.append(Diagnostic(pos, message, "note"))

    @property
    def has_errors(self) -> bool:
        return any(d.severity == "error" for d in self.items)

    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "error"]
