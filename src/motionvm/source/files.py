"""Source files as read from disk and positions (file, line, col) inside them."""

from __future__ import annotations

import errno
import os
import stat
from dataclasses import dataclass
from pathlib import Path

NOT_REGULAR = "not a regular file (a device, pipe or folder)"
"""The reason `SourceFile.read` gives for a path that is not a regular file."""


def why_unreadable(path: str | Path) -> str:
    """Why `path`, which is no regular file, cannot be a source file: `no such file`, or
    NOT_REGULAR when something else (a folder named `x.hmpl`) is there."""
    return NOT_REGULAR if os.path.exists(path) else "no such file"


@dataclass(frozen=True, slots=True)
class SourcePos:
    """A place in a user's source file; `line` and `col` count from 1."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


def text_lines(text: str) -> list[str]:
    """The lines of a source text as the lexers count them: at each "\\n" (a "\\r" before it
    dropped). A form feed, a lone "\\r" or U+2028 stays inside its line (str.splitlines
    would start a new one there, and every line after would be off by one)."""
    lines = text.split("\n")
    if lines[-1] == "":
        lines.pop()  # no line after a final newline
    return [line[:-1] if line.endswith("\r") else line for line in lines]


class SourceFile:
    """The text of one source file, with its lines kept for caret rendering."""

    _cache: dict[str, SourceFile] = {}

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.text = text
        self.lines = text_lines(text)

    @classmethod
    def read(cls, path: str | Path) -> SourceFile:
        """Read a file as UTF-8 (undecodable bytes replaced) and remember it for diagnostics.

        OSError (strerror NOT_REGULAR) for anything but a regular file: a device such as
        /dev/zero would never end, /dev/stdin or a pipe could wait forever."""
        p = str(path)
        if not stat.S_ISREG(os.stat(p).st_mode):
            raise OSError(errno.EINVAL, NOT_REGULAR, p)
        data = Path(p).read_bytes()
        text = data.decode("utf-8", errors="replace").replace("\r\n", "\n").replace("\r", "\n")
        sf = cls(p, text)
        cls._cache[p] = sf
        return sf

    @classmethod
    def register(cls, path: str, text: str) -> SourceFile:
        """Remember an in-memory source (tests, stdin) under a name."""
        sf = cls(path, text)
        cls._cache[path] = sf
        return sf

    @classmethod
    def text_of(cls, path: str, text: str | None = None) -> str | None:
        """`text` if given (an unsaved buffer), else the file's text read now; None when
        the file cannot be read."""
        if text is not None:
            return text
        try:
            return cls.read(path).text
        except OSError:
            return None

    @classmethod
    def lookup(cls, path: str) -> SourceFile | None:
        """The remembered file of that path, reading it from disk if needed."""
        sf = cls._cache.get(path)
        if sf is None:
            try:
                sf = cls.read(path)
            except OSError:
                return None
        return sf

    def line(self, n: int) -> str:
        """Line `n` (1-based) without its newline, or '' beyond the end."""
        if 1 <= n <= len(self.lines):
            return self.lines[n - 1]
        return ""
