"""The simulated controller: the one clock, the task kernel, the machine and its clients.

One cycle (every language's run side is a client of it, runtime/clients.py):
    1. every client's `begin_cycle` (inputs latched, HMPL system variables, PDL drive
       phases up to this cycle)
    2. the task kernel resumes every due task once, in task order
    3. the motion kernel steps gears, gantries, homing, then every axis and its drive
    4. every client's `end_cycle` (GDL procedures, scope samples)
    5. the clock advances one cycle
Between cycles the controller jumps the clock ahead when nothing can change before a
later cycle: no task, no client has an event before it (`next_event`), and every axis
rests or runs a move it can be advanced over in closed form (sim/jumps.py). The
results are identical to stepping. A run ends when no task runs, no axis moves (an
axis jogging at a constant velocity it has reached counts as settled) and no client is
busy.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable

from motionvm.comm.hub import CommHub
from motionvm.io.position_trigger import PositionTriggers
from motionvm.io.system import IOSystem
from motionvm.motion.kernel import MotionKernel
from motionvm.runtime.clients import (
    BEGIN,
    END,
    CycleClient,
    active_hooks,
    hooked_clients,
    hooks_touch_axes,
)
from motionvm.runtime.clock import Clock
from motionvm.runtime.kernel import Kernel
from motionvm.runtime.waits import Waiting
from motionvm.sim.jumps import JumpPlanner
from motionvm.sim.machine import DEFAULT_MACHINE, MachineConfig
from motionvm.sim.pacer import RealTimePacer

_NEVER = 1 << 62
"""A cycle no run reaches (`run` without a progress callback)."""


def until_cycle(until: float, cycle_time: float) -> int:
    """The cycle a run of `until` seconds ends at: the first cycle boundary at or after
    `until` (a run lasts at least that long; 0.35 s of 1 ms cycles is 350 cycles, not 351,
    despite 0.35 / 0.001 being 349.99999999999994 in floating point). A time beyond any
    cycle a run reaches (1e308 s: its cycle count overflows a float) ends at `_NEVER`."""
    cycles = until / cycle_time - 1e-9
    return _NEVER if cycles >= _NEVER else math.ceil(cycles)


FINISHED, UNTIL, STOPPED, FOREVER = "finished", "until", "stopped", "forever"
"""Why `Controller.run` returned (FOREVER: nothing left can change, the run can never
end)."""
_ALONE_MOST = 1000
"""The most cycles `_motion_alone` steps before the run loop looks again."""


class Controller:
    """A controller with a fixed cycle time [s], up to 64 tasks and the machine's axes.

    `machine` gives the axes (default: the built-in machine's); its cycle time is not
    used, `cycle_time` is.
    """

    def __init__(self, cycle_time: float = 0.001, machine: MachineConfig | None = None) -> None:
        self.clock = Clock(cycle_time)
        self.cycle_time = cycle_time
        self.kernel = Kernel(self.clock)
        machine = machine or DEFAULT_MACHINE
        self.motion = MotionKernel(list(machine.axes), cycle_time)
        self.io = IOSystem(machine.io, self.motion, cycle_time)
        """GPIO, EtherCAT slaves, wires and sensors (io/system.py), the first client."""
        self.io.clock = self.clock
        self.triggers = PositionTriggers(self.motion, self.clock)
        """The position trigger of each axis (manual chapter 12), a client of the cycle."""
        self.clients: list[CycleClient] = [self.io]
        """Run sides stepped each cycle, in the order added (runtime/clients.py); the I/O
        system comes first, so the inputs are latched before any language's cycle."""
        self._hooked: list = []
        """The clients `_begin_hooks` and `_end_hooks` were taken from (`step` takes them
        again when `clients` changed)."""
        self._begin_hooks: list = []
        self._end_hooks: list = []
        self._hooks_touch = False
        """A client with hooks to call (or a recorder) reads or writes axes (`touches_axes`)."""
        self.defer_axes = True
        """False: no axis's cycles are ever deferred (motion/deferred.py), every axis
        steps every cycle it does not rest (the reference the tests compare with)."""
        self._defer = False
        """Inside `run`, unpaced, with no progress callback and no tracer: the motion
        kernel may defer moving axes while nothing else reads them (motion/deferred.py)."""
        self.alone_cycles = True
        """False: `run` never steps cycles as motion phases alone (`_motion_alone`), each
        cycle goes through `step` (the reference the tests compare with)."""
        self._alone = False
        """The hooks as taken allow a cycle of the motion kernel alone: no end hook, no
        begin hook but clock-driven ones (`_take_hooks`)."""
        self.comm = CommHub(self.clock, self.io.gpio, self.motion)
        """Servers' requests and client sockets (comm/hub.py), right after the inputs."""
        self.add_client(self.comm)
        self.add_client(self.triggers)
        self.skip = True
        """Jump the clock over cycles in which nothing can change; False steps every
        cycle (`--no-skip`): the results are identical either way."""
        self.jumps = JumpPlanner(self)
        self.cycles_computed = 0
        """Cycles stepped so far (the others were jumped over)."""
        self.cycles_alone = 0
        """Of `cycles_computed`, those stepped as motion phases alone (`_motion_alone`)."""
        self.stop_requested = False  # set to end run() at the next cycle (e.g. stdout closed)
        self.hmi_scope = False
        """SetHMIScope(1) sets it, SetHMIScope(0) clears it (a scope may follow it)."""
        self.hmi_scope_used = False
        """True once a program called SetHMIScope: a scope keeps only its on-periods."""

    def add_client(self, client: CycleClient) -> None:
        """Step `client` (a `PassiveClient`: every capability has its default) every
        cycle from now on, after the clients added before it."""
        self.clients.append(client)

    @property
    def axes(self) -> list:
        """The machine's axes (`motionvm.motion.axis.Axis`), by axis id."""
        return self.motion.axes

    @property
    def cycle(self) -> int:
        return self.clock.cycle

    @property
    def sim_time(self) -> float:
        """Simulated time [s]."""
        return self.clock.cycle * self.cycle_time

    def step(self, end_cycle: int | None = None, fold: bool = False) -> None:
        """Run exactly one controller cycle; with `fold` (time skipping, from `run`: no
        cycle later than `end_cycle`), the cycle's motion phase may open a jump over
        the cycles after it (`JumpPlanner.jump` after the tasks), when no client has
        an `end_cycle` to run after it."""
        clients = self.clients
        if clients != self._hooked:  # a client came (or went) or its work changed
            self._take_hooks()
        for hook in self._begin_hooks:
            hook()
        motion = self.motion
        motion.begin_cycle()
        kernel = self.kernel
        kernel.run_cycle()
        self.jumps.after_tasks()  # (stepping too: a run that can never end is seen)
        if self.skip:
            if (fold and not self._end_hooks and clients == self._hooked
                    and self.jumps.jump(end_cycle, after_tasks=True)):  # fmt: skip
                self.cycles_computed += 1
                return
        # no hook nor task but the status flags and the axis commands read an axis:
        # moving axes may be deferred (motion/deferred.py)
        motion.deferring = self._defer and not (self._hooks_touch or kernel.reads_axes)
        motion.step()
        if clients != self._hooked:  # a task added a client: it ends this cycle
            self._take_hooks()
        for hook in self._end_hooks:
            hook()
        self.clock.cycle += 1
        self.cycles_computed += 1

    def _take_hooks(self) -> None:
        """The hooks of the clients as they are now: a client's begin_cycle and end_cycle
        unless it is `PassiveClient`'s no-op or its client has no work for it now
        (runtime/clients.py); a client's `work_changed()` has them taken again."""
        self._hooked = hooked = list(self.clients)  # first: a change from now on counts
        for c in hooked:
            c.watch_work(self._work_changed)
        begins = hooked_clients(hooked, BEGIN)
        self._begin_hooks = [c.begin_cycle for c in begins]
        self._end_hooks = active_hooks(hooked, END)
        self._hooks_touch = touch = hooks_touch_axes(hooked)
        self._alone = not self._end_hooks and all(c.clock_driven for c in begins)
        if touch:  # a hook may read any axis from now on
            self.motion.catch_up()

    def _work_changed(self) -> None:
        """A client's work changed: take the hooks again before the next phase's calls."""
        self._hooked = []

    def busy(self) -> bool:
        """True while any task runs, any axis moves, enables or settles, or a client is busy."""
        return self.kernel.any_running or self.motion.busy() or any(c.busy() for c in self.clients)

    def next_event(self) -> int | None:
        """The earliest cycle a task or client wants to be stepped at (None: none)."""
        wake = self.kernel.next_wake()
        for c in self.clients:
            e = c.next_event()
            if e is not None and (wake is None or e < wake):
                wake = e
        return wake

    def run(
        self,
        until: float | None = None,
        realtime: bool = False,
        progress: Callable[[float], None] | None = None,
        progress_every: int = 100,
        deadline: bool = False,
    ) -> str:
        """Run until nothing is left to do, or until `until` seconds of simulated time;
        with `realtime`, never ahead of the wall clock (sim/pacer.py). Returns why it
        stopped: FINISHED (nothing left to do), UNTIL (the end time came first) or
        STOPPED (`stop_requested`), or FOREVER: no task, axis or client can change
        anything any more (`JumpPlanner.never_changes`), while the run is not paced and
        either has no end time or `until` is a `deadline` (a timeout: the run should have
        finished by then, not merely lasted that long). Exact: a run that a scenario
        event, a sleeping task, a moving axis or a listening server could still move on
        goes on; identical with and without time skipping.

        `progress(sim_time)` [s], if given, is called between cycles: before the first,
        then once `progress_every` cycles have passed since the last call (a jump ahead
        counts its cycles). It observes the run and must not change it; deciding when to
        redraw anything is its own business (the controller reads no wall clock)."""
        end_cycle = None if until is None else until_cycle(until, self.cycle_time)
        clock = self.clock
        pacer = RealTimePacer(self.sim_time) if realtime else None
        self.stop_requested = False
        self.jumps.forget()
        ends = pacer is None and (deadline or end_cycle is None)  # a run that never can
        self.jumps.deadline = ends and end_cycle is not None
        # while skipping, a task's status wait records the flags it read (sim/jumps.py)
        # (stepping too, so that both see a run that can never end at the same cycle)
        self.kernel.recorder = self.motion
        # nothing outside the cycle looks at the axes until the run returns
        self._defer = (self.defer_axes and pacer is None and progress is None
                       and sys.gettrace() is None)  # fmt: skip
        next_report = _NEVER if progress is None else clock.cycle
        kernel = self.kernel
        active = kernel.active  # a running task keeps the run busy: no call
        # stepping, unpaced: cycles with nothing but motion to do run as motion alone
        alone = self.alone_cycles and not self.skip and pacer is None
        try:
            while active or self.busy():
                if self.stop_requested:
                    return STOPPED
                if clock.cycle >= next_report and progress is not None:
                    progress(self.sim_time)
                    next_report = clock.cycle + progress_every
                if pacer is not None:
                    pacer.wait(self.sim_time)
                    self.jumps.forget()  # a client may have written a variable meanwhile
                if end_cycle is not None and clock.cycle >= end_cycle:
                    return UNTIL
                if self.skip:
                    if self.jumps.jump(end_cycle):
                        continue
                    never = self.jumps.never
                else:  # the test a jump makes, alone
                    never = self.never_changes()
                if never and ends:
                    return FOREVER
                if (alone and self._alone and not kernel.resumed
                        and self._motion_alone(end_cycle, next_report)):  # fmt: skip
                    continue
                self.step(end_cycle, fold=pacer is None)  # (paced: a jump waits at its start)
            return FINISHED
        finally:
            self._defer = self.motion.deferring = False
            self.motion.catch_up()  # (the host may read any axis now)
            self.show_clock()

    def _motion_alone(self, end_cycle: int | None, next_report: int) -> bool:
        """Step the cycles from this one on in which nothing but the motion kernel has
        work, as motion phases alone (`MotionKernel.step_alone`), without the rest of
        `step`; False if this cycle is not one (the run loop asks only after a cycle
        that resumed no task, `Kernel.resumed`). Such a cycle: no task is due and the
        task kernel is as a cycle without one leaves it (`Kernel.idle_until`), no client
        has an event (`next_event`) nor a hook but clock-driven ones (not called: the
        next `step`, or `show_clock` at the run's end, writes their values before
        anything reads them) and no client came.
        Stepped so, the cycles change what `step` would: no more of them than the run
        loop would step without deciding anything (up to the end time, the next
        progress report, a task's wake, `_ALONE_MOST` at a time for `stop_requested`),
        and no cycle after one that leaves the axes at rest (the run may never change
        again) or, while no task runs and no client is busy, the motion kernel not busy
        (the run ends)."""
        clock, kernel = self.clock, self.kernel
        cycle = clock.cycle
        if self.clients != self._hooked:
            return False
        limit = kernel.idle_until(cycle)
        if limit is not None and limit <= cycle:
            return False
        for c in self.clients:
            e = c.next_event()
            if e is not None and (limit is None or e < limit):
                if e <= cycle:
                    return False
                limit = e
        n = min(_ALONE_MOST, next_report - cycle)
        for bound in (limit, end_cycle):
            if bound is not None:
                n = min(n, bound - cycle)
        if n <= 0:
            return False
        until_idle = not kernel.active and not any(c.busy() for c in self.clients)
        motion = self.motion
        motion.deferring = self._defer and not (self._hooks_touch or kernel.reads_axes)
        k = motion.step_alone(n, until_idle)
        clock.cycle = cycle + k
        self.cycles_computed += k
        self.cycles_alone += k
        return True

    def never_changes(self) -> bool:
        """At a cycle boundary: nothing left in the run can change anything (every
        running task waits on an event, or none runs, and `JumpPlanner.never_changes`)."""
        kernel = self.kernel
        return bool(kernel.event_waits or not kernel.active) and self.jumps.never_changes()

    def show_clock(self) -> None:
        """Between cycles: the values computed from the clock alone (the HMPL system
        time, `clock_driven` clients) show the clock as it is now. Each cycle's
        `begin_cycle` sets them for that cycle, so after cycle k they would still show k
        (or an earlier cycle, after a jump) while the clock reads k + 1; the next
        `begin_cycle` writes the same values again."""
        for c in self.clients:
            if c.clock_driven:
                c.begin_cycle()

    def still_running(self) -> list[Waiting]:
        """What keeps the run busy: each client's tasks and programs (where they wait),
        then every axis that moves, enables or settles."""
        out: list[Waiting] = []
        for c in self.clients:
            out.extend(c.still_running())
        out.extend(self.motion.still_running())
        return out
