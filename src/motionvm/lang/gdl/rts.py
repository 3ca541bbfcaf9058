"""The GDL run-time support (RTS): object state, activators, the ready queue, output.

Model (the GDL description, 3.3):
- Every state variable of every object element holds a value; values start from the
  declaration (INITIAL$VALUE, VALUE) or the type default. Initial values are not events.
- A change of a state variable that is an activator *triggers*: every procedure whose
  expanded list holds it is appended to one FIFO ready queue, once per change, in link
  order (files as given, modules and procedures in textual order). This is the fixed,
  documented order for procedures sharing an activator; programs needing an order
  chain through a DIGITAL$FLAG [T]. Writing the value a variable already has is no
  change.
- Procedures (lowered to Python by `lower.py`) run one at a time to completion, in
  zero simulated time; a change during a run (its own activator, an injected input)
  queues one more run behind it [T].
- Forcing (`f` access, the debugger): a forced value hides every write until released;
  forcing and releasing are changes like any other.
- Time is the controller's clock (`runtime.clock.Clock`): an integer cycle count and the
  cycle time. The RTS never advances it; `client.GdlApplication` runs it once per cycle.

Output, one line each, in order: `t=S input REF = V` (scenario), `t=S run PROC`,
`t=S set REF = V` (a procedure changed it), `t=S update REF = V` (the RTS changed a
digital or set variable: a motor stopping, a home switch), `t=S force REF = V`,
`t=S release REF = V` (the value underneath). Run-time errors are reported as
`FILE:LINE:COL: runtime error in procedure P at t=S s: MSG`. Both go to callbacks
taking one line.
"""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Callable, Mapping
from fractions import Fraction
from types import TracebackType
from typing import TYPE_CHECKING

from motionvm.lang.gdl.api import ProcedureApi
from motionvm.lang.gdl.app import App, ObjectInfo, ProcInfo
from motionvm.lang.gdl.device_factory import create_device
from motionvm.lang.gdl.devices import Device, GdlFault
from motionvm.lang.gdl.objects import format_value
from motionvm.runtime.clock import Clock, stamp_prefix
from motionvm.runtime.fault_position import Fault, user_frames

if TYPE_CHECKING:
    from motionvm.motion.axis import Axis

MAX_RUNS_PER_CYCLE = 10_000
"""Procedure runs allowed in one cycle before the ready queue is declared runaway."""
MAX_DECIMALS = 9
"""Most decimals a time stamp shows (a cycle time that is no decimal fraction is rounded)."""


def time_formatter(cycle_time: float) -> Callable[[int], str]:
    """`cycle -> "S.mmm"`: simulated time from the integer cycle, without float drift.

    The cycle time is taken as the nearest fraction with a denominator up to 10**9
    (0.001 is exactly 1/1000, 0.3 / 1000 is 3/10000); a stamp shows at least 3
    decimals, more when the cycle time needs them (0.0005 s: 4).
    """
    step = Fraction(cycle_time).limit_denominator(10**MAX_DECIMALS)
    decimals = next(
        (d for d in range(3, MAX_DECIMALS + 1) if (step * 10**d).denominator == 1), MAX_DECIMALS
    )
    unit = step * 10**decimals
    scale = 10**decimals

    def fmt(cycle: int) -> str:
        n = round(cycle * unit)
        return f"{n // scale}.{n % scale:0{decimals}d}"

    return fmt


def format_time(cycle: int, cycle_time: float = 0.001) -> str:
    """Simulated time of `cycle` as seconds (see `time_formatter`)."""
    return time_formatter(cycle_time)(cycle)


def _user_place(tb: TracebackType | None, file: str) -> tuple[int, int] | None:
    """(line, column) of the deepest frame of the user's generated code in a traceback."""
    frames = user_frames(tb, file.__eq__)
    return (frames[-1].line, frames[-1].col) if frames else None


class Rts:
    """State and scheduling of one application run."""

    def __init__(
        self,
        app: App,
        clock: Clock,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        *,
        axes: Mapping[str, Axis] | None = None,
        shuffle_seed: int | None = None,
    ) -> None:
        """`clock`: the controller's; `emit`/`report`: output and error lines (no newline).

        `axes`: the machine axis of each motor object, by object key (`motors.assign_axes`).
        `shuffle_seed`: order procedures sharing an activator by a seeded permutation of
        the link order instead (a test that a program does not depend on the order).
        """
        self.app = app
        self.clock = clock
        self._emit = emit
        self._report = report
        self._stamp = time_formatter(clock.cycle_time)
        self.stamped = False
        """Lines carry the `--stamp` prefix of every language (runtime/clock.py)."""
        self.order = list(app.procedures)
        if shuffle_seed is not None:
            random.Random(shuffle_seed).shuffle(self.order)
        self.values: dict[tuple[str, str], list[object]] = {}
        self.forced: dict[tuple[str, str, int], object] = {}
        self.ready: deque[ProcInfo] = deque()
        self.current: ProcInfo | None = None
        self.runs_this_cycle = 0
        self.error_count = 0
        self.apply_injection: Callable[[ProcInfo, int], None] | None = None
        """Set by the client while injections wait: applies those due at a boundary."""
        axes = axes or {}
        self.devices: dict[str, Device] = {
            k: create_device(o, axes.get(k)) for k, o in app.objects.items()
        }
        for obj in app.objects.values():
            for spec in obj.type.states:
                init = obj.params.get(spec.init_param) if spec.init_param else None
                value = init if init is not None else spec.default
                self.values[(obj.key, spec.keyword)] = [value] * len(obj.elements)
        for dev in self.devices.values():
            dev.start(self)

    # ------------------------------------------------------------ state access

    def device(self, obj: ObjectInfo) -> Device:
        return self.devices[obj.key]

    @staticmethod
    def _slot(obj: ObjectInfo, element: int) -> int:
        return element - 1 if obj.size is not None else 0

    def read(self, obj: ObjectInfo, keyword: str, element: int) -> object:
        """The value a procedure sees: the forced one if forced."""
        key = obj.key
        if self.forced:
            forced = self.forced.get((key, keyword, element), self)
            if forced is not self:
                return forced
        return self.values[(key, keyword)][self._slot(obj, element)]

    def init_value(self, obj: ObjectInfo, keyword: str, element: int, value: object) -> None:
        """Set a value before the run starts: not an event, nothing printed."""
        self.values[(obj.key, keyword)][self._slot(obj, element)] = value

    def origin(self) -> str:
        """'set' while a procedure runs, else 'update' (the RTS itself)."""
        return "set" if self.current is not None else "update"

    def write(
        self, obj: ObjectInfo, keyword: str, element: int, value: object, origin: str
    ) -> bool:
        """Store a value; on a visible change print it, run device hooks, trigger."""
        cell = self.values[(obj.key, keyword)]
        slot = self._slot(obj, element)
        old = cell[slot]
        cell[slot] = value
        if (obj.key, keyword, element) in self.forced or old == value:
            return False
        self._changed(obj, keyword, element, value, origin)
        return True

    def input(self, obj: ObjectInfo, keyword: str, element: int, value: object) -> None:
        """An external change (scenario event): always printed, triggers if it changed."""
        spec = obj.type.state(keyword)
        assert spec is not None
        self.emit(f"input {obj.ref(keyword, element)} = {format_value(spec.kind, value)}")
        cell = self.values[(obj.key, keyword)]
        slot = self._slot(obj, element)
        old, cell[slot] = cell[slot], value
        if (obj.key, keyword, element) not in self.forced and old != value:
            self._changed(obj, keyword, element, value, None)

    def _changed(
        self, obj: ObjectInfo, keyword: str, element: int, value: object, origin: str | None
    ) -> None:
        """A visible change: print it (origin None: already printed), hooks, triggers."""
        spec = obj.type.state(keyword)
        assert spec is not None
        if origin is not None and (origin != "update" or spec.kind != "int"):
            self.emit(f"{origin} {obj.ref(keyword, element)} = {format_value(spec.kind, value)}")
        self.device(obj).on_write(self, keyword, element, value)
        if spec.activator:
            self.trigger(obj, keyword, element)

    def force(self, obj: ObjectInfo, keyword: str, element: int, value: object) -> None:
        """Debugger force of an `f` variable: the value wins over every write until released.

        Raises ValueError for a variable without `f` access.
        """
        spec = obj.type.state(keyword)
        assert spec is not None
        if not spec.forceable:
            raise ValueError(
                f"{keyword} of {obj.type.name} cannot be forced (access {spec.access})"
            )
        old = self.read(obj, keyword, element)
        self.forced[(obj.key, keyword, element)] = value
        self.emit(f"force {obj.ref(keyword, element)} = {format_value(spec.kind, value)}")
        if old != value:
            self.device(obj).on_write(self, keyword, element, value)
            if spec.activator:
                self.trigger(obj, keyword, element)

    def release(self, obj: ObjectInfo, keyword: str, element: int) -> None:
        """End a force: the variable shows its underlying value again."""
        key = (obj.key, keyword, element)
        if key not in self.forced:
            return
        old = self.forced.pop(key)
        value = self.read(obj, keyword, element)
        spec = obj.type.state(keyword)
        assert spec is not None
        self.emit(f"release {obj.ref(keyword, element)} = {format_value(spec.kind, value)}")
        if value != old:
            self._changed(obj, keyword, element, value, None)

    # ------------------------------------------------------------ activators and runs

    def trigger(self, obj: ObjectInfo, keyword: str, element: int) -> None:
        """Queue every procedure whose list holds this activator, in link order."""
        for proc in self.order:
            if any(t.matches(obj.key, keyword, element) for t in proc.triggers):
                self.ready.append(proc)

    def drain(self) -> None:
        """Run the ready queue until it is empty."""
        while self.ready:
            proc = self.ready.popleft()
            self.runs_this_cycle += 1
            if self.runs_this_cycle > MAX_RUNS_PER_CYCLE:
                self.ready.clear()
                self.report(
                    proc.node.pos.file,
                    (proc.node.pos.line, proc.node.pos.col),
                    proc.name,
                    f"more than {MAX_RUNS_PER_CYCLE} procedure runs in one cycle: procedures "
                    "keep triggering each other (ready queue cleared)",
                )
                return
            self._run(proc)

    def _run(self, proc: ProcInfo) -> None:
        self.emit(f"run {proc.name}")
        self.current = proc
        try:
            self.app.functions[proc.name.lower()](ProcedureApi(self, proc))
        except GdlFault as fault:
            place = _user_place(fault.__traceback__, proc.file)
            if place is None:
                place = (proc.node.pos.line, proc.node.pos.col)
            self.report(proc.file, place, proc.name, str(fault))
        finally:
            self.current = None

    def before_instruction(self, proc: ProcInfo, line: int) -> None:
        """Instruction boundary of a running procedure: apply injected scenario events."""
        if self.apply_injection is not None:
            self.apply_injection(proc, line)

    # ------------------------------------------------------------ the cycle

    def update_devices(self) -> None:
        """Bring every device's state variables up to date with the machine, in
        declaration order (after the controller's motion step), then run the queue."""
        for dev in self.devices.values():
            dev.update(self)
        self.drain()

    @property
    def moving(self) -> bool:
        """Some device still changes: the clock must not jump over the next cycle."""
        return any(d.busy for d in self.devices.values())

    @property
    def transient(self) -> bool:
        """Some device will still change on its own (a motor jogging at a constant
        commanded speed does not count)."""
        return any(d.transient for d in self.devices.values())

    # ------------------------------------------------------------ output

    def stamp(self, cycle: int | None = None) -> str:
        """`S.mmm`: the simulated time of `cycle` (default: now)."""
        return self._stamp(self.clock.cycle if cycle is None else cycle)

    def emit(self, text: str) -> None:
        """One trace line: `t=S.mmm TEXT`; with `stamped`, the `--stamp` prefix of every
        language instead, naming the procedure that runs (`[t=...][gdl PROC] `) or none
        (`[t=...][gdl] `: an input, a scenario's force)."""
        if self.stamped:
            proc = self.current
            source = "gdl" if proc is None else f"gdl {proc.name}"
            self._emit(stamp_prefix(self.clock.cycle * self.clock.cycle_time, source) + text)
        else:
            self._emit(f"t={self.stamp()} {text}")

    def report(self, file: str, place: tuple[int, int], proc: str, message: str) -> None:
        """A procedure's run-time error at (line, column) of `file`, now."""
        self.error_count += 1
        line, col = place
        self._report(
            Fault(
                f"{file}:{line}:{col}: runtime error in procedure {proc} at t={self.stamp()} s: "
                f"{message}",
                file=file,
                line=line,
                col=col,
                time=self.clock.cycle * self.clock.cycle_time,
                message=message,
                language="GDL",
                procedure=proc,
            )  # fmt: skip
        )
