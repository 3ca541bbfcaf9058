"""One timeline: a session run by its own thread, which the debugger pauses and resumes.

The simulation runs in a thread of its own (`sim` below) so that it can stop inside a
statement: the tracer's line hook blocks that thread until the debugger says how to go
on, with the task's frames alive for inspection. At cycle boundaries it runs cycle by
cycle when a statement or a change must be seen (breakpoints, a step, data
breakpoints), else with time skipping (`Controller.run`, the same results).

A position inside a cycle counts the line events of that cycle, and those depend on
where each waiting task sits: a task that starts a `Till` yields at the wait's first
yield, and only a cycle that resumes it moves it on to the polling one (a resume from
there is a line event, the first is not). A jump over idle cycles resumes nobody, so
the cycle after a jump may count fewer events than the same cycle stepped. Every skip
therefore stops one cycle short of where statements must be seen (or a stop is made),
and that cycle is stepped: every polling task is resumed in it, and the counts of the
cycles after it are those of a run stepped from the start ("warm" below).

A timeline is driven by `Goal`s (continue, step, run to a position) and answers each
with a `Stop`. Going back in time abandons the timeline (its thread unwinds with
`Abandon`, a `SystemExit` that the task kernel lets through) and starts a fresh one on
the same inputs (engine.py).
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass

from motionvm.debug.positions import Input, Position, Stop
from motionvm.debug.tracer import LineTracer, is_user_file
from motionvm.runtime.waits import never_ends
from motionvm.sim.controller import FOREVER, STOPPED, until_cycle


class Abandon(SystemExit):
    """Unwinds an abandoned timeline's thread (through the kernel, which re-raises
    SystemExit)."""


@dataclass
class Goal:
    """How far to run before the next stop."""

    kind: str
    """"continue" (breakpoints, faults, data breakpoints, the end), "step" (the next
    statement of `thread` at `depth` or less: over, in, out), "to" (a position; no
    breakpoint stops it), "abandon"."""
    target: Position | None = None
    thread: tuple | None = None
    depth: int | None = None
    """step: stop at a statement of `thread` whose depth of user frames is <= this
    (None: any depth: step in)."""
    reason: str = "step"
    """The stop's reason when the goal is reached."""
    skip_origin: object | None = None
    """step: the frame and line the step started from (not a stop)."""
    forever: bool = False
    """continue to `target`: stop with "waits forever" before it if nothing left can
    change the run (a target that is only a pause of a longer run: a paced run's step)."""


class Timeline:
    """A session, its simulation thread, and the rules of where it stops."""

    def __init__(self, session, engine, inputs: list[Input]) -> None:
        self.session = session
        self.engine = engine
        self.controller = session.controller
        self.inputs = sorted(inputs, key=lambda i: i.position)
        """Recorded inputs still to apply, by position."""
        self.tracer = LineTracer(self._on_line, self.controller.clock)
        self.goal: Goal | None = None
        self.stop: Stop | None = None
        self.paused_frame = None
        """The frame paused inside a statement (None: paused at a cycle boundary)."""
        self.finished = False
        self._cond = threading.Condition()
        self._pause_asked = False
        self._boundary_stop: Stop | None = None
        self._thread = threading.Thread(target=self._main, name="motionvm-debug", daemon=True)
        self._error: BaseException | None = None
        self._asked_end = self._end_cycle()

    # ---------------------------------------------------------------- control (caller)

    def start(self, goal: Goal) -> Stop:
        with self._cond:
            self.goal, self.stop = goal, None
        self._thread.start()
        return self._wait()

    def go(self, goal: Goal) -> Stop:
        """Resume toward `goal`; the next stop."""
        with self._cond:
            self.goal, self.stop = goal, None
            self._cond.notify_all()
        return self._wait()

    def ask_pause(self) -> None:
        """From another thread: stop at the next cycle boundary."""
        self._pause_asked = True
        self.controller.stop_requested = True

    def abandon(self) -> None:
        if not self._thread.is_alive():
            return
        with self._cond:
            self.goal, self.stop = Goal("abandon"), None
            self._cond.notify_all()
        self.controller.stop_requested = True
        self._thread.join()

    def _wait(self) -> Stop:
        with self._cond:
            while self.stop is None:
                self._cond.wait()
            if self._error is not None:
                error, self._error = self._error, None
                raise error
            return self.stop

    # ---------------------------------------------------------------- the sim thread

    def position(self) -> Position:
        if self.paused_frame is not None:
            return Position(self.controller.cycle, self.tracer.count)
        return Position(self.controller.cycle, 0)

    def _publish(self, stop: Stop) -> Goal:
        """Pause with `stop`; the next goal."""
        with self._cond:
            self.stop = stop
            self.goal = None
            self._cond.notify_all()
            while self.goal is None:
                self._cond.wait()
            goal = self.goal
        if goal.kind == "abandon":
            raise Abandon()
        return goal

    def _main(self) -> None:
        try:
            self.session.boot()
            self._run()
        except Abandon:
            pass
        except BaseException as exc:  # noqa: BLE001 — handed to the caller
            with self._cond:
                self._error = exc
                self.stop = Stop(
                    "exited", Position(self.controller.cycle), self.controller.sim_time
                )
                self._cond.notify_all()
        finally:
            self.tracer.disable()
            sys.settrace(None)

    def _stop_at_boundary(self, reason: str, text: str = "") -> Stop:
        ctl = self.controller
        return Stop(reason, Position(ctl.cycle, 0), ctl.sim_time, None, text)

    def _end_cycle(self) -> int | None:
        _asked, end = self.session.end_time(self.engine.until)
        return None if end is None else until_cycle(end, self.controller.cycle_time)

    def _run(self) -> None:
        """The simulation thread's loop, one cycle boundary at a time."""
        ctl = self.controller
        if self.goal is not None and self.goal.kind == "entry":
            self.goal = self._publish(self._stop_at_boundary("entry"))
        while True:
            goal = self.goal  # (a pause inside a statement may have set a new one)
            cycle = ctl.cycle
            self._apply_inputs(Position(cycle, 0))
            stop = None
            if (
                goal.kind in ("to", "continue")
                and goal.target is not None
                and goal.target.count == 0
            ):
                if cycle >= goal.target.cycle:
                    stop = self._stop_at_boundary(goal.reason)
            if stop is None and self._boundary_stop is not None:
                stop, self._boundary_stop = self._boundary_stop, None
            if stop is None and self._pause_asked:
                self._pause_asked = False
                ctl.stop_requested = False
                stop = self._stop_at_boundary("pause")
            if stop is not None:
                self.goal = self._publish(stop)
                continue
            end = self._asked_end
            if (end is not None and cycle >= end) or not ctl.busy():
                self._finish()
                return
            if self._needs_cycles(goal):
                if self._waits_forever(goal):
                    continue
                self._one_cycle()
            else:
                self._free_run(goal)

    def _traced(self, goal: Goal) -> bool:
        """Whether the statements of this cycle must be seen."""
        if goal.kind == "step" or (goal.kind == "continue" and self.engine.breakpoints_set()):
            return True
        cycle = self.controller.cycle
        if self.inputs and self.inputs[0].position.count > 0:
            if self.inputs[0].position.cycle <= cycle:
                return True
        target = goal.target
        return target is not None and target.count > 0 and target.cycle <= cycle

    def _needs_cycles(self, goal: Goal) -> bool:
        """Whether the next cycle must run on its own: a change must be seen at its end,
        or its statements (a position within a cycle is that of the cycle stepped: a
        jump over idle cycles changes which cycles a polling task runs in)."""
        if self.engine.watching():
            return True
        return self._traced(goal)

    def _waits_forever(self, goal: Goal) -> bool:
        """A run that steps its cycles (breakpoints set, a data breakpoint) and may stop
        for "waits forever" (`goal.forever`): True, with that stop noted, when nothing
        left can change anything (the test a free run's jump makes, at the same
        boundary), so it does not step on for ever."""
        if not goal.forever or self.inputs or self._asked_end is not None:
            return False
        ctl = self.controller
        if not ctl.never_changes():
            return False
        text = "\n".join(never_ends(ctl.still_running(), ctl.sim_time))
        self._boundary_stop = self._stop_at_boundary("waits forever", text)
        return True

    def _one_cycle(self) -> None:
        ctl = self.controller
        before = self.engine.watch_values() if self.engine.watching() else None
        self._trace(self._traced(self.goal))
        ctl.step()
        ctl.stop_requested = False
        if before is not None and self._boundary_stop is None:
            change = self.engine.watch_changed(before)
            if change:
                self._boundary_stop = self._stop_at_boundary("data breakpoint", change)
        if self._boundary_stop is None and self.engine.axis_errors_wanted():
            text = self.engine.new_axis_error(self.controller)
            if text:
                self._boundary_stop = self._stop_at_boundary("exception", text)

    def _trace(self, on: bool) -> None:
        if on:
            self.tracer.enable()
        else:
            self.tracer.disable()

    def _free_run(self, goal: Goal) -> None:
        """Run with time skipping up to the cycle before the next place something must
        be seen, then step that cycle (warm: see the module's docstring)."""
        ctl = self.controller
        limits = [self._asked_end]
        if goal.kind in ("to", "continue") and goal.target is not None:
            limits.append(goal.target.cycle)
        if self.inputs:
            limits.append(self.inputs[0].position.cycle)
        limits = [c for c in limits if c is not None]
        if limits and min(limits) - 1 <= ctl.cycle:
            self._one_cycle()
            return
        until = (min(limits) - 1) * ctl.cycle_time if limits else None
        self._trace(False)
        # a goal's target that only paces a longer run: a run that can never end ends
        # before it (unless an input still to come, or the run's end, could change that)
        deadline = goal.forever and not self.inputs and self._asked_end is None
        result = ctl.run(until, deadline=deadline)
        if result == STOPPED and not self._pause_asked:
            ctl.stop_requested = False  # a fault asked for a stop at this boundary
        elif result == STOPPED and ctl.busy():
            # a pause lands one cycle later, on a warm boundary (it is asked at any time)
            self._one_cycle()
        elif result == FOREVER and self._boundary_stop is None:  # stop, rather than spin
            text = "\n".join(never_ends(ctl.still_running(), ctl.sim_time))
            self._boundary_stop = self._stop_at_boundary("waits forever", text)

    def _finish(self) -> None:
        self.finished = True
        self.session.finish()
        ctl = self.controller
        while True:  # nothing runs any more: every later goal stops here again
            self._publish(Stop("exited", Position(ctl.cycle), ctl.sim_time))

    # ---------------------------------------------------------------- inside a cycle

    def fault(self, text: str) -> None:
        """A task faulted (from the report callback, inside the cycle)."""
        if self._boundary_stop is None and self.engine.faults_wanted():
            ctl = self.controller
            self._boundary_stop = Stop(
                "exception", Position(ctl.cycle + 1, 0), ctl.sim_time + ctl.cycle_time, None, text
            )
            ctl.stop_requested = True

    def _apply_inputs(self, here: Position) -> None:
        while self.inputs and self.inputs[0].position <= here:
            self.engine.apply_input(self, self.inputs.pop(0))

    def _on_line(self, frame, count: int) -> None:
        ctl = self.controller
        here = Position(ctl.cycle, count)
        if self.inputs and self.inputs[0].position.cycle == ctl.cycle:
            self.paused_frame = frame
            try:
                self._apply_inputs(here)
            finally:
                self.paused_frame = None
        goal = self.goal
        stop: Stop | None = None
        if goal.kind == "to" and goal.target is not None and goal.target.count > 0:
            if here >= goal.target:
                stop = self._here(goal.reason, frame)
        elif goal.kind == "step" and self._step_ends(goal, frame):
            stop = self._here("step", frame)
        if stop is None and goal.kind in ("continue", "step"):
            hit = self.engine.breakpoint_hits(self, frame)
            if hit:
                stop = self._here("breakpoint", frame, hit)
        if stop is None:
            return
        self.paused_frame = frame
        try:
            nxt = self._publish(stop)
        finally:
            self.paused_frame = None
        if nxt.kind == "step" and nxt.skip_origin is None:
            nxt.skip_origin = (frame, frame.f_lineno)
        self.goal = nxt
        ctl.stop_requested = True  # the run's plan changes: made anew at the next boundary

    def _here(self, reason: str, frame, hits: tuple[int, ...] = ()) -> Stop:
        ctl = self.controller
        key = self.engine.thread_key(frame)
        return Stop(reason, Position(ctl.cycle, self.tracer.count), ctl.sim_time, key, "", hits)

    def _step_ends(self, goal: Goal, frame) -> bool:
        origin = goal.skip_origin
        if origin is not None and origin[0] is frame and origin[1] == frame.f_lineno:
            return False
        if goal.thread is not None and self.engine.thread_key(frame) != goal.thread:
            return False
        return goal.depth is None or user_depth(frame) <= goal.depth


def user_depth(frame) -> int:
    """How many frames of the user's code this one is deep (1: the task's own)."""
    depth = 0
    while frame is not None and is_user_file(frame.f_code.co_filename):
        depth += 1
        frame = frame.f_back
    return depth


def user_root(frame):
    """The outermost frame of the user's code under `frame` (the task's own frame)."""
    root = frame
    while frame is not None and is_user_file(frame.f_code.co_filename):
        root = frame
        frame = frame.f_back
    return root


Callback = Callable[[str], None]
