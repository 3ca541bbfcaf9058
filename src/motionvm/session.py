"""The one place a run is assembled: source files, machine, scenario and scope -> a run.

Both faces of motionvm build their runs here, so they give the same results for the
same inputs: the command line (`motionvm.cli`) and the host API (`motionvm.api`).

    spec = RunSpec([Source("main.hmpl"), Source("app.gdl")], machine="m.toml")
    session = Session(spec, emit=print, report=print_to_stderr)   # compiles everything
    session.run(until=2.0)
    session.fault_count                                           # 0: no task faulted

Assembly, in order:
1. The machine: a `MachineConfig`, a machine file (loaded; a bad file is a
   `SessionError`) or the built-in default machine.
2. Each source's language by its suffix: `.hmpl` files are tasks (in the order given,
   skipping ids placed explicitly), `.pdl` files go onto the drives of machine axes that
   run no PDL program yet (a standalone `prog.pdl` on the default machine: axis 0),
   `.gdl` files form one application.
3. Everything compiles before anything runs: any compile error in any language and
   nothing runs (`CompileFailed`, diagnostics already reported).
4. One controller, one clock: each language's run side is a client of its cycle
   (runtime/clients.py), added in a fixed order (HMPL, PDL drives, GDL, then the scope
   recorder, which sees the state every other part left), so that within one cycle
   HMPL messages come before PDL drive messages, which come before GDL's.
5. The scope channels are resolved before the first cycle (an unknown channel is a
   `SessionError`): the machine's own sources (axes, controller I/O, gears) then each
   language's (HMPL variables, `driveN.` PDL drive variables, `OBJECT.STATE` GDL states).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from motionvm.comm.config import CommConfig
from motionvm.runtime.scope import ScopeError
from motionvm.runtime.waits import Waiting
from motionvm.sim.controller import FINISHED, UNTIL, Controller
from motionvm.sim.machine import (
    DEFAULT_MACHINE,
    MachineConfig,
    MachineFileError,
    PdlDriveSpec,
    load_machine,
)
from motionvm.sim.scope import ChannelRegistry, ScopeRecorder, ScopeRequest
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink, render_diagnostic

if TYPE_CHECKING:  # each language is imported when a run has a file of it
    from motionvm.lang.hmpl.compiler import TaskFile
    from motionvm.lang.hmpl.rtapi import HmplRuntime

LANGUAGES = {".hmpl": "HMPL", ".pdl": "PDL", ".gdl": "GDL"}
"""File suffix -> language."""
N_TASKS = 64


class SessionError(Exception):
    """Input that is not a program cannot be used: the command line, a machine file, a
    scenario, a scope request (the CLI's exit code 3). The message is complete; a bad
    file gives one message per problem (`messages`, all of them at once), `located`:
    each starts with the place (`FILE:LINE:COL: error: ...`)."""

    def __init__(self, *messages: str, located: bool = False) -> None:
        super().__init__("\n".join(messages))
        self.messages = list(messages)
        self.located = located


class CompileFailed(Exception):
    """A program did not compile; its diagnostics were reported, nothing runs (exit 2)."""

    def __init__(self, diagnostics: Sequence[Diagnostic]) -> None:
        super().__init__(diagnostics[0].headline() if diagnostics else "compile errors")
        self.diagnostics = list(diagnostics)


@dataclass(frozen=True)
class Source:
    """One program file of a run."""

    path: str
    text: str | None = None
    """The source text, for a program that is not in a file (HMPL only); None: read it."""
    task: int | None = None
    """HMPL: the task it runs as (None: the next free task id)."""

    @property
    def language(self) -> str | None:
        return LANGUAGES.get(Path(self.path).suffix.lower())


@dataclass
class RunSpec:
    """Everything a run is made of (the CLI's options, the API's arguments)."""

    sources: Sequence[Source] = ()
    machine: MachineConfig | str | Path | None = None
    """A loaded machine, a machine file, or None for the built-in machine."""
    scenario: str | None = None
    """A scenario file of timed input changes and faults (sim/scenario.py), shared with
    a GDL application."""
    scope: ScopeRequest | None = None
    stamp: bool = False
    """Prefix every message with the simulated time and its source."""
    pdl_starts: Sequence[str] = ()
    """Labels the host starts on a PDL program given as a file (`--start`)."""
    gdl_forces: Sequence[str] = ()
    """GDL: `REF = VALUE` forces applied at t=0 (`--force`)."""
    shuffle_seed: int | None = None
    """GDL: permute the order of procedures sharing an activator."""
    data_dir: str | Path | None = None
    """Folder of persistent data (user table); default: the machine's."""
    skip: bool = True
    """Jump the clock over idle cycles (False: `--no-skip`, step every cycle; the same
    output either way). The environment variable MOTIONVM_NO_SKIP=1 also turns it off."""
    scope_title: str = ""
    """The title of scope plots (the command line's files)."""
    werror: bool = False
    """Compiler warnings (HMPL, GDL) fail the compile like errors (`--Werror`)."""


def load_machine_spec(machine: MachineConfig | str | Path | None) -> MachineConfig:
    """The machine of a run; SessionError (each problem at its file, line and column) for
    a bad file."""
    if machine is None:
        return DEFAULT_MACHINE
    if isinstance(machine, MachineConfig):
        return machine
    try:
        return load_machine(machine)
    except MachineFileError as exc:
        raise SessionError(*exc.messages, located=exc.located) from None


def place_tasks(sources: Sequence[Source]) -> list[TaskFile]:
    """HMPL sources as tasks: explicit ids first, the others take 0, 1, 2, ... in order."""
    placed: dict[int, Source] = {}
    for s in sources:
        if s.task is None:
            continue
        if not 0 <= s.task < N_TASKS:
            raise SessionError(f"task {s.task}: task ids are 0..{N_TASKS - 1}")
        if s.task in placed:
            raise SessionError(f"task {s.task} given twice ({placed[s.task].path} and {s.path})")
        placed[s.task] = s
    nxt = 0
    for s in sources:
        if s.task is not None:
            continue
        while nxt in placed:
            nxt += 1
        if nxt >= N_TASKS:
            raise SessionError(f"more than {N_TASKS} task files")
        placed[nxt] = s
        nxt += 1
    from motionvm.lang.hmpl.compiler import TaskFile

    return [TaskFile(t, s.path, s.text) for t, s in sorted(placed.items())]


def check_sources(sources: Sequence[Source]) -> None:
    """Every source has a known language and, unless given as text, exists."""
    for s in sources:
        if s.language is None:
            suffix = Path(s.path).suffix.lower() or "(none)"
            raise SessionError(
                f"unknown file type '{suffix}' of {s.path} (expected .hmpl, .pdl or .gdl)"
            )
        if s.text is None and not Path(s.path).is_file():
            raise SessionError(f"{s.path}: no such file")
        if s.text is not None and s.language != "HMPL":
            raise SessionError(f"{s.path}: only HMPL programs can be given as text")


@dataclass
class Compiled:
    """The compiled programs of a run, per language (None: the language is absent)."""

    hmpl: tuple | None = None
    """(CompiledProgram, Memory)"""
    pdl: list | None = None
    """Compiled PDL drives, by axis."""
    gdl: object | None = None
    """The GDL application (`lang.gdl.App`)."""


def _render(items: Sequence[Diagnostic], report: Callable[[str], None]) -> None:
    for d in items:
        report(render_diagnostic(d))


def compile_run(
    spec: RunSpec,
    machine: MachineConfig,
    report: Callable[[str], None],
    *,
    place: bool = True,
    standalone: bool = False,
) -> tuple[Compiled, MachineConfig]:
    """Compile every program of `spec` (diagnostics reported, HMPL then PDL then GDL).

    Returns the programs and the machine with the command line's PDL programs placed on
    its drives. With `place` false (`motionvm check`) PDL files are compiled on their
    own, any number of them, and the machine's programs are not. `standalone`: the one
    PDL file runs alone on the default machine (see `Session`). Raises CompileFailed
    after any error, SessionError for bad input.
    """
    check_sources(spec.sources)
    by_lang: dict[str, list[Source]] = {"HMPL": [], "PDL": [], "GDL": []}
    for s in spec.sources:
        by_lang[s.language].append(s)  # type: ignore[index]
    if place:
        machine = _place_pdl(machine, by_lang["PDL"], spec.pdl_starts)
    else:
        machine = dataclasses.replace(
            machine,
            pdl_drives=tuple(PdlDriveSpec(i, Path(s.path)) for i, s in enumerate(by_lang["PDL"])),
        )
    if spec.pdl_starts and not by_lang["PDL"]:
        raise SessionError("--start applies to a PDL program given as a file; none was given")
    if not by_lang["GDL"]:
        for given, option in (
            (spec.gdl_forces, "--force"),
            (spec.shuffle_seed is not None, "--shuffle-order"),
        ):
            if given:
                raise SessionError(f"{option} applies to GDL applications; no .gdl file was given")
    out = Compiled()
    failed: list[Diagnostic] = []
    pdl_failed = gdl_failed = False
    if by_lang["HMPL"]:
        from motionvm.lang.hmpl.compiler import compile_tasks

        sink = DiagnosticSink()
        prog, mem = compile_tasks(place_tasks(by_lang["HMPL"]), sink, bytecode=place)
        _render(sink.items, report)
        failed += _failures(sink, spec.werror)
        out.hmpl = (prog, mem) if prog is not None else None
    if machine.pdl_drives:
        from motionvm.lang.pdl.machine_drives import (
            PdlStartError,
            compile_drives,
            compile_program,
        )

        try:
            if standalone:  # one program on the command line, the default machine
                drives = compile_program(by_lang["PDL"][0].path, spec.pdl_starts, report, failed)
            else:
                drives = compile_drives(machine, report, failed)
        except PdlStartError as exc:
            raise SessionError(str(exc), located=True) from None
        pdl_failed = drives is None
        out.pdl = drives
    if by_lang["GDL"]:
        from motionvm.lang.gdl.compiler import compile_app

        paths = [s.path for s in by_lang["GDL"]]
        sink = DiagnosticSink()
        app = compile_app(paths, sink=sink)
        order = {p: i for i, p in enumerate(paths)}
        _render(
            sorted(sink.items, key=lambda d: (order.get(d.pos.file, -1), d.pos.line, d.pos.col)),
            report,
        )
        failed += _failures(sink, spec.werror)
        gdl_failed = app is None
        out.gdl = app
    if failed or pdl_failed or gdl_failed:
        if spec.werror and any(d.severity == "warning" for d in failed):
            report(WERROR_NOTE)
        raise CompileFailed(failed)
    return out, machine


WERROR_NOTE = "motionvm: all warnings being treated as errors (--Werror)"


def _failures(sink: DiagnosticSink, werror: bool) -> list[Diagnostic]:
    """The diagnostics that fail a compile: its errors, and with --Werror its warnings."""
    return [d for d in sink.items if d.severity == "error" or (werror and d.severity == "warning")]


def _place_pdl(
    machine: MachineConfig, files: Sequence[Source], starts: Sequence[str]
) -> MachineConfig:
    """The machine with each PDL file on the next axis whose drive runs no program."""
    if not files:
        return machine
    if len(files) > 1:
        raise SessionError(
            "one .pdl program per drive on the command line; a machine file puts programs "
            'on several drives (pdl = "x.pdl" in an [[axis]] table)'
        )
    taken = {d.axis for d in machine.pdl_drives}
    free = [i for i in range(len(machine.axes)) if i not in taken]
    if not free:
        raise SessionError(f"{files[0].path}: every axis of the machine runs a PDL program")
    spec = PdlDriveSpec(free[0], Path(files[0].path), tuple(starts))  # no `where`: --start
    return dataclasses.replace(machine, pdl_drives=(*machine.pdl_drives, spec))


def check(spec: RunSpec, report: Callable[[str], None]) -> bool:
    """Compile only (`motionvm check`): True if every program compiles; diagnostics reported."""
    try:
        compile_run(spec, DEFAULT_MACHINE, report, place=False)
    except CompileFailed:
        return False
    return True


TIMEOUT = "timeout"
"""`Session.run` ended at its `timeout`: the run should have finished before."""


@dataclass(frozen=True)
class RunResult:
    """Why a run stopped, when, and what still ran then."""

    reason: str
    """FINISHED (nothing left to do), UNTIL (the end time came first), TIMEOUT (the run
    had not finished by its timeout) or STOPPED (its output went away)."""
    sim_time: float
    """Simulated time at the end [s]."""
    still_running: list[Waiting]
    """With UNTIL and TIMEOUT: every task, drive task, scenario and axis that had not
    finished, with the place in the user's file where it waits (if one says it)."""
    end: float | None = None
    """The end time asked for [s]: `until` (or a GDL scenario's), or `timeout`."""

    @property
    def finished(self) -> bool:
        return self.reason == FINISHED


class Session:
    """One assembled run: the controller and every language's run side on it."""

    def __init__(
        self,
        spec: RunSpec,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
    ) -> None:
        """Compile and wire the run of `spec`. `emit` receives every message line a
        program prints, `report` every diagnostic and fault (one line each, or a
        rendered diagnostic of several lines)."""
        self.spec = spec
        self._emit = emit
        self._report = report
        base = load_machine_spec(spec.machine)
        self.standalone_pdl = (
            spec.machine is None
            and bool(spec.sources)
            and all(s.language == "PDL" for s in spec.sources)
        )
        """One PDL program alone, no machine file: it runs on axis 0 of the default
        machine with the drive's own default parameters, and its messages and faults
        name the task only (`[task N]`), as a single drive reports them."""
        compiled, machine = compile_run(spec, base, report, standalone=self.standalone_pdl)
        self.machine = machine
        self.controller = ctl = Controller(machine.cycle_time, machine=machine)
        ctl.skip = spec.skip and os.environ.get("MOTIONVM_NO_SKIP", "") in ("", "0")
        ctl.comm.config = machine.comm
        self.scenario = None
        if spec.scenario is not None:  # its events apply before every language's cycle
            from motionvm.sim.scenario import ScenarioClient

            self.scenario = ScenarioClient(ctl, report)
            ctl.add_client(self.scenario)
        self.hmpl: HmplRuntime | None = None
        self.pdl = None
        self.gdl = None
        if compiled.hmpl is not None:
            from motionvm.lang.hmpl.rtapi import HmplRuntime, data_dir_default

            prog, mem = compiled.hmpl
            if spec.data_dir is not None:
                data_dir = Path(spec.data_dir)
            else:
                data_dir = machine.data_dir or data_dir_default(
                    machine.path.parent if machine.path else None
                )
            self.hmpl = HmplRuntime(
                ctl,
                prog,
                mem,
                emit=emit,
                report=report,
                data_dir=data_dir,
                task_slice=machine.task_slice,
            )
            self.hmpl.stamp = spec.stamp
            ctl.add_client(self.hmpl)
            from motionvm.lang.hmpl.rtcomm import HmplComm

            self.hmpl_comm = HmplComm(self.hmpl)  # Native ASCII, variables, ASCII agent
            self.hmpl_comm.attach(ctl.comm)
            ctl.add_client(self.hmpl_comm)
            ctl.io.on_estop(self.hmpl.estop_input)  # E-stop input: tasks stop
        if compiled.pdl:
            from motionvm.lang.pdl.machine_drives import PdlDrives

            self.pdl = PdlDrives(
                ctl,
                compiled.pdl,
                machine,
                emit=emit,
                report=report,
                stamp=spec.stamp,
                standalone=self.standalone_pdl,
            )
            ctl.add_client(self.pdl)
        shared = self._load_scenario(compiled.gdl is not None)
        if compiled.gdl is not None:
            self.gdl = self._gdl_client(compiled.gdl, shared)
            ctl.add_client(self.gdl)
        self.recorder: ScopeRecorder | None = None
        if spec.scope is not None:
            try:
                channels = self.scope_registry().resolve_all(spec.scope.channels)
            except ScopeError as exc:
                raise SessionError(str(exc)) from None
            self.recorder = ScopeRecorder(channels, ctl.cycle_time, spec.scope.every)
        self._booted = False
        self.closed = False
        """`close()` was called: the run can no longer step."""

    def _load_scenario(self, with_gdl: bool):
        """The scenario file's machine and program events, loaded onto the scenario
        client; the events left to a GDL application are named in the result."""
        if self.scenario is None:
            return None
        from motionvm.sim.scenario import ScenarioError, load_scenario
        from motionvm.sim.variables import Variables

        variables = Variables(self.scope_registry(), self.controller)

        def resolve(name: str):
            if not variables.known(name):
                return None
            if variables.read_only(name):
                raise ValueError(f"'{name}' is read-only")
            return lambda value: variables.write(name, value)

        try:
            loaded = load_scenario(
                self.spec.scenario, resolve, self.controller.io, with_gdl=with_gdl
            )
        except ScenarioError as exc:
            raise SessionError(*exc.messages, located=exc.located) from None
        self.scenario.load(loaded)
        return loaded

    def _gdl_client(self, app, shared=None):
        """The GDL application on this run's controller, with its scenario and forces."""
        from motionvm.lang.gdl.client import GdlApplication
        from motionvm.lang.gdl.motors import GdlMachineError
        from motionvm.lang.gdl.scenario import Scenario, ScenarioError, load_scenario

        spec = self.spec
        try:
            scenario = (
                load_scenario(spec.scenario, app, shared.gdl_events, shared.gdl_initial)
                if shared is not None
                else Scenario((), (), None)
            )
            return GdlApplication(
                self.controller,
                app,
                scenario,
                emit=self._emit,
                report=self._report,
                forces=spec.gdl_forces,
                shuffle_seed=spec.shuffle_seed,
                motor_axes=self.machine.gdl_motors,
            )
        except ScenarioError as exc:  # a scenario file's problems, or a --force text
            raise SessionError(*exc.messages, located=exc.located) from None
        except GdlMachineError as exc:
            raise SessionError(str(exc), located=True) from None

    # ------------------------------------------------------------ running

    def boot(self) -> None:
        """Power on: the PDL drives' start labels, HMPL globals and the tasks that start
        by themselves (task 0, _AUTORUN_); the scope starts recording. Once. (`run` and
        `step` call it first: SessionError once the run was closed.)"""
        self._check_open()
        if self._booted:
            return
        self._booted = True
        if self.pdl is not None:
            from motionvm.lang.pdl.machine_drives import PdlStartError

            try:
                self.pdl.boot()
            except PdlStartError as exc:  # a standalone drive refused a --start label
                raise SessionError(str(exc), located=True) from None
        if self.hmpl is not None:
            self.hmpl.boot()
        if self.recorder is not None:
            self.recorder.attach(self.controller)

    def run(
        self,
        until: float | None = None,
        realtime: bool = False,
        timeout: float | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> RunResult:
        """Run until every part has finished, or until `until` seconds of simulated time
        (the run was meant to last that long), or until `timeout` seconds (the run should
        have finished by then). Returns why it stopped and, if it did not finish, what
        still ran and where. `progress(sim_time)` is called between cycles every so often
        (`Controller.run`); it must not change the run."""
        for value, option in ((until, "--until"), (timeout, "--timeout")):
            if value is not None and not (value >= 0 and math.isfinite(value)):
                raise SessionError(
                    f"{option} must be a finite, non-negative number of seconds, got {value}"
                )
        self.boot()
        self.controller.comm.paced = realtime  # client built-ins take network time
        by_timeout = timeout is not None and (until is None or timeout <= until)
        if by_timeout:
            asked = end = timeout
        else:
            asked = end = until
            if self.gdl is not None:  # a GDL end time is inclusive: events due at it apply
                if asked is None:
                    asked = self.gdl.scenario.until
                end = self.gdl.run_until(end)
            elif asked is None and self.scenario is not None:
                asked = end = self.scenario.scenario.until
        reason = self.controller.run(end, realtime=realtime, progress=progress)
        if self.gdl is not None:
            self.gdl.finish()
        if reason == UNTIL and by_timeout:
            reason = TIMEOUT
        waiting = self.controller.still_running() if reason in (UNTIL, TIMEOUT) else []
        return RunResult(reason, self.controller.sim_time, waiting, asked)

    def serve(
        self,
        until: float | None = None,
        ready: Callable[[dict[str, int]], None] | None = None,
        comm: CommConfig | None = None,
    ) -> RunResult:
        """A run paced to the wall clock with the TCP servers listening (comm/servers.py;
        `comm`: address and ports, default the machine file's `[comm]`), until `until`
        seconds, or until `controller.stop_requested` is set (STOPPED) or Ctrl-C (the
        KeyboardInterrupt goes on after the servers closed). The servers keep answering
        after every task has ended. `ready(ports)` is called once they listen."""
        from motionvm.comm.servers import CommError, CommServers

        self._check_open()  # before any server listens
        servers = CommServers(self.controller.comm, comm or self.machine.comm)
        try:
            ports = servers.start()
        except CommError as exc:
            raise SessionError(str(exc)) from None
        try:
            if ready is not None:
                ready(ports)
            return self.run(until, realtime=True)
        finally:
            servers.stop()

    def step(self, cycles: int = 1) -> None:
        """Run exactly `cycles` controller cycles."""
        self.boot()
        for _ in range(cycles):
            self.controller.step()

    def _check_open(self) -> None:
        if self.closed:
            raise SessionError("this run was closed: it cannot run any more")

    def close(self) -> None:
        """Free the run's memory now (the HMPL program's memory and namespace); nothing
        runs afterwards. Idempotent."""
        if self.closed:
            return
        self.closed = True
        self.controller.comm.close()
        if self.hmpl is not None:
            self.hmpl.close()

    @property
    def fault_count(self) -> int:
        """Faults of tasks, drive tasks and procedures, and scenario writes the run
        refused, so far (0: the run is clean)."""
        n = 0
        if self.hmpl is not None:
            n += self.hmpl.faults
        if self.pdl is not None:
            n += len(self.pdl.faults)
        if self.gdl is not None:
            n += self.gdl.error_count
        if self.scenario is not None:
            n += self.scenario.errors
        return n

    # ------------------------------------------------------------ scope

    def scope_registry(self) -> ChannelRegistry:
        """Every channel this run offers: the machine's, then each language's."""
        from motionvm.sim.scope_sources import registry_for

        return registry_for(self.controller, self.hmpl, self.pdl, self.gdl)

    def scope_channels(self) -> list[tuple[str, str]]:
        """(name, unit) of every channel this run offers, in `scope_registry()` order
        (`motionvm scope --list`); the run need not have started."""
        registry = self.scope_registry()
        return [(name, registry.resolve(name).unit) for name in registry.names()]

    def save_scope(self) -> None:
        """Write the recording (the samples in `--scope-window`) to every `--scope-out`
        file, and `-` as lines through `emit`, after the run's messages (SessionError if
        a file cannot be written); a note when SetHMIScope or the window left no sample."""
        rec, request = self.recorder, self.spec.scope
        if rec is None or request is None:
            return
        if rec.hmi_gated and not any(rec.hmi_on):
            self._report(
                "motionvm: note: the program called SetHMIScope but the HMI scope was never on "
                "at the end of a recorded cycle: the scope recording is empty"
            )
        elif request.window is not None and rec.cycles:
            rec.apply_hmi_gate()
            times = rec.times
            if not any(t in request.window for t in times):
                self._report(
                    f"motionvm: note: --scope-window {request.window} holds no sample (the "
                    f"recording spans {times[0]:g} to {times[-1]:g} s): the scope files are empty"
                )
        for path in request.outputs:
            if request.is_stdout(path):
                for line in rec.csv_lines(request.window):
                    self._emit(line)
                continue
            try:
                rec.save(path, title=self.spec.scope_title, window=request.window)
            except ScopeError as exc:
                raise SessionError(str(exc)) from None
