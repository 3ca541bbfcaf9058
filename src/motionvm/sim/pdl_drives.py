"""PDL programs on the drives of a machine: compile them, step them with the controller.

A machine file's `[[axis]]` table with `pdl = "prog.pdl"` puts that program on the
axis's drive (sim/machine.py reads the keys). `compile_drives` compiles every program
(diagnostics in the DESIGN.md format; any error: nothing runs) and checks the
`pdl_start` labels; `PdlDrives` is the controller client that runs them:

- At `end_cycle` of every controller cycle it runs each drive, in axis order, up to the
  phase that matches the end of that cycle: a cycle of `cycle_time` [s] is
  `round(cycle_time * phase_rate)` phases (15 for 1 ms). After a cycle the drives' time
  equals the controller's, so the HMPL tasks of cycle k see the drives as they were at
  k * cycle_time and the drive messages of cycle k follow the HMPL messages of cycle k.
- A drive message is one stdout line; with `--stamp` it is prefixed
  `[t=SECONDS][drive A task N] ` (A the axis id, t to the phase, 6 decimals). A task's
  fault is `FILE:LINE: runtime error in drive A task N: MESSAGE` on stderr.
- `busy()` is true while any drive task runs or any drive's axis moves; the controller
  counts it as running work and never jumps the clock ahead meanwhile.
- A scope records `driveN.<name>` (a drive's system variable, state or global, N the
  axis id): `PdlDrives` adds a `PdlDriveSource` to `controller.scope_sources`.

The drive moves its own axis model (lang/pdl/drive_axis.PdlAxis, configured from the
axis table: counts_per_unit, max_vel, max_acc, max_dec, start_position, home switch,
left limit switch). The controller's HMPL axis of the same id is marked
`controlled_by = "PDL drive"`; HMPL motion and setting commands to it return
eERR_AXIS_CMD_INVALID_CONTROL_MODE (lang/hmpl/lib/axis.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from motionvm.lang.pdl.drive_axis import AxisConfig as PdlAxisConfig
from motionvm.lang.pdl.drive_rt import Drive, DriveConfig, Message
from motionvm.lang.pdl.lower import PdlProgram
from motionvm.lang.pdl.program import compile_pdl
from motionvm.motion.axis_config import AxisConfig
from motionvm.sim.machine import MachineConfig, PdlDriveSpec
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

CONTROLLED_BY = "PDL drive"


class PdlStartError(Exception):
    """A `pdl_start` label the program does not have (a machine-file error, exit 3)."""


@dataclass
class CompiledDrive:
    spec: PdlDriveSpec
    program: PdlProgram


def compile_drives(
    machine: MachineConfig, report: Callable[[str], None]
) -> list[CompiledDrive] | None:
    """Compile the machine's PDL programs; None (diagnostics reported) on any compile error.

    Raises PdlStartError for a `pdl_start` label the program lacks.
    """
    sink = DiagnosticSink()
    out: list[CompiledDrive] = []
    for spec in machine.pdl_drives:
        program = compile_pdl(str(spec.path), sink=sink)
        if program is not None:
            out.append(CompiledDrive(spec, program))
    for d in sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col)):
        report(render_diagnostic(d))
    if sink.has_errors:
        return None
    for c in out:
        for label in c.spec.starts:
            if label != "top" and label not in c.program.entries:
                raise PdlStartError(
                    f"{c.spec.where}: error: [[axis]] {c.spec.axis}: pdl_start: "
                    f"{c.spec.path.name} has no label '{label}'"
                )
    return out


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


class PdlDrives:
    """The controller client that runs the machine's PDL drives (see the module docstring)."""

    def __init__(
        self,
        controller,
        drives: list[CompiledDrive],
        machine: MachineConfig,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        stamp: bool = False,
    ) -> None:
        self.controller = controller
        self.stamp = stamp
        self._emit = emit
        self._report = report
        self.faults: list[str] = []
        self.drives: list[tuple[int, Drive]] = []
        self.phase_rate = DriveConfig().phase_rate
        self.phases_per_cycle = round(controller.cycle_time * self.phase_rate)
        for c in sorted(drives, key=lambda c: c.spec.axis):
            axis_id = c.spec.axis
            config = DriveConfig(axis=pdl_axis_config(machine.axes[axis_id]))
            drive = Drive(
                c.program,
                config,
                on_message=self._message_sink(axis_id),
                on_fault=self._fault_sink(axis_id),
            )
            self.drives.append((axis_id, drive))
            controller.axes[axis_id].controlled_by = CONTROLLED_BY
        self._starts = {c.spec.axis: c.spec.starts for c in drives}
        from motionvm.sim.scope_sources import PdlDriveSource

        # `driveN.<system variable>` scope channels (README "Scope"), N the axis id
        controller.__dict__.setdefault("scope_sources", []).append(PdlDriveSource(self.drives))

    def _message_sink(self, axis_id: int) -> Callable[[Message], None]:
        rate = self.phase_rate

        def show(m: Message) -> None:
            if self.stamp:
                self._emit(f"[t={m.phase / rate:.6f}][drive {axis_id} task {m.task}] {m.text}")
            else:
                self._emit(m.text)

        return show

    def _fault_sink(self, axis_id: int) -> Callable[[str], None]:
        def fault(text: str) -> None:
            text = text.replace(
                ": runtime error in task ", f": runtime error in drive {axis_id} task ", 1
            )
            self.faults.append(text)
            self._report(text)

        return fault

    def boot(self) -> None:
        """Start the host labels (`pdl_start`) of every drive, in order; the `#task/n`
        tasks started at the drive's reset already. A refused start is a fault."""
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
                    text = f"{drive.program.path}: error: drive {axis_id}: pdl_start {label}: {exc}"
                    self.faults.append(text)
                    self._report(text)

    def begin_cycle(self) -> None:
        """Nothing: the drives run at the end of the cycle."""

    def end_cycle(self) -> None:
        """Run every drive, in axis order, to the end of this controller cycle."""
        target = (self.controller.kernel.cycle + 1) * self.phases_per_cycle
        for _axis_id, drive in self.drives:
            if drive.phase < target and drive.busy:
                drive.run_phases(target - drive.phase)

    def busy(self) -> bool:
        """True while a drive task runs or a drive's axis moves."""
        return any(drive.busy for _a, drive in self.drives)

    def next_event(self) -> int | None:
        """Every cycle while busy: the drives' phases are stepped, never jumped over."""
        return self.controller.cycle if self.busy() else None
