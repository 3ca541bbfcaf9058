"""The host API: run programs from Python (tests, HMIs, CI scripts) without the CLI.

    with Simulation.from_files(["main.hmpl", "conveyor.hmpl"], machine="m.toml") as sim:
        rec = sim.scope(["axis0.ref_pos", "count"])       # record from now on
        sim.write("gpi3", 1)                              # an input, at once
        sim.run(until=2.0)                                # -> RunResult: why it stopped
        print(sim.read("system_dtest0"), sim.axis(0).pos_fb, rec.data())

A thin face over `motionvm.session`, the assembler the command line uses too: the
same files and machine give the same `messages` as the CLI's stdout lines (HMPL
tasks, PDL drives and GDL applications alike). Everything runs on simulated time;
the same inputs give the same results every run. Variables are named as the scope's
channels (sim/variables.py); docs/api.md has the whole API with examples.
"""

from __future__ import annotations

import math
import operator
import threading
import weakref
from collections.abc import Callable, Sequence
from pathlib import Path
from types import TracebackType
from typing import Any

from motionvm.comm.config import COMM_KEYS, CommConfig, load_comm
from motionvm.debug import Breakpoint, BreakpointSpec, DebugEngine, Frame, Position, Stop
from motionvm.io.system import bit_of
from motionvm.lang import CallError
from motionvm.runtime.fault_position import Fault
from motionvm.session import (
    TIMEOUT,
    CompileFailed,
    RunResult,
    RunSpec,
    Session,
    SessionError,
    Source,
    check_run_times,
)
from motionvm.sim.controller import FINISHED, FOREVER, UNTIL, until_cycle
from motionvm.sim.machine import MachineConfig
from motionvm.sim.scope import ScopeRecorder
from motionvm.sim.variables import AxisState, Variables, WriteError
from motionvm.source.diagnostics import CompileError

__all__ = [
    "AxisState",
    "CallError",
    "Breakpoint",
    "Frame",
    "Stop",
    "CompileError",
    "Fault",
    "Recording",
    "Serving",
    "RunResult",
    "SessionError",
    "Simulation",
    "TaskFault",
    "WriteError",
]


class TaskFault(Exception):
    """A task, drive task or procedure stopped with a runtime error (`raise_faults=True`).

    `fault` is the structured report (`Fault`: file, line, col, time, message, ...);
    `str()` of the exception is the report line the CLI prints."""

    def __init__(self, fault: Fault) -> None:
        super().__init__(fault.text)
        self.fault = fault


class _Log:
    """Where the session's output goes: the lists a `Simulation` shows. A separate
    object, so that the session does not refer back to the `Simulation` (a dropped
    simulation is then freed at once, by reference counting)."""

    def __init__(self, raise_faults: bool) -> None:
        self.messages: list[str] = []
        self.faults: list[str] = []
        self.diagnostics: list[str] = []
        self.to = self.diagnostics
        self.raise_faults = raise_faults
        self.pending: Fault | None = None
        self.controller = None

    def report(self, line: str) -> None:
        self.to.append(line)
        if self.raise_faults and isinstance(line, Fault) and self.pending is None:
            self.pending = line
            if self.controller is not None:  # end `Controller.run` after this cycle
                self.controller.stop_requested = True

    def raise_pending(self) -> None:
        fault, self.pending = self.pending, None
        if fault is not None:
            raise TaskFault(fault)


class Recording:
    """Channels recorded every `every`-th cycle from the moment `Simulation.scope` was
    called until `stop()` (or the end of the simulation)."""

    def __init__(self, recorder: ScopeRecorder, controller) -> None:
        self._recorder = recorder
        self._controller = controller

    @property
    def channels(self) -> list[str]:
        return [c.name for c in self._recorder.channels]

    @property
    def units(self) -> dict[str, str]:
        """Channel -> unit (`mm`, `mm/s`, `bool`, `raw`, ...)."""
        return {c.name: c.unit for c in self._recorder.channels}

    def stop(self) -> None:
        """Stop recording (the samples so far stay)."""
        clients = self._controller.clients
        if self._recorder in clients:
            clients.remove(self._recorder)

    def as_dict(self) -> dict[str, list[float]]:
        """`{"time": [s, ...], channel: [value, ...], ...}`, one entry per sample."""
        rec = self._recorder
        out: dict[str, list[float]] = {"time": rec.times}
        for ch, column in zip(rec.channels, rec.columns):
            out[ch.name] = list(column)
        return out

    def data(self) -> Any:
        """A pandas DataFrame (index `time` [s], one column per channel). Needs pandas
        (`pip install 'motionvm[data]'`): without it, an ImportError that says so
        (`as_dict()` needs nothing)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError(
                "Recording.data() returns a pandas DataFrame and pandas is not installed: "
                "pip install 'motionvm[data]' (or use Recording.as_dict(), which needs "
                "nothing)",
                name="pandas",
            ) from None
        data = self.as_dict()
        times = data.pop("time")
        return pd.DataFrame(data, index=pd.Index(times, name="time"))


class Simulation:
    """One controller running a set of programs (HMPL tasks, PDL drives, a GDL application).

    Raises `CompileError` (with every diagnostic) if a program does not compile and
    `SessionError` for a bad machine file, scenario or file name. Use it as a context
    manager, or call `close()`: either frees its memory at once (so does dropping the
    last reference to it).
    """

    def __init__(
        self,
        tasks: Sequence[Source] = (),
        machine: MachineConfig | str | Path | None = None,
        data_dir: str | Path | None = None,
        *,
        sources: Sequence[Source] = (),
        scenario: str | None = None,
        stamp: bool = False,
        skip: bool = True,
        forces: Sequence[str] = (),
        shuffle_seed: int | None = None,
        raise_faults: bool = False,
        debug: bool = False,
    ) -> None:
        """`tasks` place HMPL task files explicitly (each with `path`, `text` and `task`:
        a `Source`); `sources` are files of any language
        (HMPL ones take the free task ids in order). `scenario`: a scenario file (input
        changes and faults, shared with a GDL application). GDL: `forces` (`REF = VALUE`
        texts applied at t=0), `shuffle_seed`. `skip=False` steps every
        cycle (the same results, slower). `raise_faults`: `run` and `step` raise
        `TaskFault` at the end of the cycle in which the first (next) fault happened.
        `debug`: run under the debug engine (`motionvm.debug`): breakpoints (`break_at`),
        inspection when paused (`threads`, `stack`, `locals`, `evaluate`) and time travel
        (`step_back`, `go_to`); `debugger` is the engine itself."""
        self._log = log = _Log(raise_faults)
        self.messages: list[str] = log.messages
        """Every message line the programs printed, as the CLI prints them."""
        self.faults: list[str] = log.faults
        """Every runtime fault report and note of the run, as the CLI prints them on
        stderr; the fault reports are `Fault`s (see `fault_records`)."""
        self.diagnostics: list[str] = log.diagnostics
        """Compile warnings and notes, rendered."""
        spec = RunSpec(
            [Source(t.path, t.text, t.task) for t in tasks] + list(sources),
            machine=machine,
            data_dir=data_dir,
            scenario=scenario,
            stamp=stamp,
            skip=skip,
            options={"forces": tuple(forces), "shuffle_seed": shuffle_seed},
        )
        self.debugger: DebugEngine | None = None
        """The debug engine of a `debug=True` simulation (None otherwise)."""
        try:
            if debug:
                if raise_faults:
                    raise SessionError("raise_faults does not apply to a debugged simulation")
                self.debugger = DebugEngine(spec, emit=log.messages.append, report=log.report)
                self._session = self.debugger.session
            else:
                self._session = Session(spec, emit=log.messages.append, report=log.report)
        except CompileFailed as exc:
            raise CompileError(exc.diagnostics) from None
        log.to = log.faults
        log.controller = self._session.controller
        self._variables: Variables | None = None
        self._serving: Serving | None = None
        self.pause_reason: Stop | None = None
        """Why a debugged simulation is paused (None: not debugged, or not paused)."""
        if self.debugger is not None:
            self._finalizer = weakref.finalize(self, self.debugger.close)
            self.pause_reason = self.debugger.start(stop_on_entry=True)
        else:
            self._finalizer = weakref.finalize(self, self._session.close)
            self._session.boot()

    @property
    def session(self) -> Session:
        """The session now (a debugged simulation gets a fresh one when it goes back)."""
        return self.debugger.session if self.debugger is not None else self._session

    @property
    def controller(self):
        return self.session.controller

    @property
    def runtime(self):
        """The HMPL run time (None without HMPL files)."""
        side = self.session.side("HMPL")
        return side.runtime if side is not None else None  # type: ignore[attr-defined]

    @classmethod
    def from_files(cls, paths: Sequence[str | Path], **kw: Any) -> Simulation:
        """Files of any language; HMPL files become tasks 0, 1, 2, ... in the order given.
        `machine=` takes a machine file's path or a loaded `MachineConfig`."""
        return cls(sources=[Source(str(p)) for p in paths], **kw)

    @classmethod
    def from_source(cls, text: str, name: str = "program.hmpl", **kw: Any) -> Simulation:
        """One HMPL program given as text, as task 0."""
        return cls([Source(name, text, 0)], **kw)

    # ------------------------------------------------------------ life

    def __enter__(self) -> Simulation:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def close(self) -> None:
        """Free the simulation's memory now; it cannot run afterwards (`SessionError`).
        What it recorded (`messages`, `faults`, recordings) stays readable."""
        if self._serving is not None:
            self._serving.stop()
        self._finalizer()

    @property
    def closed(self) -> bool:
        return self.session.closed

    def _open(self, what: str) -> None:
        """SessionError once closed: the run's state is gone with its memory."""
        if self.closed:
            raise SessionError(
                f"{what}: this simulation was closed; what it recorded (messages, faults, "
                "recordings) stays readable"
            )

    # ------------------------------------------------------------ running

    def run(self, until: float | None = None, timeout: float | None = None) -> RunResult:
        """Run until every part has finished, or until `until` seconds of simulated time
        (the run was meant to last that long), or until `timeout` seconds (it should have
        finished by then). Returns why it stopped: `reason` is "finished", "until",
        "timeout", "forever" (nothing left in the run can change what every remaining
        task waits on: it ends at once, exactly when it never can end) or "stopped", with
        `sim_time` and, if it did not finish,
        `still_running`: each task, drive task, scenario and axis and where it waits.
        With `raise_faults`, raises `TaskFault` instead at the first fault."""
        self._not_serving("run")
        if self.debugger is not None:
            return self._debug_run(until, timeout)
        result = self.session.run(until, timeout=timeout)
        self._log.raise_pending()
        return result

    def advance(self, seconds: float, timeout: float | None = None) -> RunResult:
        """Run `seconds` more of simulated time from now: `run(until=time + seconds)`.
        The end is counted in whole cycles from the cycle the clock shows now, so that
        `advance(0.1)` ten times ends where `run(until=1.0)` does. `timeout`: seconds
        from now, as `run`'s. ValueError for a negative or infinite duration."""
        for value, what in ((seconds, "duration"), (timeout, "timeout")):
            if value is not None and not (
                isinstance(value, int | float) and value >= 0 and math.isfinite(value)
            ):
                raise ValueError(f"advance takes a finite, non-negative {what} [s], got {value!r}")
        dt = self.controller.cycle_time
        now = self.controller.cycle
        until = _after(now, seconds, dt)
        end = None if timeout is None else _after(now, timeout, dt)
        return self.run(until=until, timeout=end)

    def call(self, name: str, *args: Any) -> Any:
        """Call the HMPL built-in `name` now, between cycles, as a task's call would: the
        manual's checks, C's conversions of the arguments (a `str` is a `char *`
        string), and its value. A call the built-in refuses returns the manual's error
        code, as in HMPL (`call("MoveAbs", 99, 1.0)` -> the code of a bad axis id).
        Out-parameters are left out of `args`: the value is then the tuple (return
        value, each out-parameter's value). `CallError` (a ValueError) for a call that
        cannot be made: an unknown or unimplemented name (with the closest names), a
        wrong number or kind of arguments, a built-in that waits (Sleep, Till, the
        client functions: only a task can wait). Needs a run side with built-ins (an
        HMPL program)."""
        self._not_serving("call")
        self.session.boot()
        for side in self.session.sides:
            if name in side.builtin_names():
                return side.call(name, args)
        for side in self.session.sides:
            if side.builtin_names():  # its message names the closest built-ins
                return side.call(name, args)
        raise CallError(
            f"call('{name}'): this simulation runs no program whose built-ins can be called "
            "(an HMPL program)"
        )

    def _debug_run(self, until: float | None, timeout: float | None) -> RunResult:
        check_run_times(until, timeout)
        engine = self.debugger
        by_timeout = timeout is not None and (until is None or timeout <= until)
        end = timeout if by_timeout else until
        target = None
        if end is not None:
            target = Position(until_cycle(end, self.controller.cycle_time))
        stop = self.pause_reason = engine.resume_to(target)
        reason = {"exited": FINISHED, "waits forever": FOREVER}.get(stop.reason, "paused")
        if target is not None and stop.reason == "goto":
            reason = TIMEOUT if by_timeout else UNTIL
        waiting = self.controller.still_running() if reason in (TIMEOUT, FOREVER) else []
        return RunResult(reason, stop.time, waiting, end)

    # ------------------------------------------------------------ debugging

    def _engine(self) -> DebugEngine:
        if self.debugger is None:
            raise SessionError("this simulation is not debugged: create it with debug=True")
        return self.debugger

    def break_at(
        self,
        file: str | Path,
        line: int,
        condition: str | None = None,
        hit_condition: str | None = None,
        log: str | None = None,
    ) -> Breakpoint:
        """A breakpoint at `line` of `file` (moved to the next line with a statement:
        `Breakpoint.line`, `verified`), added to the file's others. `condition`: an
        expression of the file's language; `hit_condition`: `N`, `>= N`, `% N`; `log`: a
        logpoint's message (`{expr}` replaced) instead of a stop."""
        engine = self._engine()
        path = str(file)
        kept = [BreakpointSpec(b.line, b.condition, b.hit_condition, b.log_message)
                for b in engine.breakpoints_of(path)]  # fmt: skip
        found = engine.set_breakpoints(
            path, [*kept, BreakpointSpec(line, condition, hit_condition, log)]
        )
        return found[-1]

    def clear_breakpoints(self, file: str | Path) -> None:
        self._engine().set_breakpoints(str(file), [])

    def threads(self) -> list[tuple[tuple, str]]:
        """(key, name) of every task, drive task and procedure running now."""
        return [(t.key, t.name) for t in self._engine().threads()]

    def stack(self, thread: tuple | None = None) -> list[Frame]:
        """The frames of `thread` (default: the paused one), innermost first."""
        engine = self._engine()
        key = thread or (self.pause_reason.thread if self.pause_reason else None)
        if key is None:
            threads = engine.threads()
            if not threads:
                return []
            key = threads[0].key
        return engine.stack(key)

    def locals(self, frame: Frame | None = None) -> dict[str, object]:
        """The local variables of `frame` (default: the paused statement's frame)."""
        engine = self._engine()
        pyframe = frame.python if frame is not None else engine.timeline.paused_frame
        return engine.locals_of(pyframe) if pyframe is not None else {}

    def evaluate(self, expression: str, frame: Frame | None = None) -> object:
        """An expression of the program's language, on `frame` or the paused statement
        (`count > 3 && !done`, `axis0.pos_fb`, `VALUE OF fan`)."""
        engine = self._engine()
        return engine.evaluate_in(
            expression, frame.python if frame is not None else engine.timeline.paused_frame
        )

    def step_back(self) -> Stop:
        """Back to the statement before the paused one (a fresh run to it)."""
        self.pause_reason = self._engine().step_back()
        self._variables = None
        return self.pause_reason

    def go_to(self, time: float) -> Stop:
        """To the start of the cycle at `time` seconds, earlier or later."""
        self.pause_reason = self._engine().go_to_time(time)
        self._variables = None
        return self.pause_reason

    def _not_serving(self, what: str) -> None:
        """SessionError while `serve` runs the simulation in its thread: a second thread
        stepping or writing the same controller would race with it."""
        if self._serving is not None and self._serving.running:
            raise SessionError(
                f"{what}: this simulation is being served (its thread runs it); "
                "stop the serving first (Serving.stop())"
            )

    def serve(
        self,
        *,
        bind: str = "127.0.0.1",
        native_ascii_port: int = 0,
        user_ascii_port: int = 0,
        modbus_port: int = 0,
        until: float | None = None,
        **access: Any,
    ) -> Serving:
        """Start the controller's TCP servers (Native ASCII, User ASCII, Modbus TCP; port
        0: a free port) and run the simulation paced to the wall clock in a background
        thread, as `motionvm serve` does, until `until` seconds or `Serving.stop()`.
        `access`: other keys of the machine file's `[comm]` (`token`, `idle_timeout`,
        `native_ascii_read_only`, `modbus_read_only`), each overriding the machine
        file's; a bad value is a ValueError, another name a TypeError.
        Returns at once with the bound ports (`Serving.ports`); `SessionError` if a server
        cannot listen, or if it is already being served. `run`, `step` and `write` are
        refused (SessionError) while it serves; `close()` stops it first."""
        if self._serving is not None and self._serving.running:
            raise SessionError("this simulation is already being served")
        unknown = sorted(set(access) - COMM_KEYS)
        if unknown:
            raise TypeError(f"serve() got an unexpected keyword argument '{unknown[0]}'")
        table = dict(vars(self.session.machine.comm))
        table.update(access, bind=bind, native_ascii_port=native_ascii_port,
                     user_ascii_port=user_ascii_port, modbus_port=modbus_port)  # fmt: skip
        comm = load_comm(table, _RaiseValueError())
        self._serving = Serving(self, comm, until)
        return self._serving

    def step(self, cycles: int = 1) -> None:
        """Run exactly `cycles` controller cycles (with `raise_faults`: fewer, if a fault
        raises `TaskFault` at the end of its cycle). ValueError for a negative count."""
        self._not_serving("step")
        if cycles < 0:
            raise ValueError(f"step takes a number of cycles >= 0, got {cycles}")
        if self.debugger is not None:
            self.pause_reason = self.debugger.step_cycle(cycles)
            return
        session, log = self.session, self._log
        if not log.raise_faults:
            session.step(cycles)
            return
        for _ in range(cycles):
            session.step(1)
            log.raise_pending()

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.controller.sim_time

    @property
    def fault_count(self) -> int:
        """Runtime faults of tasks, drive tasks and procedures so far (the CLI exits 1
        if any); `faults` holds their reports and the notes of the run."""
        return self.session.fault_count

    @property
    def fault_records(self) -> list[Fault]:
        """The faults so far, structured: `task`, `file`, `line`, `col`, `time` [s],
        `message`, `kind` ("runtime": the program's error; "internal": an error of
        motionvm while it ran the program) (`str()`: the report line)."""
        return [f for f in self.faults if isinstance(f, Fault)]

    def on_event(self, callback: Callable[[str, object], None]) -> None:
        """Call `callback(kind, payload)` for each SendEvent ('event', id) and SendMsgEvent
        ('msg', text) of an HMPL program. KeyError if no program sends events."""
        if self.runtime is None:
            raise KeyError("this simulation runs no HMPL program")
        for side in self.session.sides:
            side.on_event(callback)

    # ------------------------------------------------------------ variables

    @property
    def variables(self) -> Variables:
        """Every variable of the run by its scope channel name (read, write, units);
        SessionError once closed."""
        self._open("variables")
        if self.debugger is not None:
            return Variables(self.session.scope_registry(), self.controller)
        if self._variables is None:
            self._variables = Variables(self.session.scope_registry(), self.controller)
        return self._variables

    def read(self, name: str, index: int | None = None) -> Any:
        """The value of a variable now, named as a scope channel: an HMPL global or
        system variable (`count`, `system_dtest0`, `table[3]`), a controller input or
        output (`gpi3`, `gpo5`), an axis variable of manual 5.1.1 (`axis0.pos_fb`, in mm
        or deg), a PDL drive variable (`drive1.x_ref_pos`), a GDL state
        (`cooling_fan.VALUE`). `index`: an array element (`read("table", 3)`). KeyError
        (with the closest names) for an unknown name; SessionError once closed."""
        self._open("read")
        _check_name("read", name)
        if index is not None:
            name = f"{name}[{index}]"
        return self.variables.read(name)

    def write(self, name: str, value: Any) -> None:
        """Set a variable now; the next `read` and the programs' next instruction see it.
        HMPL variables as an assignment stores them; `gpiN`/`gpoN`; the axis variables
        an HMPL Set* function sets (`axis0.max_vel` by SetVel, ... `WRITABLE_AXIS`),
        through that function; `driveN.<name>` as the drive's host write; GDL states as a
        scenario input. KeyError for an unknown name, `WriteError` for a read-only
        variable or a refused value (with the manual's error code); SessionError once
        closed."""
        self._open("write")
        _check_name("write", name)
        self._not_serving("write")
        if self.debugger is not None:  # an input of the run: replayed when going back
            self.variables.channel(name)
            self.debugger.set_value(name, value)
            return
        self.variables.write(name, value)

    def axis(self, n: int) -> AxisState:
        """A snapshot of axis `n` now: every axis variable of manual 5.1.1 by its name
        (`pos_fb`, `ref_vel`, ...; mm or deg) and its status flags (`enabled`, `moving`,
        `in_pos`, `error_stop`, ...). IndexError if the machine has no axis `n`, TypeError
        if `n` is not an integer."""
        n = operator.index(n)
        axes = self.controller.axes
        if not 0 <= n < len(axes):
            raise IndexError(f"no axis {n} on this machine (axes 0..{len(axes) - 1})")
        return AxisState.of(axes[n], self.controller.sim_time)

    def set_input(self, name: int | str, value: Any) -> None:
        """Drive an input now: a controller input by number (`set_input(4, True)`: GetGPI(4),
        numbered from 1) or any input by name (`gpi4`, `slv8.di1`, `slv9.ai1` with a raw
        word), as a scenario's `set` does; IndexError / KeyError if there is no such input,
        ValueError for a value the input cannot take (a digital input: 0 or 1, True/False,
        "ON"/"OFF"); SessionError once closed."""
        self._open("set_input")
        if isinstance(name, int):
            self.controller.io.gpio.set_input(name, bit_of(value))
            return
        found = self.controller.io.channel(name)
        if (
            found is None
            or found[1] is None
            or name.startswith("gpo")
            or ".do" in name
            or ".ao" in name
        ):
            raise KeyError(f"no input '{name}' on this machine (inputs: gpiN, slvS.diK, slvS.aiK)")
        found[1](value)

    def inject_fault(self, fault: str, **target: Any) -> None:
        """Inject a fault now, as a scenario's fault event does: `inject_fault("drive",
        axis=0, code=0x7500)`, `("encoder_loss", axis=1)`, `("following_error", axis=0)`,
        `("hw_limit", axis=0, side="left")`, `("slave_lost", slave=9)`, `("estop")`
        (motionvm.io.faults). ValueError for an unknown fault or a bad target; SessionError
        once closed."""
        from motionvm.io.faults import inject_fault

        self._open("inject_fault")
        inject_fault(self.controller.io, fault, **target)

    def output(self, name: int | str) -> int:
        """An output's state now: a controller output by number (GetGPO numbering, from 1)
        or by name (`gpo3`, `slv8.do2`, `slv9.ao1`: the raw word); SessionError once
        closed."""
        self._open("output")
        if isinstance(name, int):
            return self.controller.io.gpio.output(name)
        found = self.controller.io.channel(name)
        if found is None:
            raise KeyError(f"no output '{name}' on this machine")
        return found[0]()

    # ------------------------------------------------------------ scope

    def scope(self, channels: Sequence[str], every: int = 1) -> Recording:
        """Record `channels` (scope channel names, as `read` takes them) at the end of
        every `every`-th cycle from now on; the returned `Recording` gives the data.
        KeyError for an unknown channel. While recording, the clock does not jump over
        idle cycles (the results are the same). TypeError for one name given as a string
        (`scope("count")`: its letters would be channels); SessionError once closed."""
        if isinstance(channels, str):
            raise TypeError(f"scope takes a list of channel names, got the string {channels!r}")
        self._open("scope")
        if every < 1:
            raise ValueError(f"every must be a whole number of cycles >= 1, got {every}")
        found = [self.variables.channel(name) for name in channels]
        recorder = ScopeRecorder(found, self.controller.cycle_time, every)
        recorder.attach(self.controller)
        return Recording(recorder, self.controller)


def _after(cycle: int, seconds: float, dt: float) -> float:
    """The time [s] `seconds` after the start of `cycle`, counted in whole cycles of `dt`
    [s] (a time too long to count in cycles, 1e308 s, as it is)."""
    cycles = seconds / dt
    return (cycle + round(cycles)) * dt if math.isfinite(cycles) else cycle * dt + seconds


class _RaiseValueError:
    """`load_comm`'s problems of `Simulation.serve`'s arguments: the first is a ValueError."""

    def at(self, section: str, key: str, message: str) -> None:
        raise ValueError(message)


class Serving:
    """A simulation served over TCP in a background thread (`Simulation.serve`)."""

    def __init__(self, sim: Simulation, comm: CommConfig, until: float | None) -> None:
        self.sim = sim
        self.ports: dict[str, int] = {}
        """Bound port by server: "native-ascii", "user-ascii", "modbus"."""
        self.result: RunResult | None = None
        """Why the served run stopped (None while it runs)."""
        self._error: BaseException | None = None
        ready = threading.Event()

        def on_ready(ports: dict[str, int]) -> None:
            self.ports = dict(ports)
            ready.set()

        def main() -> None:
            try:
                self.result = sim.session.serve(until, ready=on_ready, comm=comm)
            except BaseException as exc:  # noqa: BLE001 — handed to the caller
                self._error = exc
            finally:
                ready.set()

        self._thread = threading.Thread(target=main, name="motionvm-serve", daemon=True)
        self._thread.start()
        ready.wait()
        if self._error is not None:
            self._thread.join()
            raise self._error

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    def wait(self, timeout: float | None = None) -> RunResult | None:
        """Wait until the served run ends (its `until`), at most `timeout` seconds [wall]."""
        self._thread.join(timeout)
        return self.result

    def stop(self) -> RunResult | None:
        """Stop the run at the next cycle and close the servers; why it stopped."""
        controller = self.sim.controller
        while self._thread.is_alive():
            controller.stop_requested = True
            self._thread.join(0.05)
        if self._error is not None:
            error, self._error = self._error, None
            raise error
        return self.result

    def __enter__(self) -> Serving:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


def _check_name(what: str, name: object) -> None:
    """TypeError unless `name` is a variable's name (a string, as a scope channel)."""
    if not isinstance(name, str):
        raise TypeError(
            f"{what}: a variable is named by a string ('count', 'table[3]', 'axis0.pos_fb'),"
            f" got {name!r}"
        )
