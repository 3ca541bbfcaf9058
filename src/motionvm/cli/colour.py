"""Colour for the messages on stderr when a person reads them: a terminal, and `NO_COLOR`
unset or empty (https://no-color.org). Piped or redirected, every byte stays as it is.

A message is plain text in the one diagnostic format (`FILE:LINE:COL: error: MESSAGE`,
the source line, a caret) or `motionvm: error: ...`; this face only adds styles to it
(rich writes the escape sequences): the place in bold, the severity in its colour, the
caret in green, as gcc and clang do.
"""

from __future__ import annotations

import os
import re
import sys

_HEAD = re.compile(
    r"^(?P<place>(?:[^\n]*?:\d+:\d+|motionvm)): (?P<severity>error|warning|note|runtime error)"
    r"(?P<rest>[^\n]*)"
)
_STYLES = {
    "error": "bold red",
    "runtime error": "bold red",
    "warning": "bold magenta",
    "note": "bold cyan",
}


def wanted(stream=None) -> bool:
    """True when `stream` (default stderr) is a terminal and NO_COLOR is unset or empty."""
    if os.environ.get("NO_COLOR", ""):
        return False
    stream = sys.stderr if stream is None else stream
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False


def coloured(message: str) -> str:
    """`message` with ANSI styles: its first line's place and severity, a caret line."""
    try:
        from rich.console import Console
        from rich.text import Text
    except ImportError:  # a dependency, but an install without it still prints
        return message

    lines = message.split("\n")
    text = Text()
    m = _HEAD.match(lines[0])
    if m is None:
        text.append(lines[0])
    else:
        text.append(m["place"], "bold")
        text.append(": ")
        text.append(m["severity"], _STYLES[m["severity"]])
        text.append(m["rest"], "bold" if m["severity"] != "note" else "")
    for line in lines[1:]:
        text.append("\n")
        caret = line.rstrip().endswith("^") and not line.replace("^", "").strip()
        text.append(line, "bold green" if caret else "")
    console = Console(force_terminal=True, color_system="standard", highlight=False, width=10**6)
    with console.capture() as capture:
        console.print(text, end="", soft_wrap=True)
    return capture.get()
