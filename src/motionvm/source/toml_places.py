"""Places in a TOML file's text: the line and column of a key, a table, a syntax error.

`tomllib` gives values without positions, so the machine-file and scenario readers find
the key they complain about in the text: the first `key =` (bare or quoted) of the table,
which is where a user looks for it. Lines and columns count from 1. `TomlProblems`
collects a file's problems at their places, so that a reader reports them all at once.
"""

from __future__ import annotations

import re
import tomllib

from motionvm.source.diagnostics import Diagnostic
from motionvm.source.files import SourcePos

Place = tuple[int, int]
"""(line, column), both from 1."""


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _key_pattern(key: str) -> str:
    k = re.escape(key)
    return rf"(?:{k}|\"{k}\"|'{k}')\s*="


def _header(line: str) -> str | None:
    """The table name of a `[name]` or `[[name]]` header line, else None."""
    m = re.match(r"\s*\[\[?\s*([^\]]*?)\s*\]\]?\s*(#.*)?$", line)
    return m.group(1) if m else None


def key_place(lines: list[str], section: str, key: str | None) -> Place | None:
    """Where `key` is written in `[section]` ("": the top level, before any header); with
    key None, the section's header. None when it is not found."""
    in_sec = section == ""
    for i, line in enumerate(lines, 1):
        name = _header(line)
        if name is not None:
            in_sec = name == section
            if key is None and in_sec:
                return i, _indent(line) + 1
            continue
        if in_sec and key is not None and re.match(_key_pattern(key), line.strip()):
            return i, _indent(line) + 1
    return None


def array_table_place(lines: list[str], array: str, index: int, key: str | None) -> Place | None:
    """Where `key` (dotted: its last part, also inside inline tables) is written in the
    `index`-th (from 0) `[[array]]` table; its header when the key is not there or is
    None. None when the file has no such table."""
    last = key.split(".")[-1] if key is not None else None
    header: Place | None = None
    seen = -1
    for i, line in enumerate(lines, 1):
        name = _header(line)
        if name is not None:
            if name == array and line.lstrip().startswith("[["):
                seen += 1
                if seen == index:
                    header = (i, _indent(line) + 1)
                elif seen > index:
                    break
            elif seen == index and not name.startswith(array + "."):
                break  # another table: the `index`-th one ended
            continue
        if seen == index and last is not None:
            m = re.search(rf"(^|[{{,\s]){_key_pattern(last)}", line)
            if m:
                return i, m.start() + len(m.group(1)) + 1
    return header


def undecodable_place(data: bytes, exc: UnicodeDecodeError) -> Place:
    """The place of the first byte of `data` that is not UTF-8 (TOML files are UTF-8)."""
    before = data[: exc.start]
    return before.count(b"\n") + 1, exc.start - (before.rfind(b"\n") + 1) + 1


def syntax_error_place(exc: tomllib.TOMLDecodeError, lines: list[str]) -> tuple[Place, str]:
    """The place and the message (without its own `(at line L, column C)`) of a TOML
    syntax error; an error at the end of the document is after its last character."""
    text = str(exc)
    m = re.search(r"\s*\(at line (\d+), column (\d+)\)$", text)
    if m:
        return (int(m.group(1)), int(m.group(2))), text[: m.start()]
    m = re.search(r"\s*\(at end of document\)$", text)
    if m:
        text = text[: m.start()]
    if lines:
        return (len(lines), len(lines[-1]) + 1), text
    return (1, 1), text


def parse_toml(raw: bytes, problems_of, invalid: str = "not valid TOML"):
    """`(table, problems)` of a TOML file's bytes: `problems_of(text)` makes the file's
    problems (a `TomlProblems`). Bytes that are not UTF-8 or text that is not TOML give
    the table None and one problem at its place, `INVALID: ...` (a reader's wording)."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        problems = problems_of("")
        problems.add(undecodable_place(raw, exc), f"{invalid}: the file is not UTF-8 text")
        return None, problems
    problems = problems_of(text)
    try:
        return tomllib.loads(text), problems
    except tomllib.TOMLDecodeError as exc:
        place, message = syntax_error_place(exc, problems.lines)
        problems.add(place, f"{invalid}: {message}")
        return None, problems


class TomlProblems:
    """The problems of one TOML file, each at a line and column of its text."""

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()
        self.items: list[Diagnostic] = []

    def add(self, place: Place, message: str) -> None:
        self.items.append(Diagnostic(SourcePos(self.path, *place), message))

    def at(self, section: str, key: str | None, message: str) -> None:
        """A problem of `key` in `[section]` ("": the top level; key None: the table).
        Not found as written: the table's header or its key (an inline table), else 1:1."""
        place = key_place(self.lines, section, key)
        if place is None and section:
            place = key_place(self.lines, section, None) or key_place(self.lines, "", section)
        self.add(place or (1, 1), message)

    def in_array(self, array: str, index: int, key: str | None, message: str) -> None:
        """A problem of `key` in the `index`-th `[[array]]` table (None: the table)."""
        self.add(self.array_place(array, index, key), message)

    def array_place(self, array: str, index: int, key: str | None) -> Place:
        """`array_table_place`, else the top-level key `array` (inline tables), else 1:1."""
        return (
            array_table_place(self.lines, array, index, key)
            or key_place(self.lines, "", array)
            or (1, 1)
        )

    def where(self, place: Place) -> str:
        """`FILE:LINE:COL` of a place."""
        return f"{self.path}:{place[0]}:{place[1]}"

    def headlines(self) -> list[str]:
        """`FILE:LINE:COL: error: MESSAGE` of every problem, in file order."""
        items = sorted(self.items, key=lambda d: (d.pos.line, d.pos.col))
        return [d.headline() for d in items]
