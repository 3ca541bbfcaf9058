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
2. Each source's language by its suffix, through the language interface
   (`motionvm.lang`; this module names no language): `.hmpl` files are tasks (in the
   order given, skipping ids placed explicitly), `.pdl` files go onto the drives of
   machine axes that run no PDL program yet (a standalone `prog.pdl` on the default
   machine: axis 0), `.gdl` files form one application.
3. Everything compiles before anything runs: any compile error in any language and
   nothing runs (`CompileFailed`, diagnostics already reported).
4. One controller, one clock: each language's run side (`Language.attach`) is a client
   of its cycle (runtime/clients.py), added in registry order (HMPL, PDL drives, GDL, then
   the scope
   recorder, which sees the state every other part left), so that within one cycle
   HMPL messages come before PDL drive messages, which come before GDL's.
5. The scope channels are resolved before the first cycle (an unknown channel is a
   `SessionError`): the machine's own sources (axes, controller I/O, gears) then each
   language's (HMPL variables, `driveN.` PDL drive variables, `OBJECT.STATE` GDL states).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from motionvm.comm.config import CommConfig
from motionvm.lang import (
    LANGUAGES,
    CompileRequest,
    Language,
    LanguageInputError,
    RunContext,
    RunSide,
    Source,
    language_of,
    suffix_list,
)
from motionvm.lang.coverage import Coverage, collecting
from motionvm.runtime.scope import ScopeError
from motionvm.runtime.waits import Waiting
from motionvm.sim.controller import FINISHED, FOREVER, UNTIL, Controller
from motionvm.sim.machine import (
    DEFAULT_MACHINE,
    MachineConfig,
    MachineFileError,
    load_machine,
)
from motionvm.sim.scope import ChannelRegistry, ScopeRecorder, ScopeRequest
from motionvm.source.diagnostics import Diagnostic, in_order, render_diagnostic
from motionvm.source.files import why_unreadable

__all__ = [
    "CompileFailed",
    "RunResult",
    "RunSpec",
    "Session",
    "SessionError",
    "Source",
    "check",
    "check_sources",
]


class SessionError(Exception):
    """Input that is not a program cannot be used: the command line, a machine file, a
    scenario, a scope request (the CLI's exit code 3). The message is complete; a bad
    file gives one message per problem (`messages`, all of them at once), `located`:
    each starts with the place (`FILE:LINE:COL: error: ...`)."""

    def __init__(self, *messages: str, located: bool = False) -> None:
        super().__init__("\n".join(messages))
        self.messages = list(messages)
        self.located = located

    @classmethod
    def of(cls, exc: LanguageInputError) -> SessionError:
        return cls(*exc.messages, located=exc.located)


class CompileFailed(Exception):
    """A program did not compile; its diagnostics were reported, nothing runs (exit 2)."""

    def __init__(self, diagnostics: Sequence[Diagnostic]) -> None:
        super().__init__(diagnostics[0].headline() if diagnostics else "compile errors")
        self.diagnostics = list(diagnostics)


@dataclass
class RunSpec:
    """Everything a run is made of (the CLI's options, the API's arguments)."""

    sources: Sequence[Source] = ()
    machine: MachineConfig | str | Path | None = None
    """A loaded machine, a machine file, or None for the built-in machine."""
    scenario: str | None = None
    """A scenario file of timed input changes and faults (sim/scenario.py); each
    language takes the entries that name its objects."""
    scope: ScopeRequest | None = None
    stamp: bool = False
    """Prefix every message with the simulated time and its source."""
    options: Mapping[str, Any] = field(default_factory=dict)
    """Options that one language takes, by key (`Language.options`): `starts` (labels
    the host starts on a PDL program given as a file, `--start`), `forces` (GDL:
    `REF = VALUE` forces applied at t=0, `--force`), `shuffle_seed` (GDL: permute the
    order of procedures sharing an activator)."""
    data_dir: str | Path | None = None
    """Folder of persistent data (user table); default: the machine's."""
    skip: bool = True
    """Jump the clock over idle cycles (False: `--no-skip`, step every cycle; the same
    output either way). The environment variable MOTIONVM_NO_SKIP=1 also turns it off."""
    scope_title: str = ""
    """The title of scope plots (the command line's files)."""
    werror: bool = False
    """Compiler warnings fail the compile like errors (`--Werror`)."""
    coverage: bool = False
    """Count the lines and `if` arms of every program file that run (`Session.coverage`,
    lang/coverage.py): the programs are compiled with probes."""


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


def check_run_times(until: object, timeout: object) -> None:
    """SessionError unless `until` and `timeout` are each None or a finite, non-negative
    number of seconds (every way of running checks them so)."""
    for value, option in ((until, "until"), (timeout, "timeout")):
        if value is not None and not (
            isinstance(value, int | float) and value >= 0 and math.isfinite(value)
        ):
            raise SessionError(
                f"{option} must be a finite, non-negative number of seconds, got {value!r}"
            )


def check_sources(sources: Sequence[Source]) -> None:
    """Every source has a known language and, unless given as text, exists."""
    for s in sources:
        lang = language_of(s.path)
        if lang is None:
            suffix = Path(s.path).suffix.lower() or "(none)"
            raise SessionError(
                f"unknown file type '{suffix}' of {s.path} (expected {suffix_list()})"
            )
        if s.text is None and not Path(s.path).is_file():
            raise SessionError(f"{s.path}: {why_unreadable(s.path)}")
        if s.text is not None and not lang.accepts_text:
            takers = " or ".join(x.name for x in LANGUAGES if x.accepts_text)
            raise SessionError(f"{s.path}: only {takers} programs can be given as text")


def _by_language(sources: Sequence[Source]) -> dict[Language, list[Source]]:
    """The sources of each language, in registry order (every language, maybe none)."""
    out: dict[Language, list[Source]] = {lang: [] for lang in LANGUAGES}
    for s in sources:
        out[language_of(s.path)].append(s)  # type: ignore[index]
    return out


def _check_options(spec: RunSpec, files: dict[Language, list[Source]]) -> None:
    """A language's option needs a file of that language."""
    for lang in LANGUAGES:
        for option in lang.options:
            given = spec.options.get(option.key)
            if given not in (None, (), []) and not files[lang]:
                raise SessionError(f"{option.flag} {option.unused}")


def _alone(spec: RunSpec, lang: Language) -> bool:
    """Only files of `lang` and no machine file."""
    return (
        spec.machine is None
        and bool(spec.sources)
        and all(language_of(s.path) is lang for s in spec.sources)
    )


def compile_run(
    spec: RunSpec,
    machine: MachineConfig,
    report: Callable[[str], None],
    *,
    check_only: bool = False,
    diagnostics: list[Diagnostic] | None = None,
) -> tuple[list[tuple[Language, object]], MachineConfig]:
    """Compile every program of `spec`, language by language (diagnostics reported).

    Returns each language's program and the machine with the files placed on it (PDL
    programs on drives). `check_only` (`motionvm check`): each language checks its files
    on their own, nothing will run. `diagnostics` receives every diagnostic reported.
    Raises CompileFailed after any error, SessionError
    for bad input.
    """
    check_sources(spec.sources)
    files = _by_language(spec.sources)
    try:
        for lang in LANGUAGES:
            request = CompileRequest(machine, spec.options, check_only, _alone(spec, lang))
            machine = lang.place(machine, files[lang], request)
        _check_options(spec, files)
        programs: list[tuple[Language, object]] = []
        failed: list[Diagnostic] = []
        broken = False
        for lang in LANGUAGES:
            if not lang.has_programs(files[lang], machine):
                continue
            request = CompileRequest(machine, spec.options, check_only, _alone(spec, lang))
            result = lang.compile(files[lang], request)
            for d in in_order(result.diagnostics):
                report(render_diagnostic(d))
            if diagnostics is not None:
                diagnostics += result.diagnostics
            failed += [
                d
                for d in result.diagnostics
                if d.severity == "error" or (spec.werror and d.severity == "warning")
            ]
            if result.program is None:
                broken = True
            else:
                programs.append((lang, result.program))
    except LanguageInputError as exc:
        raise SessionError.of(exc) from None
    if failed or broken:
        if spec.werror and any(d.severity == "warning" for d in failed):
            report(WERROR_NOTE)
        raise CompileFailed(failed)
    return programs, machine


def _line_table(path: str):
    """The line table of a program file, from its language (coverage's executable lines)."""
    lang = language_of(path)
    if lang is None:
        raise LanguageInputError(f"{path}: no language")
    return lang.line_table(path)


WERROR_NOTE = "motionvm: all warnings being treated as errors (--Werror)"


def check(
    spec: RunSpec,
    report: Callable[[str], None],
    diagnostics: list[Diagnostic] | None = None,
) -> bool:
    """Compile only (`motionvm check`): True if every program compiles; diagnostics
    reported, and each added to `diagnostics` too (the language server's)."""
    try:
        compile_run(spec, DEFAULT_MACHINE, report, check_only=True, diagnostics=diagnostics)
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
    had not finished by its timeout), FOREVER (it never can: what every remaining part
    waits on, nothing left in the run can change; without an end time or before the
    timeout, never before `until`) or STOPPED (its output went away)."""
    sim_time: float
    """Simulated time at the end [s]."""
    still_running: list[Waiting]
    """With UNTIL, TIMEOUT and FOREVER: every task, drive task, scenario and axis that had not
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
        self.coverage: Coverage | None = None
        """The line and branch counters of the run (`RunSpec.coverage`), else None."""
        if spec.coverage:
            self.coverage = Coverage(_line_table)
        with collecting(self.coverage):
            programs, machine = compile_run(spec, base, report)
        self.machine = machine
        self.controller = ctl = Controller(machine.cycle_time, machine=machine)
        ctl.skip = spec.skip and os.environ.get("MOTIONVM_NO_SKIP", "") in ("", "0")
        ctl.comm.config = machine.comm
        self.scenario = None
        if spec.scenario is not None:  # its events apply before every language's cycle
            from motionvm.sim.scenario import ScenarioClient

            self.scenario = ScenarioClient(ctl, report)
            ctl.add_client(self.scenario)
        self.sides: list[RunSide] = []
        """Each language's run side, in run order (`motionvm.lang.LANGUAGES`)."""
        data_dir = Path(spec.data_dir) if spec.data_dir is not None else None
        try:
            for lang, program in programs:
                context = RunContext(
                    machine, emit, report, spec.stamp, spec.options, data_dir, _alone(spec, lang)
                )
                self.sides.append(lang.attach(ctl, program, context))
        except LanguageInputError as exc:
            raise SessionError.of(exc) from None
        self._load_scenario()
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

    def side(self, language: str) -> RunSide | None:
        """The run side of the language called `language` ("HMPL"), None if the run has
        no program of it."""
        return next((s for s in self.sides if s.language.name == language), None)

    @property
    def has_programs(self) -> bool:
        """Whether any language runs a program (files, or programs the machine names)."""
        return bool(self.sides)

    def _load_scenario(self) -> None:
        """The scenario file's events: the machine's go to the scenario client, each
        language's run side takes its own (sim/scenario.py, the one reader)."""
        if self.scenario is None:
            return
        from motionvm.sim.scenario import ScenarioError, load_scenario
        from motionvm.sim.variables import Variables

        variables = Variables(self.scope_registry(), self.controller)

        def resolve(name: str):
            if not variables.known(name):
                return None
            if variables.read_only(name):
                raise ValueError(f"'{name}' is read-only")
            return lambda value: variables.write(name, value)

        takers = [side for side in self.sides if side.takes_scenario()]
        try:
            loaded = load_scenario(self.spec.scenario, resolve, self.controller.io, takers)
        except ScenarioError as exc:
            raise SessionError(*exc.messages, located=exc.located) from None
        self.scenario.load(loaded)
        for side in takers:
            side.scenario_loaded(loaded.until)

    # ------------------------------------------------------------ running

    def boot(self) -> None:
        """Power on: the PDL drives' start labels, HMPL globals and the tasks that start
        by themselves (task 0, _AUTORUN_); the scope starts recording. Once. (`run` and
        `step` call it first: SessionError once the run was closed.)"""
        self._check_open()
        if self._booted:
            return
        self._booted = True
        try:
            for side in self.sides:
                side.boot()
        except LanguageInputError as exc:  # a standalone drive refused a --start label
            raise SessionError.of(exc) from None
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
        check_run_times(until, timeout)
        self.boot()
        self.controller.comm.paced = realtime  # client built-ins take network time
        by_timeout = timeout is not None and (until is None or timeout <= until)
        if by_timeout:
            asked = end = timeout
        else:
            asked, end = self.end_time(until)
        reason = self.controller.run(end, realtime=realtime, progress=progress, deadline=by_timeout)
        self.finish()
        if reason == UNTIL and by_timeout:
            reason = TIMEOUT
        waiting = self.controller.still_running() if reason in (UNTIL, TIMEOUT, FOREVER) else []
        return RunResult(reason, self.controller.sim_time, waiting, asked)

    def end_time(self, until: float | None) -> tuple[float | None, float | None]:
        """(asked, end) of a run asked to last `until` seconds (None: the scenario's end,
        or none): the time asked for, and the end time to give the controller after each
        language's end-of-run rule (GDL: inclusive, the events due at it still apply)."""
        asked = until
        if asked is None and self.scenario is not None:
            asked = self.scenario.scenario.until
        end = asked
        for side in self.sides:
            end = side.end_time(end)
        return asked, end

    def finish(self) -> None:
        """After a run: each language's notes of what never happened."""
        for side in self.sides:
            side.finish()

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
        after every task has ended. `ready(ports)` is called once they listen; then a
        warning is reported if they listen beyond loopback."""
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
            warning = servers.config.exposure_warning()
            if warning is not None:
                self._report(warning)
            return self.run(until, realtime=True)
        finally:
            servers.stop()

    def step(self, cycles: int = 1) -> None:
        """Run exactly `cycles` controller cycles."""
        self.boot()
        for _ in range(cycles):
            self.controller.step()
        self.controller.show_clock()

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
        for side in self.sides:
            side.close()

    @property
    def fault_count(self) -> int:
        """Faults of tasks, drive tasks and procedures, and scenario writes the run
        refused, so far (0: the run is clean)."""
        n = sum(side.fault_count for side in self.sides)
        if self.scenario is not None:
            n += self.scenario.errors
        return n

    # ------------------------------------------------------------ scope

    def scope_registry(self) -> ChannelRegistry:
        """Every channel this run offers: the machine's, then each language's."""
        from motionvm.sim.scope_sources import registry_for

        return registry_for(self.controller, *self.sides)

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
