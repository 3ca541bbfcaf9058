"""printl format strings: split into text and conversions, and the checks the manual asks.

Conversions follow C printf (manual §2.4.2): `%g` for floats, `%d %ld %u %x` for
integers (32-bit values), `%s` for strings packed 4 characters per long, `%%`.
Two conversions written back to back (`%d%d`) are rejected: the manual says they
must be separated by a space or the output is wrong.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_SPEC = re.compile(
    r"%(?P<flags>[-+ #0]*)(?P<width>\d*)(?:\.(?P<prec>\d+))?(?P<len>l|h)?"
    r"(?P<conv>[a-zA-Z%]?)"
)

CONVERSIONS = frozenset("dixXugGfeEsc")
INT_CONVERSIONS = frozenset("dixXuc")
FLOAT_CONVERSIONS = frozenset("gGfeE")


@dataclass(frozen=True, slots=True)
class Conversion:
    """One `%...` conversion; `offset` is its index in the format string."""

    text: str
    conv: str
    offset: int


@dataclass(frozen=True, slots=True)
class FormatIssue:
    """A problem in a format string; `offset` is the index of the offending '%'."""

    message: str
    offset: int


def parse_format(fmt: str) -> tuple[list[str | Conversion], list[FormatIssue]]:
    """The format as literal text pieces and conversions, plus any problems found."""
    parts: list[str | Conversion] = []
    issues: list[FormatIssue] = []
    i = 0
    last_end = -1
    text = ""
    while i < len(fmt):
        if fmt[i] != "%":
            text += fmt[i]
            i += 1
            continue
        m = _SPEC.match(fmt, i)
        assert m is not None
        conv = m.group("conv")
        if conv == "%":
            text += "%"
            i = m.end()
            continue
        if conv == "" or conv not in CONVERSIONS:
            shown = m.group(0) if conv else "%"
            issues.append(
                FormatIssue(
                    f"unknown conversion '{shown}' in the format "
                    "(use %d, %ld, %u, %x, %g or %s; '%%' prints '%')",
                    i,
                )
            )
            text += m.group(0)
            i = m.end()
            continue
        if last_end == i:
            prev = parts[-1]
            assert isinstance(prev, Conversion)
            issues.append(
                FormatIssue(
                    f"conversions '{prev.text}{m.group(0)}' must be separated "
                    "by a space (manual §2.4.2)",
                    i,
                )
            )
        if text:
            parts.append(text)
            text = ""
        parts.append(Conversion(m.group(0), conv, i))
        i = last_end = m.end()
    if text:
        parts.append(text)
    return parts, issues


def count_arguments(parts: list[str | Conversion]) -> tuple[int, bool]:
    """(number of conversions, whether any is %s — which may consume several arguments)."""
    convs = [p for p in parts if isinstance(p, Conversion)]
    return len(convs), any(c.conv == "s" for c in convs)
