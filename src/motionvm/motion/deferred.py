"""Deferred axis cycles: a moving axis that nobody reads is advanced in batches.

While a run steps every cycle (time skipping off, or a task that polls every cycle so
the clock cannot jump), most of a moving axis's cycles change nothing anybody looks at
but its status flags, and those stay the same until its move reaches a status change.
The motion kernel then defers such an axis's cycles (`Deferrals.step`): when the axis
comes to a motion phase on the common path (motion/axis_coast.py), `coast_cycles` tells
how many cycles it can be advanced without its status changing before the last of
them (the horizon), and the axis is not stepped until then: each motion phase only
counts one more deferred cycle. In the motion phase of the horizon's last cycle the
deferred cycles and that one are advanced at once in closed form (`coast`), exactly
as stepping them would, so a status change lands in the cycle stepping puts it in.

Nothing may see a deferred axis in between except its status flags (`moving`,
`in_pos`, `enabled`, `error_stop`, `resting`: all as stepping leaves them over the
horizon). Whatever reads or changes anything else of it brings it up to date first
(`catch_up`: the deferred cycles in closed form, or stepped when they are too few for
the formulas): every command and getter of the axis (`MotionKernel.axis`), the motion
kernel's own questions but the status flags (`busy`, `coast_horizon`, `coast`,
`still_running`), and the end of every run. The controller defers only while nothing
else can look (`Controller.step`): no hook of a client that reads or writes axes
(`touches_axes`, runtime/clients.py), no task that might read an axis other than
through those getters (`Kernel.reads_axes`: an HMPL program calling only the system,
string, math and axis built-ins clears it), no gear, gantry pair, enabled axis group or
starting bus, no debugger tracing, no progress callback and no real-time pacing.
"""

from __future__ import annotations

from motionvm.motion.axis_coast import MAX_COAST, MIN_COAST, coast, coast_cycles
from motionvm.motion.profile import VELOCITY

MIN_DEFER = 8
"""Fewest cycles worth deferring (a shorter horizon: the axis steps)."""

RETRY = 4
"""Cycles an axis steps before it asks again for a horizon after it had none."""


class Deferrals:
    """The deferred axes of one motion kernel. Motion phases are counted (`phase`); a
    deferred axis has [the phase before its first deferred one, the phase of its
    horizon's last cycle] in `lagging` and waits in `_due` under the latter; the axes
    not deferred (`_free`, in step order) are the only ones a motion phase looks at."""

    __slots__ = ("lagging", "batches", "phase", "passed", "_due", "_free", "_order", "_retry")

    def __init__(self) -> None:
        self.lagging: dict = {}
        """Each deferred axis: [the last phase it was up to date at, its horizon's end]."""
        self.batches = 0
        """Deferred runs of cycles advanced at once so far (at their horizon or caught up)."""
        self.phase = 0
        """Motion phases run so far (`step`, and those `pass_idle` counted)."""
        self.passed = 0
        """Of `phase`, those `pass_idle` counted."""
        self._due: dict = {}  # phase -> the axes whose horizon ends in it
        self._free: list = []  # the axes of `_order` not deferred
        self._order: list | None = None  # the step order `_free` was taken from
        self._retry: dict = {}  # axis -> phases it steps before asking for a horizon again

    def _freed(self, axes: list) -> None:
        lagging = self.lagging
        self._order = axes
        self._free = [a for a in axes if a not in lagging]

    def step(self, axes: list) -> None:
        """The motion phase of one cycle of `axes` (in step order), deferring what can be."""
        self.phase = phase = self.phase + 1
        lagging = self.lagging
        if axes is not self._order:
            self._freed(axes)
        due = self._due.pop(phase, None)
        if due is not None:  # the horizon's last cycle: advance all of them now
            for a in due:
                entry = lagging.get(a)
                if entry is not None and entry[1] == phase:  # (else caught up since)
                    del lagging[a]
                    coast(a, phase - entry[0])
                    self.batches += 1
            self._freed(axes)
        changed = False
        retry = self._retry
        for a in self._free:
            if a.resting or (due is not None and a in due):  # (due: advanced just now)
                continue
            wait = retry.get(a)
            if wait is not None:
                if wait > 1:
                    retry[a] = wait - 1
                else:
                    del retry[a]
            elif a.moving or (a.enabled and not a.in_pos):  # (else: no move to advance)
                if not a._comp_dependents:  # (an axis whose compensation reads it)
                    h = coast_cycles(a, MAX_COAST)
                    if h >= MIN_DEFER:
                        end = phase - 1 + h
                        lagging[a] = [phase - 1, end]
                        self._due.setdefault(end, []).append(a)
                        changed = True
                        continue
                retry[a] = RETRY
            a.step()
        if changed:
            self._freed(axes)

    def pass_idle(self, axes: list, n: int) -> int:
        """Pass up to `n` motion phases of `axes` in which `step` would do nothing, by
        counting them (`MotionKernel.step_alone`): every axis not deferred rests and no
        deferred axis's horizon ends before the last of them. Returns the phases passed
        (0: the next phase has work). Nothing changes in them, so what the run asks of
        the kernel between them (`busy`, `at_rest`) answers as after the last phase."""
        if axes is not self._order:
            return 0
        for a in self._free:
            if not a.resting:
                return 0
        due = self._due
        k = n if not due else min(n, min(due) - self.phase - 1)
        if k <= 0:
            return 0
        self.phase += k
        self.passed += k
        return k

    def one_busy(self) -> bool:
        """True if a deferred axis keeps the run busy (`MotionKernel.busy`) whatever its
        deferred cycles hold: its status flags say it moves or settles (they are as
        stepping leaves them) and it runs a positioning move with nothing buffered, or
        it moves and can never be jogging at a reached velocity (`Axis.cruising`,
        `_never_cruises`). The run loop asks every cycle once its tasks ended: it need
        not catch the axes up to know. (The answer for a jog that may cruise needs the
        axis up to date: `busy` then catches up.)"""
        for a in self.lagging:
            if a.moving:
                if _never_cruises(a):
                    return True
            elif not (a.enabled and not a.in_pos):
                continue
            if a.pg.mode != VELOCITY and not a._command_queue:
                return True
        return False

    def catch_up(self, a) -> None:
        """Bring deferred axis `a` up to date (the end of the last motion phase)."""
        n = self.phase - self.lagging.pop(a)[0]
        self.batches += 1
        if self._order is not None:
            self._freed(self._order)
        if n >= max(MIN_COAST, a.drive.mechanics.delay_cycles + 3):
            coast(a, n)
        else:  # too few cycles for the closed form's formulas: step them
            for _ in range(n):
                a.step()

    def catch_up_all(self) -> None:
        """Bring every deferred axis up to date."""
        lagging = self.lagging
        while lagging:
            self.catch_up(next(iter(lagging)))
        self._due.clear()
        self._retry.clear()


def _never_cruises(a) -> bool:
    """Whether moving axis `a` can never be cruising (`Axis.cruising`) before it is
    commanded again, from what its deferred cycles do not change: a jog with its software
    limits on ends on a limit (not a rollover axis), and a jog toward a hardware limit
    switch that is checked ends on it (a cruise runs in its commanded velocity's
    direction)."""
    if not (a._ignore_swl or a._rollover):
        return True
    pg = a.pg
    if a.ignore_hwl or pg.mode != VELOCITY or pg._v_cmd == 0.0:
        return False
    sensors = a.drive.sensors
    return (sensors.positive_limit if pg._v_cmd > 0.0 else sensors.negative_limit) is not None
