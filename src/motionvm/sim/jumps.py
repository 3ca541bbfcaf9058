"""Time skipping: where the controller may jump the clock to, and the jump itself.

One rule for every part of a run: each reports the next cycle at which something of it
can change, and the clock jumps to the earliest of them, so that the cycles in between
are never computed. A task reports its wake cycle (Sleep), or nothing while it waits on
an event (a Till whose condition only a computed cycle can change: `runtime/kernel.py`
EVENT_WAIT); a client its `next_event`; the motion kernel how far its axes can be
advanced in closed form (`MotionKernel.coast_horizon`: a resting axis forever, an axis
on a plain profile move until region I ends, or, when no task passed over reads its
`IsMoving`, until it comes into position; a moving axis group and its axes to the
next segment end where its path stops, motion/group_coast.py; any other axis not at
all). Axes are
advanced over the jumped cycles by `MotionKernel.coast`, which leaves every value as
stepping would; a client that reads moving axes in its hooks (`observes_motion`)
keeps the clock from jumping while an axis moves. A client that samples skipped cycles
(`samples_skipped_cycles`: a scope) has each jumped cycle it samples (`next_sample`:
every cycle, or every N-th) sampled: the jump then stops at each of them, setting the
clock-driven values (the HMPL system time) and advancing the moving axes to it, with no
task, no other client run. The planner
reads only what each part declares: the task kernel's `wake_horizon`, the motion
kernel's `coast_horizon`, `coast` and `steps_alone`, and the capabilities of the
clients (runtime/clients.py, each with its default on `PassiveClient`).

A task waiting on an event is passed over only if nothing it tests changed since it
polled: no task acted after it in its cycle (`Kernel.quiet`), and the status it tests
(every axis's flags, the digital inputs and outputs) is now what it was right after
the tasks of the last computed cycle (`after_tasks`); a jump then ends at the first
change of any axis's status. Otherwise that task is stepped
once more, and polls again. Each `Controller.run` starts without that record, as the
host may have changed a variable between runs. A task waiting on a condition of status
flags alone (STATUS_WAIT) is passed over while the flags its poll read answer the same
(`Task.record_holds`), whatever the other tasks did.

When no task and no client is due but an axis can be advanced neither by coasting nor
by resting (the end of a smoothed move, an axis that is not on the common path), the
jump is a single cycle of the motion kernel alone (`_motion_cycle`): the cycle stepping
computes, minus tasks that would only poll and clients that have nothing to do in it.
"""

from __future__ import annotations

from motionvm.motion.axis_coast import NEVER
from motionvm.runtime.clients import PassiveClient, is_default, motion_observation

_NO_EVENT = PassiveClient.next_event


class JumpPlanner:
    """Decides, between two cycles of one controller, whether and how far to jump."""

    def __init__(self, controller) -> None:
        self.controller = controller
        self._signature: tuple | None = None
        """The status right after the tasks of the last computed cycle (None: unknown)."""
        self.jumps = 0
        """Jumps made so far (the cycles they covered were not computed)."""
        self.never = False
        """The last jump found that nothing can change any more (`never_changes`)."""
        self.deadline = False
        """The run's end cycle is a deadline, not a time to reach: a jump does not go to
        it when nothing can change any more (the run ends as one that never can)."""
        self._take_clients(controller.clients)

    def _status(self) -> tuple:
        ctl = self.controller
        gpio = ctl.io.gpio
        return (ctl.motion.status_signature(), tuple(gpio.inputs), tuple(gpio.outputs),
                ctl.io.digital_signature())  # fmt: skip

    def after_tasks(self) -> None:
        """Record what the waiting tasks without a record of their own saw (the
        controller calls it after the tasks)."""
        self._signature = self._status() if self.controller.kernel.unrecorded_waits else None

    def forget(self) -> None:
        """Something outside the cycle may have changed what a task tests."""
        self._signature = None

    def _take_clients(self, clients: list) -> None:
        """What a jump asks of `clients`: their next events (a `PassiveClient` has none),
        whether they read moving axes (a constant or a property), which sample every
        cycle."""
        self._clients = list(clients)
        self._events = [c.next_event for c in clients if not is_default(c.next_event, _NO_EVENT)]
        self._observers = []
        self._observed = False
        for c in clients:
            observes = motion_observation(c)
            if observes is None:
                self._observers.append(c)
            elif observes:
                self._observed = True
        self._samplers = [c for c in clients if c.samples_skipped_cycles]

    def jump(self, end_cycle: int | None, after_tasks: bool = False) -> bool:
        """Jump the clock ahead if nothing can change before a later cycle (advancing the
        moving axes to it); True if it jumped. `end_cycle` bounds the jump.

        `after_tasks`: the jump opens in the motion phase of the cycle being computed,
        whose tasks have run and left a task running (`Controller.step` asks it when no
        client has an `end_cycle` for it): the axes are advanced from this cycle's
        motion phase on, and no task may be due in the next cycle. A jump of k cycles
        is then this cycle's motion phase and the k - 1 cycles after it."""
        ctl = self.controller
        cycle = ctl.clock.cycle
        self.never = False
        limit = NEVER if end_cycle is None else end_cycle - cycle
        if limit <= after_tasks:  # (after the tasks, one cycle is no jump)
            return False
        if after_tasks and not ctl.kernel.active:
            return False  # (no task runs: the run may end with this cycle)
        first = cycle + after_tasks  # the first cycle whose tasks are passed over
        wake, watched, watches = ctl.kernel.wake_horizon(first, self._status_holds, "moving")
        if wake is not None and wake <= first:
            return False
        clients = ctl.clients
        if clients != self._clients:
            self._take_clients(clients)
        if after_tasks and self._samplers:
            return False  # (a sampler records this cycle's motion phase)
        for next_event in self._events:
            e = next_event()
            if e is not None and (wake is None or e < wake):
                if e <= first:
                    return False
                wake = e
        motion = ctl.motion
        resting = motion.at_rest()
        if wake is not None:
            limit = min(limit, wake - cycle)
        if resting:
            if wake is None and (end_cycle is None or self.deadline):
                self.never = not after_tasks  # nothing will ever change (`never_changes`)
                return False
            k = limit
        else:
            if self._observed:
                return False
            for c in self._observers:  # (a loop: no generator for any() per jump)
                if c.observes_motion:
                    return False
            k = motion.coast_horizon(limit, watched, watches)
            if after_tasks:
                if k <= 1:  # this cycle's motion phase is stepped
                    return False
            elif not k:
                return self._motion_cycle(cycle)
        if self._samplers:
            self._sampled_jump(cycle, k, resting, self._samplers)
        elif not resting:
            motion.coast(k)
        ctl.clock.cycle = cycle + k
        self.jumps += 1
        return True

    def never_changes(self) -> bool:
        """True if nothing of the run can change any more, at a cycle boundary of a run
        with no input from outside (no pacing, no server): every axis rests, every
        running task waits on an event that it would find false again if polled now
        (`Kernel.wake_horizon`, the same test a jump passes tasks over by), no task
        sleeps and no client has a next event. A jump would then go on forever: the
        run can never end (`Controller.run` ends it as FOREVER)."""
        ctl = self.controller
        if not ctl.motion.at_rest():
            return False
        wake, _watched, _watches = ctl.kernel.wake_horizon(
            ctl.clock.cycle, self._status_holds, "moving"
        )
        if wake is not None:
            return False
        for next_event in self._events_of(ctl.clients):
            if next_event() is not None:
                return False
        return True

    def _events_of(self, clients: list) -> list:
        if clients != self._clients:
            self._take_clients(clients)
        return self._events

    def _status_holds(self) -> bool:
        """True if the status is what it was right after the tasks of the last computed
        cycle (`after_tasks`): what a task waiting on an event without a record of its
        own tests is unchanged (`Kernel.wake_horizon`)."""
        seen = self._signature
        return seen is not None and seen == self._status()

    def _motion_cycle(self, cycle: int) -> bool:
        """Jump over cycle `cycle` stepping only the motion kernel (no task, no client
        is due in it); True if it did. Not with a client that samples every cycle, nor
        with gears, gantry pairs or a starting bus."""
        ctl = self.controller
        motion = ctl.motion
        if self._samplers:
            return False
        if not motion.steps_alone():
            return False
        motion.begin_cycle()
        motion.step()
        ctl.clock.cycle = cycle + 1
        self.jumps += 1
        return True

    def _sampled_jump(self, cycle: int, k: int, resting: bool, samplers: list) -> None:
        """Jump over cycles `cycle` .. `cycle + k - 1` for the clients that sample skipped
        cycles (a scope): at each cycle one of them samples (`next_sample`) the clock
        shows it, the clients whose `begin_cycle` only writes values of the clock
        (`clock_driven`, the HMPL system time) set them, the moving axes are advanced to
        it (in closed form from the last sampled cycle: the same values as one cycle at
        a time) and the samplers' `end_cycle` records the state that cycle left, as
        stepping would."""
        ctl = self.controller
        clock, motion = ctl.clock, ctl.motion
        timed = [c for c in ctl.clients if c.clock_driven]
        pos, end = cycle, cycle + k  # pos: the next cycle the axes are advanced over
        while pos < end:
            c = min([s.next_sample(pos) for s in samplers])
            if c >= end:
                if not resting:
                    motion.coast(end - pos)
                return
            clock.cycle = c
            for t in timed:
                t.begin_cycle()
            if not resting:
                motion.coast(c + 1 - pos)
            for s in samplers:
                s.end_cycle()
            pos = c + 1
