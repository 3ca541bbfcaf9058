"""Source files as read from disk and positions (file, line, col) inside them."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, slots=True)
class SourcePos:
    """A place in a user's source file; `line` and `col` count from 1."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


class SourceFile:
    """The text of one source file, with its lines kept for caret rendering."""

    _cache: dict[str, SourceFile] = {}

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.text = text
        self.lines = text.splitlines()

    @classmethod
    def read(cls, path: str | Path) -> SourceFile:
        """Read a file as UTF-8 (undecodable bytes replaced) and remember it for diagnostics."""
        p = str(path)
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
