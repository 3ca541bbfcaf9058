"""A GDL application as a client of the controller's cycle: scenario, procedures, devices.

Assembly of a run (the controller owns the clock and the axes):

    controller = Controller(cycle_time, machine)
    app = compile_app(paths, sink=sink)
    scenario = load_scenario(path, app)
    client = GdlApplication(controller, app, scenario, emit=print, report=print_err)
    controller.add_client(client)
    controller.run(client.run_until(until))
    client.finish()
    exit_code = 1 if client.error_count else 0

One controller cycle k, as the application sees it (`end_cycle`, after the motion step):
every device brings its state variables up to date with the machine (motor positions,
arrivals, home switches, encoders), in declaration order, then the ready queue runs;
then the scenario events due at k are applied in file order, each followed by running
the ready queue empty. In the first cycle the `--force` values are applied instead of
the device update. Every line is stamped `t=S` from the cycle k and the cycle time.
A procedure's motion command thus moves the axis from the next cycle on.

End and jump rules: the client is busy while scenario events remain or a device will
still change on its own (a motor moving, stopping or ramping to a speed; an encoder not
yet up to date). Its next event is the current cycle while any motor is commanded (the
controller then steps every cycle), else the cycle of the next scenario event. So a run
without an end time ends once the scenario has no events left, the ready queue is empty
and every motor stands still or runs at a constant commanded speed.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from motionvm.lang.gdl.app import App, ProcInfo
from motionvm.lang.gdl.motors import assign_axes
from motionvm.lang.gdl.rts import Rts, format_time
from motionvm.lang.gdl.scenario import Event, Scenario, parse_target, parse_value
from motionvm.lang.gdl.scope import GdlScopeSource
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.waits import Waiting
from motionvm.sim.scenario import ScenarioError

if TYPE_CHECKING:
    from motionvm.runtime.scope import ChannelSource
    from motionvm.sim.controller import Controller
    from motionvm.sim.machine import GdlMotorSpec


NO_SCENARIO = Scenario((), (), None)
"""The scenario of a run without a scenario file."""


def event_cycle(at: float, cycle_time: float) -> int:
    """The cycle of a scenario time `at` [s]: rounded up to a whole cycle."""
    return math.ceil(round(at / cycle_time, 6))


def parse_forces(app: App, forces: Sequence[str]) -> list[Event]:
    """`--force "VALUE OF fan = 300"` arguments as force events at t=0 (ScenarioError)."""
    out: list[Event] = []
    for i, text in enumerate(forces):
        ref, sep, raw = text.partition("=")
        try:
            if not sep:
                raise ValueError("write --force 'KEYWORD OF object = value'")
            target = parse_target(app, ref.strip())
            if not target.spec.forceable:
                raise ValueError(
                    f"{target.spec.keyword} of {target.obj.type.name} cannot be "
                    f"forced (access {target.spec.access})"
                )
            value = parse_value(target, raw.strip())
        except ValueError as exc:
            raise ScenarioError(f"--force '{text}': {exc}") from None
        out.append(Event(-1 - i, 0.0, "force", target, value, None, None))
    return out


def apply_event(rts: Rts, ev: Event) -> None:
    """Apply one scenario action to every element it names."""
    t = ev.target
    for e in t.elements:
        if ev.action == "set":
            rts.input(t.obj, t.spec.keyword, e, ev.value)
        elif ev.action == "force":
            rts.force(t.obj, t.spec.keyword, e, ev.value)
        else:
            rts.release(t.obj, t.spec.keyword, e)


class GdlApplication(PassiveClient):
    """One GDL application running on a controller: a cycle client (runtime/clients.py).

    `controller`: whose clock the run uses and whose axes the motors are (motors.py:
    declaration order onto axes 0, 1, ...). `scenario`: initial values (set now, not
    events), timed events and injections. `emit` receives every output line, `report`
    every run-time error and warning line (one line each, no newline). `forces`:
    `--force 'REF = VALUE'` texts, applied in the first cycle. `shuffle_seed`: permute
    the order of procedures sharing an activator (`Rts`). `motor_axes`: the motors the
    machine file puts on named axes (motors.py).

    Raises ScenarioError for a bad `--force` text and `motors.GdlMachineError` when the
    machine has too few axes (both exit code 3). Module docstring: the cycle and the
    end and jump rules.
    """

    def __init__(
        self,
        controller: Controller,
        app: App,
        scenario: Scenario = NO_SCENARIO,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        forces: Sequence[str] = (),
        shuffle_seed: int | None = None,
        motor_axes: Sequence[GdlMotorSpec] = (),
        stamp: bool = False,
    ) -> None:
        self.controller = controller
        self.app = app
        self._report = report
        self._forces = parse_forces(app, forces)
        self.axes = assign_axes(app, controller.axes, motor_axes)
        """The machine axis of each motor object, by case-folded object name."""
        self.rts = Rts(
            app, controller.clock, emit, report, axes=self.axes, shuffle_seed=shuffle_seed
        )
        self.rts.stamped = stamp
        self._started = False
        self.use_scenario(scenario)

    def use_scenario(self, scenario: Scenario) -> None:
        """Take `scenario`: its initial values now (not events), its events at their
        cycles. Before the first cycle."""
        self.scenario = scenario
        for target, value in scenario.initial:
            for e in target.elements:
                self.rts.init_value(target.obj, target.spec.keyword, e, value)
        ct = self.controller.cycle_time
        timed = [(event_cycle(ev.at, ct), ev) for ev in scenario.events if ev.during is None]
        timed.sort(key=lambda ce: (ce[0], ce[1].number))
        self._timed: deque[tuple[int, Event]] = deque(timed)
        self._injections = [
            (event_cycle(ev.at, ct), ev) for ev in scenario.events if ev.during is not None
        ]
        self.rts.apply_injection = self._inject if self._injections else None

    @property
    def error_count(self) -> int:
        """Run-time errors so far (exit code 1 if any)."""
        return self.rts.error_count

    def run_until(self, until: float | None) -> float | None:
        """The `until` [s] to give `Controller.run`: the caller's end time, else the
        scenario's, inclusive (the events due at that time still apply), or None."""
        end = until if until is not None else self.scenario.until
        if end is None:
            return None
        ct = self.controller.cycle_time
        return (max(0, round(end / ct)) + 1) * ct

    # ------------------------------------------------------------ the cycle client

    def begin_cycle(self) -> None:
        """Nothing: the application reacts to the state the motion step leaves."""

    def end_cycle(self) -> None:
        rts = self.rts
        rts.runs_this_cycle = 0
        if not self._started:
            self._started = True
            for ev in self._forces:
                apply_event(rts, ev)
                rts.drain()
        else:
            rts.update_devices()
        cycle = self.controller.cycle
        timed = self._timed
        while timed and timed[0][0] <= cycle:
            apply_event(rts, timed.popleft()[1])
            rts.drain()

    def busy(self) -> bool:
        return not self._started or bool(self._timed) or self.rts.transient

    def still_running(self) -> list[Waiting]:
        """The scenario events not applied yet, and the devices still changing."""
        out: list[Waiting] = []
        if self._timed:
            cycle, ev = self._timed[0]
            out.append(
                Waiting(
                    "the GDL scenario",
                    why=f"{len(self._timed)} event{'s' if len(self._timed) > 1 else ''} not "
                    "applied yet, the next at "
                    f"t={format_time(cycle, self.controller.cycle_time)}",
                )
            )
        for key, dev in self.rts.devices.items():
            if dev.transient:
                obj = self.app.objects[key]
                out.append(Waiting(f"{obj.type.name} {obj.name}", obj.pos.file, obj.pos.line,
                                   obj.pos.col, why="still changing"))  # fmt: skip
        return out

    def next_event(self) -> int | None:
        cycle = self.controller.cycle
        if not self._started or self.rts.moving:
            return cycle
        return max(cycle, self._timed[0][0]) if self._timed else None

    def finish(self) -> None:
        """After the run: warn of scenario injections that never applied."""
        for _, ev in self._injections:
            self._report(
                f"{ev.where}: warning: scenario event {ev.number} (during {ev.during}, line "
                f"{ev.line}) was never applied"
            )

    # ------------------------------------------------------------ injections, scope

    def _inject(self, proc: ProcInfo, line: int) -> None:
        """Apply the injections due now just before `line` of the running `proc`."""
        cycle = self.controller.cycle
        for item in list(self._injections):
            due, ev = item
            if due <= cycle and ev.during == proc.name and ev.line == line:
                self._injections.remove(item)
                apply_event(self.rts, ev)
        if not self._injections:
            self.rts.apply_injection = None

    def scope_sources(self) -> list[ChannelSource]:
        """Scope channels `OBJECT.STATE` of the application's state variables (scope.py)."""
        return [GdlScopeSource(self.rts)]
