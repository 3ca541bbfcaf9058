"""The plant between outputs and inputs: wires (`[[wire]]`) and position sensors
(`[[sensor]]`), stepped by the I/O system's cycle.

Timing (exact to the cycle): the controller writes its outputs at the end of a cycle
(after the tasks and the motion step) and latches its inputs at the start of the next.
A wire samples its output's pin at the end of every cycle; a change seen at the end of
cycle k reaches the input at the start of cycle k + 1 + D, D = ceil(delay_ms / cycle).
So with no delay a program that sets `gpo3` in cycle k reads the wired `gpi4` changed
in cycle k + 1; with `delay_ms = 5` at 1 ms, in cycle k + 6. An analog wire carries
raw values as GetSlvAORaw and GetSlvAIRaw read them (two's complement on an
HMPL_DAC_SIGNED channel, so a negative value keeps its sign through a gain):
input raw = round(gain * output raw + offset), clamped to the raw values the input's
type holds (-2^(bits-1) .. 2^(bits-1) - 1 signed, 0 .. 2^bits - 1 unsigned). A sensor sets its input at the start of each cycle from the axis's feedback
position the last motion step left, as GetPosFb reports it (wrapped on a rollover axis):
on inside [from, to], `invert` swaps on and off.

For the controller's time skipping each `Wire` keeps its pending changes in order and
`next_due` tells the earliest; a wire whose output changed since it was last sampled
(a host write between cycles) asks for the current cycle. Sensors change only when
their axis moves, and a moving axis makes the controller step anyway.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable


class Wire:
    """One wire: reads an output pin, drives an input pin `delay_cycles` later."""

    __slots__ = ("read", "write", "delay_cycles", "analog", "gain", "offset", "last", "pending")

    def __init__(
        self,
        read: Callable[[], int],
        write: Callable[[int], None],
        delay_cycles: int,
        analog: bool = False,
        gain: float = 1.0,
        offset: float = 0.0,
    ) -> None:
        self.read = read
        self.write = write
        self.delay_cycles = delay_cycles
        self.analog = analog
        self.gain = gain
        self.offset = offset
        self.last: int | None = None
        """The output's value at the last sample (None: never sampled)."""
        self.pending: deque[tuple[int, int]] = deque()
        """(cycle it reaches the input, value), in cycle order."""

    def sample(self, cycle: int) -> None:
        """End of `cycle`: a changed output reaches the input at cycle + 1 + delay."""
        value = self.read()
        if value != self.last:
            self.last = value
            self.pending.append((cycle + 1 + self.delay_cycles, value))

    def deliver(self, cycle: int) -> None:
        """Start of `cycle`: every change due by now reaches the input, in order."""
        pending = self.pending
        while pending and pending[0][0] <= cycle:
            self.write(self._carry(pending.popleft()[1]))

    def _carry(self, value: int) -> int:
        if not self.analog or (self.gain == 1.0 and self.offset == 0.0):
            return value
        x = self.gain * value + self.offset
        return int(math.floor(x + 0.5))

    def next_due(self, cycle: int) -> int | None:
        if self.last is None or self.read() != self.last:
            return cycle
        return self.pending[0][0] if self.pending else None


class Sensor:
    """A position switch: drives an input while an axis's feedback lies in [lo, hi]."""

    __slots__ = ("axis", "lo", "hi", "invert", "write", "level")

    def __init__(self, axis, lo: float, hi: float, invert: bool, write: Callable[[int], None]):
        self.axis = axis
        self.lo = lo
        self.hi = hi
        self.invert = invert
        self.write = write
        self.level: int | None = None

    def value(self) -> int:
        inside = self.lo <= self.axis.variable("pos_fb") <= self.hi
        return 1 if inside != self.invert else 0

    def update(self) -> None:
        v = self.value()
        if v != self.level:
            self.level = v
            self.write(v)

    def changed(self) -> bool:
        """True if the input is not what the axis's position says (needs a cycle)."""
        return self.value() != self.level


def delay_cycles(delay_ms: float, cycle_time: float) -> int:
    """Whole cycles a wire's delay spans: ceil(delay / cycle), exact for whole multiples."""
    return max(0, math.ceil(delay_ms / (cycle_time * 1000.0) - 1e-9))
