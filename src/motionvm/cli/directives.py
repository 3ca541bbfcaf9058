"""The directives of `motionvm test` cases: `expect: ...` and its kin, read from comments.

Each language says how a one-line comment that holds a directive opens and closes
(`Language.directive_comment`): `("//", "")` runs to the end of the line and holds one directive,
`("|", "|")` may hold several on one line. The kinds are listed in cli/cases.py.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from motionvm.lang import language_of

_KINDS = (
    r"expect regex|expect runtime error|expect|error|warning|diagnostics|check|args"
    r"|restart|pending|task\s+(?P<task>\d+)"
)
_LOOKS_LIKE = r"expect|(?:error|warning|diagnostics|check|args|restart|pending|task\s+\d+)\s*:"
"""What a comment opening with a directive's word looks like: `// expected: x` is a
misspelt directive, not prose."""


class CaseError(Exception):
    """A case that cannot run as written: a malformed directive, a missing task file."""


@dataclass(frozen=True)
class Directive:
    """One directive of a case: `kind: text` in a comment of `file` at `line`."""

    kind: str
    text: str
    file: str
    line: int
    task: str | None = None
    """The N of `task N:`."""

    @property
    def where(self) -> str:
        return f"{self.file}:{self.line}"


CommentForm = tuple[str, str]
"""How a one-line comment opens and closes ('' closes at the end of the line)."""


def comment_form(path: Path) -> CommentForm:
    """The directive comment form of the language of `path`."""
    lang = language_of(path)
    if lang is None:
        raise CaseError(f"{path.name}: not a program of any language")
    return lang.directive_comment


@cache
def _patterns(form: CommentForm) -> tuple[re.Pattern[str], re.Pattern[str]]:
    opening, closing = (re.escape(s) for s in form)
    if closing:
        directive = rf"{opening}\s*(?P<kind>{_KINDS}):(?: (?P<text>.*?))?\s*{closing}"
    else:
        directive = rf"{opening}\s*(?P<kind>{_KINDS}):(?: (?P<text>.*)|$)"
    return re.compile(directive), re.compile(rf"{opening}\s*(?:{_LOOKS_LIKE})")


def directives(text: str, file: str, form: CommentForm) -> list[Directive]:
    """Every directive in the comments of `text` (the contents of `file`), in order.

    Raises CaseError for a comment that opens like a directive but does not parse."""
    pattern, looks_like = _patterns(form)
    to_end = not form[1]
    out = []
    for lineno, line in enumerate(text.splitlines(), 1):
        found = list(pattern.finditer(line))
        if to_end:
            found = found[:1]  # the comment runs to the end of the line
        starts = {m.start() for m in found}
        for m in looks_like.finditer(line):
            if m.start() not in starts and not any(f.start() < m.start() < f.end() for f in found):
                raise CaseError(f"{file}:{lineno}: malformed directive: {line.strip()!r}")
        for m in found:
            kind = " ".join(m.group("kind").split())
            out.append(Directive(kind, m.group("text") or "", file, lineno, m.group("task")))
    return out
