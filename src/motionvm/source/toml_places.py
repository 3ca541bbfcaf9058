"""Places in a TOML file's text: the line and column of a key, a table, a syntax error.

`tomllib` gives values without positions, so the machine-file and scenario readers find
the key they complain about in the text: the first `key =` (bare or quoted) of the table,
which is where a user looks for it. Lines and columns count from 1.
"""

from __future__ import annotations

import re
import tomllib

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


def key_place(lines: list[str], section: str, key: str | None) -> Place:
    """Where `key` is written in `[section]` ("": the top level, before any header); with
    key None, the section's header. (1, 1) when it is not found."""
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
    return 1, 1


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
