"""The protocol of a scope channel source, and the error of a bad scope request.

Every layer that owns observable values (the axes, the controller I/O, a language's
variables, a PDL drive's system variables, a GDL object's states) offers them to the
scope through a `ChannelSource`; the assembler of a run collects the sources and the
scope (sim/scope.py) asks them in turn. Language run sides hand theirs over with a
`scope_sources()` method; nothing is attached to another layer's object.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Protocol

# Unit of a channel that is a single bit (drawn as steps, a 1-bit wire in VCD).
BIT_UNIT = "bool"
# Unit of a plain number with no physical unit (test variables, globals, counters).
RAW_UNIT = "raw"


class ScopeError(ValueError):
    """A bad scope request (unknown channel, bad flag, unwritable output); exit code 3."""


class ChannelSource(Protocol):
    """Something that owns values the scope can record."""

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        """(getter, unit) for a channel of this source; None if `name` is not one of ours.

        A source may raise ScopeError for a name that is its own but wrong (an array
        index out of range, an axis that does not exist), to say exactly what is wrong.
        """
        ...

    def channel_names(self) -> Iterable[str]:
        """Names offered for "did you mean" suggestions (may be a subset for big arrays)."""
        ...
