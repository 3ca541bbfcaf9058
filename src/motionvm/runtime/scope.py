"""The protocol of a scope channel source, and the error of a bad scope request.

Every layer that owns observable values (the axes, the controller I/O, a language's
variables, a PDL drive's system variables, a GDL object's states) offers them to the
scope through a `ChannelSource` (the base every source derives from); the assembler of
a run collects the sources and the scope (sim/scope.py) asks them in turn. Language
run sides hand theirs over with a `scope_sources()` method; nothing is attached to
another layer's object. What the scope reads of an axis is `ScopeAxis`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence

# Unit of a channel that is a single bit (drawn as steps, a 1-bit wire in VCD).
BIT_UNIT = "bool"
# Unit of a plain number with no physical unit (test variables, globals, counters).
RAW_UNIT = "raw"


class ScopeError(ValueError):
    """A bad scope request (unknown channel, bad flag, unwritable output); exit code 3."""


class ChannelSource:
    """Something that owns values the scope can record: the base of every source, with
    the default of each capability (a source overrides what it offers)."""

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        """(getter, unit) for a channel of this source; None if `name` is not one of ours.

        A source may raise ScopeError for a name that is its own but wrong (an array
        index out of range, an axis that does not exist), to say exactly what is wrong.
        """
        return None

    def channel_names(self) -> Iterable[str]:
        """Names offered for "did you mean" suggestions (may be a subset for big arrays)."""
        return ()

    def write(self, name: str, value: object) -> bool:
        """Set channel `name` to `value` (a host's or a scenario's write); False if
        `name` is not this source's to write (default: none is). A source may raise
        ValueError or TypeError for a value it refuses."""
        return False

    def read_only(self, name: str) -> bool:
        """True if `name` is this source's and refuses every write (a value the run sets
        itself, such as the system time); default: none is."""
        return False


class EdgeGetter:
    """A channel getter that also knows the exact times its value changed, between
    samples (the position trigger's output, whose pulses are shorter than a cycle): the
    VCD writer puts each change at its time."""

    def __call__(self) -> float:
        """The value now."""
        raise NotImplementedError

    def record_edges(self) -> None:
        """Keep the changes from now on (a recording attaches)."""

    def edges(self) -> list[tuple[float, int]]:
        """(sim_time [s], value) of each change since `record_edges`."""
        return []


class ScopeAxis:
    """What the scope reads of an axis (`axisN.<variable>`): the base of the axis
    layer's axes, with the default of each capability."""

    __slots__ = ()

    rotary = False
    """True if the axis turns: its variables are in deg, not mm."""

    def variable(self, name: str) -> float | int:
        """The axis variable `name` of manual 5.1.1 (KeyError if there is none)."""
        raise KeyError(name)

    def variable_names(self) -> Sequence[str] | None:
        """The variables `variable` answers; None (the default): those of manual 5.1.1."""
        return None
