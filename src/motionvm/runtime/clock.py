"""The controller's one clock: an integer cycle count and the cycle time.

Every part of a run reads time from here: HMPL tasks (`system_timeInMs`), PDL drives
(their phases run inside each cycle), GDL procedures (`t=S` stamps) and the scope.
Time is an integer count of cycles, so no float drift accumulates; `sim_time` [s] is
derived from it. Nothing reads the wall clock.
"""

from __future__ import annotations

import math


class Clock:
    """Simulated time: `cycle` [int] of `cycle_time` [s] each."""

    __slots__ = ("cycle", "cycle_time")

    def __init__(self, cycle_time: float = 0.001) -> None:
        if not (cycle_time > 0 and math.isfinite(cycle_time)):
            raise ValueError(f"cycle time must be positive, got {cycle_time}")
        self.cycle = 0
        """Cycles completed since power-on [int]."""
        self.cycle_time = cycle_time
        """Length of one cycle [s]."""

    @property
    def sim_time(self) -> float:
        """Simulated time [s]."""
        return self.cycle * self.cycle_time


STAMP_DECIMALS = 6
"""Decimals of the simulated time in a `--stamp` prefix, in every language."""


def stamp_prefix(sim_time: float, source: str) -> str:
    """The `--stamp` prefix of a message line, the same for every language:
    `[t=S.SSSSSS][SOURCE] ` (SOURCE: `task 3`, `drive 1 task 0`, `gdl PROC`, `gdl`)."""
    return f"[t={sim_time:.{STAMP_DECIMALS}f}][{source}] "
