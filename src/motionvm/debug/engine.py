"""The debug engine: a run that stops, shows what is inside, and goes back in time.

    engine = DebugEngine(RunSpec([Source("main.hmpl")]), emit=print, report=print)
    engine.start(stop_on_entry=True)              # -> Stop("entry", ...)
    engine.set_breakpoints("main.hmpl", [BreakpointSpec(12)])
    engine.resume()                               # -> Stop("breakpoint", ...)
    engine.stack(engine.stop.thread)              # frames: file, line, locals
    engine.step_back()                            # the statement before, in a fresh run
    engine.go_to_time(0.5)                        # any earlier or later time

Faces (the DAP server, the API, the studio) call it from their own thread; every call
that runs the program blocks until the program stops again (`pause()` from another
thread stops a running one). Everything the user changes while paused (a variable, a
forced input) is recorded with its position (positions.py) and applied again by every
replay, so a replay reaches the same state: going back to a position is running a fresh
session of the same spec and inputs to it (timeline.py), with time skipping wherever
nothing must be seen. The history kept is the list of inputs: a few bytes each.

Languages are reached only through `motionvm.lang` (the run sides' threads, frames and
variables; the line tables that place breakpoints).
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache

from motionvm.debug.expressions import ExpressionError, compile_expression, evaluate
from motionvm.debug.positions import Breakpoint, History, Input, Position, Stop, hit_rule
from motionvm.debug.timeline import Goal, Timeline, user_depth, user_root
from motionvm.debug.tracer import is_user_file
from motionvm.lang import DebugThread, language_of
from motionvm.runtime.fault_position import Fault
from motionvm.session import RunSpec, Session
from motionvm.sim.controller import until_cycle
from motionvm.sim.variables import Variables


@dataclass(frozen=True)
class BreakpointSpec:
    line: int
    condition: str | None = None
    hit_condition: str | None = None
    log_message: str | None = None


@dataclass(frozen=True)
class Frame:
    """One frame of a thread's call stack, innermost first."""

    id: int
    name: str
    file: str
    line: int
    python: object
    """The Python frame of the generated code."""


FILTERS = ("runtime", "axis")
"""Exception filters: a task's runtime fault; an axis or group error."""


class DebugEngine:
    """One debugged run (see the module docstring)."""

    def __init__(
        self,
        spec: RunSpec,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        until: float | None = None,
    ) -> None:
        """Compiles the programs (CompileFailed, SessionError as `Session` raises them)."""
        self.spec = spec
        self.until = until
        self._emit_out = emit
        self._report_out = report
        self.history = History()
        self._lines_shown = 0
        self._lines_now = 0
        self._bp_by_file: dict[str, list[Breakpoint]] = {}
        self._next_bp = 1
        self._watches: list[str] = []
        self._filters: set[str] = {"runtime"}
        self._axis_errors_seen: set[int] = set()
        self._lock = threading.RLock()
        self._frames: dict[int, Frame] = {}
        self.timeline: Timeline | None = None
        self.timeline = self._new_timeline([])  # compiles: errors raise here

    # ---------------------------------------------------------------- timelines

    def _new_timeline(self, inputs: list[Input]) -> Timeline:
        """A fresh session on `inputs`, with time skipping (a timeline steps the cycle
        before any place where statements are seen: timeline.py)."""
        self._lines_now = 0
        self._axis_errors_seen = set()
        session = Session(self.spec, emit=self._emit, report=self._report)
        self.session = session
        return Timeline(session, self, inputs)

    def _emit(self, line: str) -> None:
        self._lines_now += 1
        if self._lines_now > self._lines_shown:
            self._lines_shown = self._lines_now
            self._emit_out(line)

    def _report(self, line: str) -> None:
        if isinstance(line, Fault) and self.timeline is not None:
            self.timeline.fault(line.text)
        self._emit_out_report(line)

    def _emit_out_report(self, line: str) -> None:
        # faults are output of the run too: shown once per place in the run
        self._lines_now += 1
        if self._lines_now > self._lines_shown:
            self._lines_shown = self._lines_now
            self._report_out(line)

    @property
    def stop(self) -> Stop | None:
        return self.timeline.stop

    @property
    def controller(self):
        return self.session.controller

    @property
    def exit_code(self) -> int:
        return 1 if self.session.fault_count else 0

    def _go(self, goal: Goal) -> Stop:
        self._frames.clear()
        with self._lock:
            tl = self.timeline
            if tl.stop is None and not tl.finished and tl.goal is None:
                return tl.start(goal)
            return tl.go(goal)

    # ---------------------------------------------------------------- running

    def start(self, stop_on_entry: bool = True) -> Stop:
        """Boot the run: paused at its start, or running to the first stop."""
        return self._go(Goal("entry") if stop_on_entry else Goal("continue"))

    def resume(self) -> Stop:
        return self._go(Goal("continue"))

    def resume_to(self, target: Position | None, forever: bool = False) -> Stop:
        """Continue, stopping at `target` too (reason "goto") if nothing stops before;
        with `forever`, `target` only paces a longer run: a run that can never end stops
        before it ("waits forever"), as `resume` does."""
        if target is not None and target <= self.position():
            return self.go_to(target)
        return self._go(Goal("continue", target, reason="goto", forever=forever))

    def pause(self) -> None:
        """From another thread: the running program stops at the next cycle boundary."""
        self.timeline.ask_pause()

    def step(self, kind: str = "over", thread: tuple | None = None) -> Stop:
        """The next statement of `thread` (default: the paused one): "over" (in this
        function or a caller), "in" (any), "out" (in a caller)."""
        stop = self.timeline.stop
        thread = thread or (stop.thread if stop else None)
        frame = self.timeline.paused_frame
        if thread is None or frame is None or self.thread_key(frame) != thread:
            frame = self._frame_of(thread)
        if frame is None:  # not inside a statement of that thread: to its next one
            return self._go(Goal("step", thread=thread, depth=None))
        depth = user_depth(frame)
        depth = {"over": depth, "in": None, "out": depth - 1}[kind]
        if depth is not None and depth < 1:
            depth = None  # out of the task's own function: its next statement anywhere
        return self._go(Goal("step", thread=thread, depth=depth))

    def step_cycle(self, count: int = 1) -> Stop:
        """Run `count` whole controller cycles (from inside a cycle: to the end of it)."""
        here = self.position()
        return self._go(Goal("to", Position(here.cycle + max(1, count), 0), reason="step"))

    def go_to(self, target: Position, reason: str = "goto") -> Stop:
        """To any position of the run, earlier (a fresh run to it) or later."""
        if target >= self.position() and not self.timeline.finished:
            return self._go(Goal("to", target, reason=reason))
        return self._replay_to(target, reason)

    def go_to_time(self, seconds: float) -> Stop:
        """To the start of the cycle nearest `seconds` [s] (0 if negative); ValueError
        for a time that is not a finite number."""
        if not (isinstance(seconds, int | float) and math.isfinite(seconds)):
            raise ValueError(f"go to a time: a finite number of seconds, got {seconds!r}")
        cycles = seconds / self.controller.cycle_time
        cycle = (
            round(cycles)
            if math.isfinite(cycles)
            else until_cycle(seconds, self.controller.cycle_time)
        )
        return self.go_to(Position(max(0, cycle), 0))

    def position(self) -> Position:
        return self.timeline.position()

    def _replay_to(self, target: Position, reason: str) -> Stop:
        with self._lock:
            self.timeline.abandon()
            self.session.close()
            self.timeline = self._new_timeline(list(self.history.inputs))
            self._frames.clear()
            return self.timeline.start(Goal("to", target, reason=reason))

    # ---------------------------------------------------------------- going back

    def step_back(self) -> Stop:
        """To the statement before this one (in any thread), in a fresh run."""
        here = self.position()
        if here.count > 1:
            return self._replay_to(Position(here.cycle, here.count - 1), "step")
        target = self._last_statement_before(here.cycle)
        return self._replay_to(target or Position(0, 0), "step")

    def _last_statement_before(self, cycle: int) -> Position | None:
        """The last statement of the latest cycle before `cycle` that ran one (scanning
        back in windows of cycles, each stepped and traced)."""
        window = 64
        while True:
            first = max(0, cycle - window)
            counts = _Scan(self, self.history.inputs).count_statements(first, cycle)
            if counts:
                last = max(counts)
                return Position(last, counts[last])
            if first == 0:
                return None
            window *= 8

    def reverse_continue(self) -> Stop:
        """Back to the latest breakpoint hit (or data breakpoint change) before now; to the
        start if there is none (scanning back in windows of cycles)."""
        here = self.position()
        window = 256
        while True:
            first = max(0, here.cycle - window)
            hit = _Scan(self, self.history.inputs).last_hit_before(here, first)
            if hit is not None:
                return self._replay_to(hit, "breakpoint")
            if first == 0:
                return self._replay_to(Position(0, 0), "entry")
            window *= 8

    def last_change(self, expression: str) -> tuple[float, object, object] | None:
        """When the value of `expression` (at cycle boundaries) last changed before now:
        (time [s], value before, value after), or None if it never did."""
        scan = _Scan(self, self.history.inputs)
        return scan.last_change(expression, self.position())

    # ---------------------------------------------------------------- breakpoints

    def set_breakpoints(self, file: str, specs: Sequence[BreakpointSpec]) -> list[Breakpoint]:
        """Replace the line breakpoints of `file`; each moved to the next line that holds
        a statement (`verified`), or not verified with a message."""
        lang = language_of(file)
        table = None
        if lang is not None:
            # the run's text of the file: an unsaved buffer (the studio's) if it runs one
            text = next((s.text for s in self.spec.sources if _norm(s.path) == _norm(file)),
                        None)  # fmt: skip
            try:
                table = lang.line_table(file, text)
            except Exception:  # noqa: BLE001 — a file that does not parse: nothing verified
                table = None
        out = []
        for spec in specs:
            bp = Breakpoint(self._next_bp, file, spec.line, False, spec.condition,
                            spec.hit_condition, spec.log_message)  # fmt: skip
            self._next_bp += 1
            line = table.next_line(spec.line) if table is not None else None
            problem = _breakpoint_problem(spec)
            if line is None:
                bp.message = "no statement at or after this line"
            elif problem:
                bp.line, bp.message = line, problem
            else:
                bp.line, bp.verified = line, True
            out.append(bp)
        self._bp_by_file[_norm(file)] = out
        return out

    def breakpoints_of(self, file: str) -> list[Breakpoint]:
        return list(self._bp_by_file.get(_norm(file), ()))

    def breakpoints_set(self) -> bool:
        return any(bp.verified for bps in self._bp_by_file.values() for bp in bps)

    def breakpoint_hits(self, timeline: Timeline, frame) -> tuple[int, ...]:
        bps = self._bp_by_file.get(_norm(frame.f_code.co_filename))
        if not bps:
            return ()
        line = frame.f_lineno
        hits = []
        for bp in bps:
            if not bp.verified or bp.line != line:
                continue
            if bp.condition and not self._true(bp.condition, frame):
                continue
            bp.hits += 1
            if not bp.hit_allows():
                continue
            if bp.log_message is not None:
                self._emit_out(self._interpolate(bp.log_message, frame))
                continue
            hits.append(bp.id)
        return tuple(hits)

    def _true(self, condition: str, frame) -> bool:
        try:
            return bool(self.evaluate_in(condition, frame))
        except ExpressionError:
            return True  # a condition that cannot be evaluated stops (and can be read)

    def _interpolate(self, message: str, frame) -> str:
        out, rest = [], message
        while "{" in rest and "}" in rest.split("{", 1)[1]:
            before, _, tail = rest.partition("{")
            expr, _, rest = tail.partition("}")
            try:
                value = self.evaluate_in(expr, frame)
            except ExpressionError as exc:
                value = f"<{exc}>"
            out += [before, _show(value)]
        return "".join(out) + rest

    def set_data_breakpoints(self, expressions: Sequence[str]) -> list[tuple[str, bool, str]]:
        """Stop at the end of a cycle in which one of `expressions` (a variable of the
        program, an axis variable `axis0.pos_fb`, an I/O point `gpi3`) changed. Returns
        (expression, verified, message) each."""
        out, ok = [], []
        for expr in expressions:
            try:
                self.evaluate_in(expr, None)
            except ExpressionError as exc:
                out.append((expr, False, str(exc)))
                continue
            ok.append(expr)
            out.append((expr, True, ""))
        self._watches = ok
        return out

    def watching(self) -> bool:
        return bool(self._watches) or "axis" in self._filters

    def watch_values(self) -> list[object]:
        values = []
        for expr in self._watches:
            try:
                values.append(self.evaluate_in(expr, None))
            except ExpressionError as exc:
                values.append(str(exc))
        return values

    def watch_changed(self, before: list[object]) -> str:
        for expr, old, new in zip(self._watches, before, self.watch_values()):
            if old != new:
                return f"{expr} changed from {_show(old)} to {_show(new)}"
        return ""

    def set_exception_filters(self, filters: Sequence[str]) -> None:
        self._filters = {f for f in filters if f in FILTERS}

    def faults_wanted(self) -> bool:
        return "runtime" in self._filters

    def axis_errors_wanted(self) -> bool:
        return "axis" in self._filters

    def new_axis_error(self, controller) -> str:
        for i, axis in enumerate(controller.axes):
            if axis.error_stop and i not in self._axis_errors_seen:
                self._axis_errors_seen.add(i)
                return (
                    f"axis {i} stopped with an error (error code {getattr(axis, 'error_code', 0)})"
                )
            if not axis.error_stop:
                self._axis_errors_seen.discard(i)
        return ""

    # ---------------------------------------------------------------- inspection

    def thread_key(self, frame) -> tuple | None:
        root = user_root(frame)
        for side in self.session.sides:
            thread = side.thread_of(root)
            if thread is not None:
                return thread.key
        return ("frame", root.f_code.co_name)

    def threads(self) -> list[DebugThread]:
        """Every task, drive task and procedure that runs now (the paused one first)."""
        out: list[DebugThread] = []
        frame = self.timeline.paused_frame
        if frame is not None:
            key = self.thread_key(frame)
            name = next(
                (t.name for s in self.session.sides for t in s.debug_threads() if t.key == key),
                None,
            )
            if name is None:
                found = [s.thread_of(user_root(frame)) for s in self.session.sides]
                name = next((t.name for t in found if t is not None), str(key[-1]))
            out.append(DebugThread(key, name))
        keys = {t.key for t in out}
        for side in self.session.sides:
            out += [t for t in side.debug_threads() if t.key not in keys]
        return out

    def _frame_of(self, thread: tuple | None):
        """The innermost user frame of a suspended thread."""
        for t in self.threads():
            if t.key == thread:
                frames = _generator_frames(t.generator)
                return frames[0] if frames else None
        return None

    def stack(self, thread: tuple) -> list[Frame]:
        """The thread's frames of the user's code, innermost first."""
        paused = self.timeline.paused_frame
        if paused is not None and self.thread_key(paused) == thread:
            pyframes = []
            f = paused
            while f is not None and is_user_file(f.f_code.co_filename):
                pyframes.append(f)
                f = f.f_back
        else:
            gen = next((t.generator for t in self.threads() if t.key == thread), None)
            pyframes = _generator_frames(gen)
        out = []
        for f in pyframes:
            fid = len(self._frames) + 1
            frame = Frame(fid, _function_name(f), f.f_code.co_filename, f.f_lineno, f)
            self._frames[fid] = frame
            out.append(frame)
        return out

    def frame(self, frame_id: int) -> Frame:
        return self._frames[frame_id]

    def _side_of(self, frame):
        lang = language_of(frame.f_code.co_filename)
        for side in self.session.sides:
            if side.language is lang:
                return side
        return self.session.sides[0] if self.session.sides else None

    def locals_of(self, pyframe) -> dict[str, object]:
        side = self._side_of(pyframe)
        return side.frame_variables(pyframe) if side is not None else {}

    def globals_of(self, pyframe) -> dict[str, object]:
        side = self._side_of(pyframe)
        return side.global_variables(pyframe) if side is not None else {}

    def variables(self) -> Variables:
        return Variables(self.session.scope_registry(), self.controller)

    def machine_view(self) -> dict[str, dict[str, object]]:
        """Axes, I/O and system variables now, by group."""
        import dataclasses

        from motionvm.sim.variables import AxisState

        ctl = self.controller
        axes = {}
        for i, axis in enumerate(ctl.axes):
            axes[f"axis{i}"] = dataclasses.asdict(AxisState.of(axis, ctl.sim_time))
        io = {}
        gpio = ctl.io.gpio
        for n in range(1, len(gpio.inputs) + 1):
            io[f"gpi{n}"] = gpio.inputs[n - 1]
        for n in range(1, len(gpio.outputs) + 1):
            io[f"gpo{n}"] = gpio.outputs[n - 1]
        system = {"time [s]": ctl.sim_time, "cycle": ctl.cycle}
        return {"axes": axes, "io": io, "system": system}

    def evaluate_in(self, expression: str, pyframe) -> object:
        """An expression of the user's language on `pyframe` (None: at the run's level)."""
        side = self._side_of(pyframe) if pyframe is not None else None
        variables = None

        def resolve(name: str):
            nonlocal variables
            if side is not None:
                try:
                    return side.variable(pyframe, name)
                except KeyError:
                    pass
            if variables is None:
                variables = self.variables()
            return variables.read(name)

        return evaluate(expression, resolve)

    def evaluate(self, expression: str, frame_id: int | None = None) -> object:
        pyframe = self._frames[frame_id].python if frame_id in self._frames else None
        if pyframe is None:
            pyframe = self.timeline.paused_frame
        return self.evaluate_in(expression, pyframe)

    # ---------------------------------------------------------------- changing the run

    def set_value(self, name: str, value: object, frame_id: int | None = None) -> None:
        """Set a variable of the run (a program global, `gpiN`, an axis variable) or a
        local of a frame, recorded as an input of the run at this position."""
        pyframe = self._frames[frame_id].python if frame_id in self._frames else None
        here = self.position()
        local = None
        if pyframe is not None and name in self.locals_of(pyframe):
            local = (self.thread_key(pyframe), user_depth(pyframe))
        entry = Input(here, name, value, local)
        self.apply_input(self.timeline, entry, pyframe)
        self.history.cut(here)
        self.history.inputs.append(entry)
        self.timeline.inputs = [i for i in self.timeline.inputs if i.position <= here]
        self._lines_shown = self._lines_now  # the future differs: show what comes

    def global_channel(self, name: str, frame_id: int | None) -> str:
        """The run's name of the global `name` seen from a frame (a PDL drive's `n`:
        `drive1.n`), which `set_value` records."""
        frame = self._frames.get(frame_id) if frame_id is not None else None
        pyframe = frame.python if frame is not None else self.timeline.paused_frame
        side = self._side_of(pyframe) if pyframe is not None else None
        return side.global_channel(pyframe, name) if side is not None else name

    def force_input(self, name: str, value: object) -> None:
        """Drive an input (`gpi3`, `slv8.di1`) from now on, as the machine would."""
        self.set_value(name, value)

    def apply_input(self, timeline: Timeline, entry: Input, pyframe=None) -> None:
        self.controller.kernel.forget_records()  # (what a waiting task tests may change)
        self.controller.jumps.forget()
        if entry.local is not None:
            frame = pyframe or timeline.paused_frame
            if frame is None or self.thread_key(frame) != entry.local[0]:
                frame = self._frame_of(entry.local[0])
            if frame is not None:
                _set_local(frame, entry.name, entry.value)
            return
        found = self.controller.io.channel(entry.name)
        if found is not None and found[1] is not None:
            found[1](entry.value)
            return
        self.variables().write(entry.name, entry.value)

    def close(self) -> None:
        self.timeline.abandon()
        self.session.close()


class _Scan:
    """A throwaway run of the same spec and inputs, in the caller's thread, to find
    positions to go back to (nothing it prints is shown)."""

    def __init__(self, engine: DebugEngine, inputs: list[Input]) -> None:
        self.engine = engine
        self.inputs = list(inputs)

    def _session(self) -> Session:
        return Session(self.engine.spec, emit=lambda line: None, report=lambda line: None)

    def count_statements(self, first: int, end: int) -> dict[int, int]:
        """Statements of the user's code per cycle of cycles first..end-1 that ran any."""
        return self._run(end, lambda frame, count: None, first=first)

    def last_hit_before(self, here: Position, first: int = 0) -> Position | None:
        engine = self.engine
        last: list[Position] = []
        saved = {f: [(b.hits) for b in bps] for f, bps in engine._bp_by_file.items()}
        session = self._session()

        def on_line(frame, count):
            pos = Position(session.controller.cycle, count)
            if pos >= here:
                return
            bps = engine._bp_by_file.get(_norm(frame.f_code.co_filename), ())
            for bp in bps:
                if bp.verified and bp.line == frame.f_lineno and bp.log_message is None:
                    if not bp.condition or _safe_true(engine, bp.condition, frame, session):
                        last.append(pos)
                        return

        def on_boundary(before, after, cycle):
            if before != after and Position(cycle, 0) < here:
                last.append(Position(cycle, 0))

        try:
            self._run(here.cycle + 1, on_line, session, on_boundary, first=first)
        finally:
            for f, hits in saved.items():
                for bp, h in zip(engine._bp_by_file.get(f, ()), hits):
                    bp.hits = h
        return max(last) if last else None

    def last_change(self, expression: str, here: Position):
        session = self._session()
        changes: list[tuple[float, object, object]] = []
        engine = self.engine

        def value():
            variables = Variables(session.scope_registry(), session.controller)
            try:
                return evaluate(expression, variables.read)
            except ExpressionError as exc:
                return f"<{exc}>"

        session.boot()
        ctl = session.controller
        old = value()
        while ctl.cycle < here.cycle and ctl.busy():
            ctl.step()
            new = value()
            if new != old:
                changes.append((ctl.sim_time, old, new))
            old = new
        session.close()
        del engine
        return changes[-1] if changes else None

    def _run(self, end: int, on_line, session=None, on_boundary=None, first: int = 0):
        """Run to the start of cycle `first` with time skipping (the cycle before it,
        and before a recorded input inside a cycle, stepped: warm, timeline.py), then
        cycles first..end-1 stepped and traced; the statement counts of the traced
        cycles that ran any."""
        import sys

        from motionvm.debug.tracer import LineTracer

        session = session or self._session()
        engine = self.engine
        ctl = session.controller
        inputs = list(self.inputs)
        tracer = LineTracer(_with_inputs(on_line, inputs, session, ctl), ctl.clock)
        session.boot()
        watches = engine._watches if on_boundary is not None else []

        def watch():
            variables = Variables(session.scope_registry(), ctl)
            out = []
            for expr in watches:
                try:
                    out.append(evaluate(expr, variables.read))
                except ExpressionError:
                    out.append(None)
            return out

        try:
            while ctl.cycle < end and ctl.busy():
                cycle = ctl.cycle
                while inputs and inputs[0].position <= Position(cycle, 0):
                    _apply_plain(session, inputs.pop(0))
                mid = bool(inputs) and inputs[0].position.cycle == cycle
                if cycle < first and not mid:
                    nxt = [first]
                    if inputs:
                        nxt.append(inputs[0].position.cycle)
                    if min(nxt) - 1 > cycle:
                        ctl.run((min(nxt) - 1) * ctl.cycle_time)
                    else:
                        ctl.step()  # the warm cycle
                    continue
                before = watch() if watches else None
                tracer.enable()
                try:
                    ctl.step()
                finally:
                    tracer.disable()
                if watches:
                    on_boundary(before, watch(), ctl.cycle)
        finally:
            tracer.disable()
            sys.settrace(None)
            session.close()
        return {c: n for c, n in tracer.counts.items() if c >= first}


def _with_inputs(on_line, inputs, session, ctl):
    def hook(frame, count):
        while inputs and inputs[0].position == Position(ctl.cycle, count):
            entry = inputs.pop(0)
            if entry.local is not None:
                _set_local(frame, entry.name, entry.value)
            else:
                _apply_plain(session, entry)
        on_line(frame, count)

    return hook


def _apply_plain(session: Session, entry: Input) -> None:
    ctl = session.controller
    found = ctl.io.channel(entry.name)
    if found is not None and found[1] is not None:
        found[1](entry.value)
        return
    Variables(session.scope_registry(), ctl).write(entry.name, entry.value)


def _safe_true(engine: DebugEngine, condition: str, frame, session: Session) -> bool:
    side = next(
        (s for s in session.sides if s.language is language_of(frame.f_code.co_filename)), None
    )
    local = side.frame_variables(frame) if side else {}
    glob = side.global_variables(frame) if side else {}
    variables = Variables(session.scope_registry(), session.controller)

    def resolve(name):
        if name in local:
            return local[name]
        if name in glob:
            return glob[name]
        return variables.read(name)

    try:
        return bool(evaluate(condition, resolve))
    except ExpressionError:
        return True


def _breakpoint_problem(spec: BreakpointSpec) -> str:
    """Why a breakpoint's condition or hit condition cannot be used ("" if it can)."""
    try:
        hit_rule(spec.hit_condition)
        if spec.condition:
            compile_expression(spec.condition)
    except (ValueError, ExpressionError) as exc:
        return str(exc)
    return ""


def _generator_frames(gen) -> list:
    """The user frames of a suspended generator chain, innermost first."""
    frames = []
    while gen is not None:
        frame = getattr(gen, "gi_frame", None)
        if frame is None:
            break
        if is_user_file(frame.f_code.co_filename):
            frames.append(frame)
        gen = getattr(gen, "gi_yieldfrom", None)
    frames.reverse()
    return frames


def _function_name(frame) -> str:
    name = frame.f_code.co_name
    for prefix in ("g_", "p_"):
        if name.startswith(prefix):
            return name[len(prefix) :]
    return name


def _set_local(frame, name: str, value: object) -> None:
    """Write a local of a paused Python frame (CPython: locals dict, then back to the
    fast locals)."""
    import ctypes

    for key in (name, f"v_{name}"):
        if key in frame.f_locals:
            frame.f_locals[key] = _like(frame.f_locals[key], name, value)
            ctypes.pythonapi.PyFrame_LocalsToFast(ctypes.py_object(frame), ctypes.c_int(0))
            return
    raise KeyError(name)


def _like(old: object, name: str, value: object) -> object:
    """`value` as the kind of number the local holds now: an integer local takes only a
    whole number (ValueError otherwise), a double takes any number."""
    if isinstance(old, float):
        return float(value)
    if isinstance(old, int) and not isinstance(value, int):
        if not (isinstance(value, float) and value.is_integer()):
            raise ValueError(f"'{name}' is an integer variable: it cannot hold {value!r}")
        return int(value)
    return value


@lru_cache(maxsize=1024)
def _norm(path: str) -> str:
    return os.path.normcase(os.path.abspath(path))


def _show(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)
