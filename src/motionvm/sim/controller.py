"""The simulated controller: the cycle clock, the task kernel and the programs on it.

One cycle (DESIGN.md): programs update system variables, the kernel runs every due
task once, motion and devices step (added by the axis work), the clock advances.
When no task is due before some later cycle and nothing else needs stepping, the
clock jumps straight to that cycle; the results are identical to stepping.
"""

from __future__ import annotations

import math
from typing import Protocol

from motionvm.runtime.kernel import Kernel


class CycleClient(Protocol):
    def begin_cycle(self) -> None: ...


class Controller:
    """A controller with a fixed cycle time [s] and up to 64 tasks."""

    def __init__(self, cycle_time: float = 0.001) -> None:
        if not (cycle_time > 0 and math.isfinite(cycle_time)):
            raise ValueError(f"cycle time must be positive, got {cycle_time}")
        self.cycle_time = cycle_time
        self.kernel = Kernel()
        self.clients: list[CycleClient] = []
        self.allow_jump = True

    @property
    def cycle(self) -> int:
        return self.kernel.cycle

    @property
    def sim_time(self) -> float:
        """Simulated time [s]."""
        return self.kernel.cycle * self.cycle_time

    def step(self) -> None:
        """Run exactly one controller cycle."""
        for c in self.clients:
            c.begin_cycle()
        self.kernel.run_cycle()
        for c in self.clients:  # optional hook: sees the state the cycle left (scope recording)
            end = getattr(c, "end_cycle", None)
            if end is not None:
                end()
        self.kernel.cycle += 1

    def busy(self) -> bool:
        """True while any task runs (motion will add to this)."""
        return self.kernel.any_running

    def run(self, until: float | None = None) -> None:
        """Run until nothing is left to do, or until `until` seconds of simulated time."""
        end_cycle = None if until is None else int(round(until / self.cycle_time))
        k = self.kernel
        while self.busy():
            if end_cycle is not None and k.cycle >= end_cycle:
                return
            if self.allow_jump:
                wake = k.next_wake()
                if wake is not None and wake > k.cycle:
                    target = wake if end_cycle is None else min(wake, end_cycle)
                    k.cycle = max(k.cycle, target)
                    continue
            self.step()
