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


_HEADER = re.compile(r"\s*\[\[?\s*([^\]]*?)\s*\]\]?\s*(#.*)?$")


def _header(line: str) -> str | None:
    """The table name of a `[name]` or `[[name]]` header line, else None."""
    m = _HEADER.match(line)
    return m.group(1) if m else None


class TableIndex:
    """Where each table header of a TOML text is, found in one pass over its lines, so
    that finding the place of a key reads only the lines of its own table: the places of
    all N events of a scenario cost one pass over the file, not N."""

    def __init__(self, lines: list[str]) -> None:
        self.lines = lines
        self.headers: dict[int, str] = {}
        """Line index (from 0) of every header line -> its table name."""
        self.tables: dict[str, list[int]] = {}
        """Table name -> line indexes of its headers, `[name]` and `[[name]]` alike."""
        self.arrays: dict[str, list[int]] = {}
        """Array name -> line index of each `[[name]]` header, in file order."""
        for i, line in enumerate(lines):
            if "[" not in line:
                continue
            name = _header(line)
            if name is None:
                continue
            self.headers[i] = name
            self.tables.setdefault(name, []).append(i)
            if line.lstrip().startswith("[["):
                self.arrays.setdefault(name, []).append(i)

    def _body(self, start: int, inside: str | None = None) -> range:
        """Line indexes from `start` up to the next header (one whose name does not
        begin with `inside.`, when given)."""
        end = start
        while end < len(self.lines):
            name = self.headers.get(end)
            if name is not None and (inside is None or not name.startswith(inside + ".")):
                break
            end += 1
        return range(start, end)

    def key_place(self, section: str, key: str | None) -> Place | None:
        """Where `key` is written in `[section]` ("": the top level, before any header);
        with key None, the section's header. None when it is not found."""
        lines = self.lines
        starts = [-1] if section == "" else self.tables.get(section, [])
        if key is None:
            return (starts[0] + 1, _indent(lines[starts[0]]) + 1) if section and starts else None
        pattern = re.compile(_key_pattern(key))
        for header in starts:
            for i in self._body(header + 1):
                if pattern.match(lines[i].strip()):
                    return i + 1, _indent(lines[i]) + 1
        return None

    def array_table_place(self, array: str, index: int, key: str | None) -> Place | None:
        """Where `key` (dotted: its last part, also inside inline tables) is written in
        the `index`-th (from 0) `[[array]]` table; its header when the key is not there
        or is None. None when the file has no such table."""
        starts = self.arrays.get(array, [])
        if not 0 <= index < len(starts):
            return None
        header = starts[index]
        lines = self.lines
        if key is not None:
            pattern = re.compile(rf"(^|[{{,\s]){_key_pattern(key.split('.')[-1])}")
            for i in self._body(header + 1, inside=array):
                m = pattern.search(lines[i])
                if m:
                    return i + 1, m.start() + len(m.group(1)) + 1
        return header + 1, _indent(lines[header]) + 1


def key_place(lines: list[str], section: str, key: str | None) -> Place | None:
    """`TableIndex.key_place` of a text's lines (one lookup; a reader keeps a TableIndex)."""
    return TableIndex(lines).key_place(section, key)


def array_table_place(lines: list[str], array: str, index: int, key: str | None) -> Place | None:
    """`TableIndex.array_table_place` of a text's lines (one lookup)."""
    return TableIndex(lines).array_table_place(array, index, key)


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
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        place, message = syntax_error_place(exc, problems.lines)
        problems.add(place, f"{invalid}: {message}")
        return None, problems
    except RecursionError:  # tomllib recurses once per level of nesting
        data = None
    if data is None or nesting(data) > MAX_DEPTH:
        problems.add(
            deep_place(text, MAX_DEPTH),
            f"{invalid}: values nested more than {MAX_DEPTH} deep (arrays and tables)",
        )
        return None, problems
    return data, problems


MAX_DEPTH = 32
"""Deepest nesting of arrays and tables a machine file or scenario may have: far beyond
what either needs, and far below what would exhaust Python's recursion."""

_SCAN = re.compile(
    # strings and comments (skipped: their brackets do not count), then brackets;
    # possessive repeats: a long string must not grow the regex engine's state
    r'"""[^"\\]*+(?:(?:\\(?s:.)|"(?!""))[^"\\]*+)*+"""'
    r"|'''(?s:.)*?'''"
    r'|"[^"\\\n]*+(?:\\.[^"\\\n]*+)*+"'
    r"|'[^'\n]*+'"
    r"|#[^\n]*+"
    r"|[\[{\]}]"
)


def nesting(value: object) -> int:
    """How deep arrays and tables nest in `value` (a scalar: 0), without recursion; stops
    counting once past MAX_DEPTH."""
    deepest = 0
    stack = [(value, 1)]
    while stack:
        v, depth = stack.pop()
        if isinstance(v, dict):
            items = v.values()
        elif isinstance(v, list):
            items = v
        else:
            continue
        if depth > deepest:
            deepest = depth
            if deepest > MAX_DEPTH:
                break
        stack.extend((item, depth + 1) for item in items)
    return deepest


def deep_place(text: str, limit: int) -> Place:
    """The place of the first `[` or `{` that opens a level deeper than `limit` (outside
    strings and comments); 1:1 if there is none (deep tables written as dotted keys)."""
    depth = 0
    for m in _SCAN.finditer(text):
        c = m.group()
        if c == "[" or c == "{":
            depth += 1
            if depth > limit:
                start = m.start()
                return text.count("\n", 0, start) + 1, start - text.rfind("\n", 0, start)
        elif c == "]" or c == "}":
            depth = max(0, depth - 1)
    return 1, 1


class TomlProblems:
    """The problems of one TOML file, each at a line and column of its text."""

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()
        self.items: list[Diagnostic] = []
        self._index: TableIndex | None = None

    @property
    def index(self) -> TableIndex:
        """The text's tables, indexed at the first place looked up."""
        if self._index is None:
            self._index = TableIndex(self.lines)
        return self._index

    def add(self, place: Place, message: str) -> None:
        self.items.append(Diagnostic(SourcePos(self.path, *place), message))

    def at(self, section: str, key: str | None, message: str) -> None:
        """A problem of `key` in `[section]` ("": the top level; key None: the table).
        Not found as written: the table's header or its key (an inline table), else 1:1."""
        index = self.index
        place = index.key_place(section, key)
        if place is None and section:
            place = index.key_place(section, None) or index.key_place("", section)
        self.add(place or (1, 1), message)

    def in_array(self, array: str, index: int, key: str | None, message: str) -> None:
        """A problem of `key` in the `index`-th `[[array]]` table (None: the table)."""
        self.add(self.array_place(array, index, key), message)

    def array_place(self, array: str, index: int, key: str | None) -> Place:
        """`array_table_place`, else the top-level key `array` (inline tables), else 1:1."""
        tables = self.index
        return tables.array_table_place(array, index, key) or tables.key_place("", array) or (1, 1)

    def where(self, place: Place) -> str:
        """`FILE:LINE:COL` of a place."""
        return f"{self.path}:{place[0]}:{place[1]}"

    def headlines(self) -> list[str]:
        """`FILE:LINE:COL: error: MESSAGE` of every problem, in file order."""
        items = sorted(self.items, key=lambda d: (d.pos.line, d.pos.col))
        return [d.headline() for d in items]
