"""The simulated controller: the cycle clock, the task kernel and the programs on it.

One cycle (DESIGN.md): programs update system variables, the kernel runs every due
task once, the motion kernel steps every axis (profile generators, limits, PDOs, the
drives and their feedback), the clock advances. When no task is due before some later
cycle and every axis rests (a fixed point: stepping it changes nothing), the clock
jumps straight to that cycle; the results are identical to stepping. A client with a
`busy()` method (sim/pdl_drives.py) counts as running work while it returns true: the
run goes on, and the clock does not jump.
"""

from __future__ import annotations

import math
from typing import Protocol

from motionvm.io.gpio import DigitalIO
from motionvm.motion.kernel import MotionKernel
from motionvm.runtime.kernel import Kernel
from motionvm.sim.machine import DEFAULT_MACHINE, MachineConfig
from motionvm.sim.pacer import RealTimePacer


class CycleClient(Protocol):
    def begin_cycle(self) -> None: ...


class Controller:
    """A controller with a fixed cycle time [s], up to 64 tasks and the machine's axes.

    `machine` gives the axes (default: the built-in machine's); its cycle time is not
    used, `cycle_time` is.
    """

    def __init__(self, cycle_time: float = 0.001, machine: MachineConfig | None = None) -> None:
        if not (cycle_time > 0 and math.isfinite(cycle_time)):
            raise ValueError(f"cycle time must be positive, got {cycle_time}")
        self.cycle_time = cycle_time
        self.kernel = Kernel()
        self.motion = MotionKernel(list((machine or DEFAULT_MACHINE).axes), cycle_time)
        self.io = DigitalIO()
        self.clients: list[CycleClient] = []
        self.busy_clients: list = []
        """Clients whose `busy()` keeps the run going and forbids jumps (PDL drives)."""
        self.allow_jump = True
        self.stop_requested = False  # set to end run() at the next cycle (e.g. stdout closed)
        self.hmi_scope = False
        """SetHMIScope(1) sets it, SetHMIScope(0) clears it (a scope may follow it)."""

    @property
    def axes(self) -> list:
        """The machine's axes (`motionvm.motion.axis.Axis`), by axis id."""
        return self.motion.axes

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
        self.motion.begin_cycle()
        self.kernel.run_cycle()
        self.motion.step()
        for c in self.clients:  # optional hook: sees the state the cycle left (scope recording)
            end = getattr(c, "end_cycle", None)
            if end is not None:
                end()
        self.kernel.cycle += 1

    def busy(self) -> bool:
        """True while any task runs or any axis moves, enables or settles."""
        return (
            self.kernel.any_running
            or self.motion.busy()
            or any(c.busy() for c in self.busy_clients)
        )

    def run(self, until: float | None = None, realtime: bool = False) -> None:
        """Run until nothing is left to do, or until `until` seconds of simulated time;
        with `realtime`, never ahead of the wall clock (sim/pacer.py)."""
        end_cycle = None if until is None else round(until / self.cycle_time)
        k = self.kernel
        pacer = RealTimePacer(self.sim_time) if realtime else None
        self.stop_requested = False
        while k._active or self.busy():  # a running task: busy, without the call
            if self.stop_requested:
                return
            if pacer is not None:
                pacer.wait(self.sim_time)
            if end_cycle is not None and k.cycle >= end_cycle:
                return
            if (
                self.allow_jump
                and self.motion.at_rest()
                and not any(c.busy() for c in self.busy_clients)
            ):
                wake = k.next_wake()
                if wake is not None and wake > k.cycle:
                    target = wake if end_cycle is None else min(wake, end_cycle)
                    k.cycle = max(k.cycle, target)
                    continue
            self.step()
