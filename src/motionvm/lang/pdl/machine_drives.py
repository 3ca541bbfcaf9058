"""PDL programs on the drives of a machine: compile them, run them on the controller's clock.

A machine file's `[[axis]]` table with `pdl = "prog.pdl"` puts that program on the
axis's drive (sim/machine.py reads the keys); `compile_drives` compiles every such
program (diagnostics in the one format; any error: nothing runs) and checks the
`pdl_start` labels. A standalone `motionvm run prog.pdl` is the default machine with
one program on the drive of axis 0 (`compile_program`). `PdlDrives` is the cycle
client (runtime/clients.py) that runs them. A run is assembled as

    controller = Controller(machine.cycle_time, machine)
    drives = compile_drives(machine, report)        # or compile_program(path, starts, report)
    client = PdlDrives(controller, drives, machine, emit=..., report=..., stamp=...)
    controller.add_client(client)
    client.boot()
    controller.run(until)

Clock. At `begin_cycle` of controller cycle k, before the tasks, every drive, in axis
order, runs its phases up to the start of that cycle, k * cycle_time: a cycle of
`cycle_time` [s] is `round(cycle_time * phase_rate)` phases (15 for 1 ms), and the
phases of [k - 1, k) ms run at the start of cycle k. So the HMPL tasks of cycle k see
the drives as they are at k * cycle_time, a scope sample stamped k shows the drives at
phase 15 k, and every line printed in a run comes out in time order: drive messages
stamped in [k - 1, k) ms, then the HMPL messages and GDL lines of cycle k. Inside a cycle
the drive skips the phases in which no task can run and its axis rests (drive_loop.py);
across cycles the controller decides: `next_event` is the current cycle while a drive
task is runnable or a drive's profile moves, else the cycle of the earliest wake-up of
a sleeping task (exact: nothing of the drive changes before it), None when every task
has ended. Stepped and jumped runs give identical results.

Motion. The program is the drive's firmware: its profile generator (drive_axis.PdlAxis,
in counts at the phase rate, configured from the axis table by `pdl_axis_config`) gives
the position demand of the machine axis's CiA 402 drive, which is under local control
(`Cia402Drive.follow_local_demand`): at the start of each cycle the client hands the
demand the phases left to the drive, and the drive's mechanics follow it at the drive's
step in the same cycle. So the controller's axis (`pos_fb`), the drive's objects
(`position_actual`, `position_demand`) and the scope's `axisN.pos_fb` show the
program's motion. Latency: the demand `driveN.ref_pos[0]` of a sample is the drive's
demand in that cycle and reaches the feedback after the mechanics' own delay
(`delay_cycles`, 1 on the default ideal drive): `axisN.pos_fb` of cycle k +
delay_cycles is `driveN.ref_pos[0]` of cycle k, in axis units. A machine run keeps going for those cycles after the drives'
last motion, so it ends with the feedback at the drives' final positions. The
controller's axis is marked `controlled_by = "PDL drive"`: HMPL motion and setting
commands to it are refused (lang/hmpl/lib/axis.py), its getters read the feedback.

Output. A message is one line through `emit`; with `stamp` it is prefixed
`[t=SECONDS][drive A task N] ` (A the axis id, t the message's phase, 6 decimals). A
task's fault is `FILE:LINE:COL: runtime error in drive A task N at t=SECONDS s: MESSAGE`
through `report`.
The scope channels `driveN.<name>` come from `scope_sources()` (drive_scope.py).

Standalone (`standalone=True`, the `motionvm run prog.pdl` of one drive): the drive
takes the manual's default parameters (`DriveConfig()`, or `config`), not the machine
axis's; messages are stamped `[t=SECONDS][task N] `, faults read
`runtime error in task N`; a start the drive refuses raises PdlStartError (a command-line
error) and a drive with no task gets a note; the scope channels also answer to bare names
(`x_ref_pos` = `drive0.x_ref_pos`); the run lasts at least one cycle and ends with the
cycle in which the drive is found idle, with no cycles added for the machine axis to
follow. Like every run, it ends at a cycle boundary (`--until` rounds up to one).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from motionvm.lang.pdl.drive_axis import AxisConfig as PdlAxisConfig
from motionvm.lang.pdl.drive_rt import Drive, DriveConfig, Message
from motionvm.lang.pdl.drive_scope import PdlDriveSource
from motionvm.lang.pdl.lower import PdlProgram
from motionvm.lang.pdl.program import compile_pdl
from motionvm.motion.axis_config import AxisConfig
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.clock import stamp_prefix
from motionvm.runtime.fault_position import Fault
from motionvm.runtime.waits import Waiting, suspended_at, why_waiting
from motionvm.sim.machine import MachineConfig, PdlDriveSpec
from motionvm.source.cache import CompileCache
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink, render_diagnostic

CONTROLLED_BY = "PDL drive"
"""`Axis.controlled_by` of an axis whose drive runs a PDL program."""


class PdlStartError(Exception):
    """A start label that cannot be started (exit 3); the message is the whole line to print:
    a machine file's `pdl_start` label the program lacks (`FILE:LINE:COL: error: ...`), or a
    standalone `--start` the program lacks or the drive refuses (`motionvm: error: --start ...`)."""


@dataclass
class CompiledDrive:
    """One compiled program and the drive it runs on."""

    spec: PdlDriveSpec
    program: PdlProgram


def compile_specs(
    specs: Sequence[tuple[PdlDriveSpec, str]],
    texts: Mapping[str, str] | None = None,
    cache: CompileCache | None = None,
) -> tuple[list[CompiledDrive] | None, list[Diagnostic]]:
    """Compile the program of each (drive, path): the drives (None after any compile
    error) and every diagnostic, by file and place. `texts`: programs' contents by path,
    instead of reading them; `cache`: the compile cache to read and fill, if any.
    PdlStartError for a start label a program lacks."""
    sink = DiagnosticSink()
    out: list[CompiledDrive] = []
    for spec, path in specs:
        program = compile_pdl(path, sink=sink, text=(texts or {}).get(path), cache=cache)
        if program is not None:
            out.append(CompiledDrive(spec, program))
    diagnostics = sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col))
    if sink.has_errors:
        return None, diagnostics
    _check_starts(out)
    return out, diagnostics


def _compile(
    specs: Sequence[tuple[PdlDriveSpec, str]], report, errors: list | None
) -> list[CompiledDrive] | None:
    out, diagnostics = compile_specs(specs)
    for d in diagnostics:
        report(render_diagnostic(d))
    if errors is not None:
        errors.extend(d for d in diagnostics if d.severity == "error")
    return out


def _check_starts(drives: list[CompiledDrive] | None) -> None:
    """PdlStartError for a start label a program lacks: a machine-file error naming the
    key (`pdl_start`), or a command-line error (`--start`) for a spec with no `where`."""
    for c in drives or ():
        for label in c.spec.starts:
            if label != "top" and label not in c.program.entries:
                if not c.spec.where:
                    raise PdlStartError(
                        f"motionvm: error: --start {label}: the program has no label '{label}'"
                    )
                raise PdlStartError(
                    f"{c.spec.where}: error: [[axis]] {c.spec.axis}: pdl_start: "
                    f"{c.spec.path.name} has no label '{label}'"
                )


def compile_drives(
    machine: MachineConfig, report: Callable[[str], None], errors: list | None = None
) -> list[CompiledDrive] | None:
    """Compile the machine's PDL programs; None (diagnostics reported, and the errors
    added to `errors`) on any compile error.

    Raises PdlStartError for a start label a program lacks.
    """
    return _compile([(spec, str(spec.path)) for spec in machine.pdl_drives], report, errors)


def compile_program(
    path: str, starts: Sequence[str], report: Callable[[str], None], errors: list | None = None
) -> list[CompiledDrive] | None:
    """Compile one standalone program for the drive of axis 0, host starts `starts` (in
    order; "top": the first statement); None (diagnostics reported) on a compile error.

    Raises PdlStartError for a start label the program lacks.
    """
    return _compile(standalone_spec(path, starts), report, errors)


def standalone_spec(path: str, starts: Sequence[str]) -> list[tuple[PdlDriveSpec, str]]:
    """The one program of a standalone run, on the drive of axis 0 (the path as given:
    faults name it so)."""
    return [(PdlDriveSpec(axis=0, path=Path(path), starts=tuple(starts)), path)]


def pdl_axis_config(axis: AxisConfig) -> PdlAxisConfig:
    """The drive's axis in counts, from the machine's axis table (mm or deg)."""
    cpu = axis.counts_per_unit
    home = None
    if axis.home_pos is not None:
        home = (axis.home_pos + axis.home_width / 2) * cpu
    return PdlAxisConfig(
        v_max=axis.max_vel * cpu,
        acc=axis.max_acc * cpu,
        dcc=axis.max_dec * cpu,
        position=axis.start_position * cpu,
        home_position=home,
        home_width=axis.home_width * cpu,
        left_limit=None if axis.hw_left is None else axis.hw_left * cpu,
    )


class _Slot:
    """One PDL drive on one machine axis."""

    __slots__ = ("axis", "axis_id", "demand", "done", "drive", "latency", "per_cycle")

    def __init__(self, axis_id: int, drive: Drive, axis, per_cycle: int):
        self.axis_id = axis_id
        self.drive = drive
        self.axis = axis
        """The controller's axis (`motion.axis.Axis`) whose CiA 402 drive the program moves."""
        self.per_cycle = per_cycle
        """Phases per controller cycle."""
        self.demand = drive.axis.position
        """The last demand handed to the CiA 402 drive [counts]."""
        self.latency = getattr(axis.drive.mechanics, "delay_cycles", 0)
        """Cycles from a demand handed over in a cycle to the feedback that shows it."""
        self.done = False
        """The phase loop found the drive idle (standalone: the run ends with that cycle)."""


class PdlDrives(PassiveClient):
    """The cycle client that runs PDL drives on the machine's axes (see the module docstring).

    `drives` are the compiled programs, on the axes their specs name; `machine` configures
    each drive's axis (standalone: `config` or the manual's `DriveConfig()`). `emit` takes
    each message line, `report` each fault and note; `faults` lists the fault reports.
    Create it before the controller's first cycle: drive phase p belongs to cycle p // 15.
    """

    def __init__(
        self,
        controller,
        drives: Sequence[CompiledDrive],
        machine: MachineConfig,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        stamp: bool = False,
        standalone: bool = False,
        config: DriveConfig | None = None,
    ) -> None:
        self.controller = controller
        self.stamp = stamp
        self.standalone = standalone
        self._emit = emit
        self._report = report
        self.faults: list[str] = []
        """Fault reports of the drives' tasks (and refused machine-file starts), in order."""
        self.drives: list[tuple[int, Drive]] = []
        """(axis id, drive), in axis order."""
        self._slots: list[_Slot] = []
        self._starts: dict[int, tuple[str, ...]] = {}
        self._where: dict[int, str] = {}  # `FILE:LINE:COL` of each drive's pdl_start key
        self._settle_until = -1  # the last cycle the machine axes still follow a demand
        self._started = False
        for c in sorted(drives, key=lambda c: c.spec.axis):
            axis_id = c.spec.axis
            if standalone:
                cfg = config or DriveConfig()
            else:
                cfg = DriveConfig(axis=pdl_axis_config(machine.axes[axis_id]))
            drive = Drive(
                c.program,
                cfg,
                on_message=self._message_sink(axis_id, cfg.phase_rate),
                on_fault=self._fault_sink(axis_id),
            )
            axis = controller.axes[axis_id]
            axis.controlled_by = CONTROLLED_BY
            axis.drive.follow_local_demand(drive.axis.position)
            per_cycle = round(controller.cycle_time * cfg.phase_rate)
            self._slots.append(_Slot(axis_id, drive, axis, per_cycle))
            self.drives.append((axis_id, drive))
            self._starts[axis_id] = c.spec.starts
            self._where[axis_id] = c.spec.where

    def _message_sink(self, axis_id: int, rate: int) -> Callable[[Message], None]:
        who = "" if self.standalone else f"drive {axis_id} "

        def show(m: Message) -> None:
            if self.stamp:
                self._emit(stamp_prefix(m.phase / rate, f"{who}task {m.task}") + m.text)
            else:
                self._emit(m.text)

        return show

    def _fault_sink(self, axis_id: int) -> Callable[[str], None]:
        def fault(text: str) -> None:
            if not self.standalone:
                named = text.replace(
                    ": runtime error in task ", f": runtime error in drive {axis_id} task ", 1
                )
                text = text.with_text(named, drive=axis_id) if isinstance(text, Fault) else named
            self.faults.append(text)
            self._report(text)

        return fault

    def boot(self) -> None:
        """Start the host labels (`pdl_start`, `--start`) of every drive, in order; the
        `#task/n` tasks started at the drive's reset already. A refused start is a fault
        (standalone: PdlStartError); a standalone drive with no task gets a note."""
        for axis_id, drive in self.drives:
            for label in self._starts.get(axis_id, ()):
                try:
                    if label == "top":
                        free = next((t.id for t in drive.tasks if t.gen is None), None)
                        if free is None:
                            raise ValueError("refused: all 4 tasks are busy")
                        drive.start_top(free)
                    else:
                        drive.start(label)
                except ValueError as exc:
                    if self.standalone:
                        raise PdlStartError(f"motionvm: error: --start {label}: {exc}") from None
                    where = self._where.get(axis_id)
                    if where:  # the machine file's pdl_start key
                        text = f"{where}: error: [[axis]] {axis_id}: pdl_start {label}: {exc}"
                    else:
                        text = f"motionvm: error: --start {label}: drive {axis_id}: {exc}"
                    self.faults.append(text)
                    self._report(text)
            if self.standalone and not drive.busy:
                self._report(
                    f"{drive.program.path}:1:1: note: no task runs: the program has no "
                    "'#task/n;' and no --start label was given"
                )

    def scope_sources(self) -> list[PdlDriveSource]:
        """The `driveN.<name>` channels (standalone: also the bare names of its drive)."""
        bare = self.drives[0][0] if self.standalone and self.drives else None
        return [PdlDriveSource(dict(self.drives), bare=bare)]

    # ---------------------------------------------------------------- the cycle client

    def end_cycle(self) -> None:
        """Nothing: the drives ran up to this cycle before its tasks."""

    def begin_cycle(self) -> None:
        """Run every drive, in axis order, up to the start of this cycle; hand its demand
        to the axis, whose motion step in this cycle takes it."""
        cycle = self.controller.cycle
        self._started = True
        for s in self._slots:
            drive = s.drive
            target = cycle * s.per_cycle
            if drive.phase < target and not s.done:
                s.done = drive.run_phases(target - drive.phase)
            p = drive.axis.position
            if p != s.demand:
                s.demand = p
                s.axis.drive.follow_local_demand(p)
                s.axis.wake()  # a resting axis would not step its drive
                self._settle_until = max(self._settle_until, cycle + s.latency)

    def _running(self, s: _Slot) -> bool:
        if self.standalone:  # the drive's own loop: until a cycle finds it idle
            return not self._started or not s.done
        return s.drive.busy

    def still_running(self) -> list[Waiting]:
        """Every drive task still running and the program line where it waits, then every
        drive whose own profile still moves."""
        out: list[Waiting] = []
        for s in self._slots:
            drive = s.drive
            who = "" if self.standalone else f"drive {s.axis_id} "
            program = drive.program
            for t in drive.tasks:
                if t.gen is None:
                    continue
                at = suspended_at(t.gen, program.path.__eq__)
                wake = t.wake / drive.config.phase_rate if t.wake > drive.phase else None
                if at is None:
                    out.append(Waiting(f"{who}task {t.id}", why=why_waiting(None, wake)))
                else:
                    file, line = program.where(at[1])
                    why = why_waiting((file, line, 1), wake)
                    out.append(Waiting(f"{who}task {t.id}", file, line, why=why))
            if drive.axis.moving:
                out.append(Waiting(f"the profile of {who.strip() or 'the drive'}", why="moving"))
        return out

    def busy(self) -> bool:
        """True while a drive task runs or sleeps or a drive's profile moves, and (machine
        run) while a machine axis has not yet followed the drive's last demand."""
        if any(self._running(s) for s in self._slots):
            return True
        return not self.standalone and self.controller.cycle <= self._settle_until

    def next_event(self) -> int | None:
        """The current cycle while a drive task is runnable, a drive's profile moves or a
        machine axis follows a demand; else the cycle of the earliest wake-up of a
        sleeping task; None once every drive is idle."""
        cycle = self.controller.cycle
        if cycle <= self._settle_until or not self._started:
            return cycle
        best = None
        for s in self._slots:
            if not self._running(s):
                continue
            phase = s.drive.next_phase()
            if phase is None:
                if self.standalone:
                    return cycle  # the cycle that finds the drive idle ends the run
                continue
            wake = phase // s.per_cycle + 1  # the cycle that runs that phase
            if wake <= cycle:
                return cycle
            if best is None or wake < best:
                best = wake
        return best
