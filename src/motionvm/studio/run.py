"""The studio's run: one debug engine, advanced in simulated time by a server-side task.

Every engine call blocks until the program stops again, so they all run on one worker
thread (`_call`), one at a time. A run is a loop of short engine runs (`resume_to` the
cycle that the pacing allows: `speed` times real time, or as many cycles as take about
one frame of wall time), each followed by what the page shows of it (notifications:
`state`, `console`, `scope`, `panels`, `stopped`). Pause ends the loop at the next frame;
a breakpoint, a fault or the end of the run ends it with its stop.

What the run did is recorded (history.py) by a cycle client on each session of the
engine, so the page can scrub it; going back is the engine's (`go_to`: a replay).
"""

from __future__ import annotations

import asyncio
import math
import time
from collections import deque
from collections.abc import Awaitable, Callable
from concurrent.futures import ThreadPoolExecutor
from functools import partial

from motionvm.debug import BreakpointSpec, DebugEngine, ExpressionError, Position, Stop
from motionvm.runtime.scope import ScopeError
from motionvm.session import CompileFailed, RunSpec, SessionError
from motionvm.studio.history import History, Recorder
from motionvm.studio.views import Layout
from motionvm.studio.workspace import Workspace

FRAME = 1 / 42
"""Wall time [s] between two updates of the page while a run goes (well under 1/30 s,
so that the page, which redraws at most once per update, still draws 30 frames a second
when some updates come late or are drawn together)."""
RUN_SHARE = 0.8
"""The part of a frame the run takes at most; the rest sends what it did (the
measured cost of that is taken off first)."""
ROWS_PER_SECOND = 4000
"""Rows recorded per second of wall time, about, at most: a run going faster is recorded
at every 2nd, 4th, ... cycle (the engine still stops at any cycle)."""
SCOPE_POINTS = 600
"""Samples per channel per update, at most (the scope's stream is thinned to it)."""

Notify = Callable[[str, dict], Awaitable[None]]


class StudioError(ValueError):
    """A request the run cannot do now (the message says why)."""


class StudioRun:
    """The engine of the studio's files, its pacing, and its recording."""

    def __init__(
        self,
        workspace: Workspace,
        notify: Notify,
        *,
        machine: str | None = None,
        scenario: str | None = None,
    ) -> None:
        self.workspace = workspace
        self.notify = notify
        self.machine = machine
        self.scenario = scenario
        self.engine: DebugEngine | None = None
        self.error = ""
        """Why there is no engine (compile errors, a bad machine file)."""
        self.speed: float | None = None
        """×k real time; None: as fast as possible."""
        self.running = False
        self.history: History | None = None
        self.layout: Layout | None = None
        self.scope: list[str] | None = None
        """The scope channels chosen in the page (None: the layout's defaults)."""
        self.breakpoints: dict[str, list[int]] = {}
        self._recorded_session = None
        self._recorder: Recorder | None = None
        self._sent_cycle = -1
        self._lines: deque[dict] = deque()
        self._pause_asked = False
        self._task: asyncio.Task | None = None
        self._moving = False
        """An engine call that runs the program is under way (a seek, a step)."""
        self._executor = ThreadPoolExecutor(1, thread_name_prefix="motionvm-studio")
        self.frames = 0
        """Updates sent while running (the page's frame count)."""
        self.forever = False
        """The run stopped because it can never end (nothing left can change it)."""

    # ---------------------------------------------------------------- the engine

    async def _call(self, fn, *args):
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self._executor, partial(fn, *args))

    async def _move(self, fn, *args) -> Stop:
        """An engine call that runs the program, however far (a seek far beyond the
        recording, many cycles): `pause` stops it at the next cycle boundary."""
        self._moving = True
        try:
            return await self._call(fn, *args)
        finally:
            self._moving = False

    def _build(self) -> None:
        """A fresh engine at t = 0, paused (worker thread)."""
        if self.engine is not None:
            self.engine.close()
        self.engine, self.error = None, ""
        spec = RunSpec(self.workspace.sources(), machine=self.machine, scenario=self.scenario)
        try:
            engine = DebugEngine(spec, emit=self._out, report=self._err)
        except CompileFailed:
            self.error = "the program does not compile (see the console)"
            return
        except SessionError as exc:
            self.error = str(exc)
            self._err(str(exc))
            return
        self.engine = engine
        engine.start(stop_on_entry=True)
        for path, lines in self.breakpoints.items():
            engine.set_breakpoints(path, [BreakpointSpec(n) for n in lines])
        ctl = engine.controller
        self.history = History(ctl.cycle_time)
        self.layout = None  # a new program: no groups seen yet
        self.forever = False
        self._recorded_session = None
        self._sent_cycle = -1
        self._observe()

    def _observe(self) -> None:
        """Record the engine's current session (a replay makes a new one)."""
        engine = self.engine
        if engine is None or engine.session is self._recorded_session:
            return
        session = engine.session
        groups = self.layout.groups if self.layout is not None else None
        self.layout = Layout(session.controller, session.scope_registry(), self.scope, groups)
        self._recorder = Recorder(self.history, session.controller.clock, self.layout.getters,
                                  self.layout.watch_groups)  # fmt: skip
        session.controller.add_client(self._recorder)
        self._recorded_session = session
        if self.history.last_cycle < 0:  # the first row: the state at t = 0
            self.history.add(0, self.layout.live_row())

    def _now(self) -> float:
        engine = self.engine
        try:
            return engine.controller.sim_time if engine is not None else 0.0
        except AttributeError:
            return 0.0

    def _out(self, line: str) -> None:
        self._lines.append({"time": self._now(), "text": str(line), "kind": "out"})

    def _err(self, line: str) -> None:
        self._lines.append({"time": self._now(), "text": str(line), "kind": "err"})

    def _need(self) -> DebugEngine:
        if self.engine is None:
            raise StudioError(self.error or "no program")
        return self.engine

    def _idle(self) -> DebugEngine:
        if self.running:
            raise StudioError("the program is running (pause it first)")
        return self._need()

    # ---------------------------------------------------------------- what the page sees

    def state(self) -> dict:
        engine = self.engine
        out = {"running": self.running, "speed": self.speed, "loaded": engine is not None,
               "error": self.error, "time": 0.0, "cycle": 0, "finished": False,
               "recorded": 0.0, "waits_forever": self.forever}  # fmt: skip
        if engine is not None:
            pos = engine.position()
            out.update(time=engine.controller.sim_time, cycle=pos.cycle,
                       finished=engine.timeline.finished, cycle_time=engine.controller.cycle_time)  # fmt: skip
        if self.history is not None and self.history.last_cycle >= 0:
            out["recorded"] = round(self.history.last_cycle * self.history.cycle_time, 9)
            out["recorded_cycle"] = self.history.last_cycle
        return out

    def describe(self) -> dict:
        out = {"files": self.workspace.describe(), "state": self.state(), "machine": None,
               "scope": [], "units": {}}  # fmt: skip
        if self.layout is not None:
            out["machine"] = self.layout.describe()
            out["scope"] = self.layout.scope
            out["units"] = self.layout.units
        return out

    async def flush(self, live: bool = True) -> None:
        """Send what changed: console lines, new scope samples, the panels, the time."""
        self._observe()
        if self._lines:
            lines = []
            while self._lines:
                lines.append(self._lines.popleft())
            await self.notify("console", {"lines": lines})
        history, layout = self.history, self.layout
        if history is not None and layout is not None:
            # the stream follows the debugger: after going back, the rows recorded before
            # are sent again as the run passes them
            last = min(history.last_cycle, self.engine.position().cycle) if self.engine else -1
            if last > self._sent_cycle:
                names = list(dict.fromkeys(layout.scope + layout.path))
                times, values = history.window(self._sent_cycle + 1, last, names, SCOPE_POINTS)
                self._sent_cycle = last
                await self.notify("scope", {"t": times, "values": values,
                                            "groups": layout.path_groups()})  # fmt: skip
            if live:
                row = layout.live_row()
                await self.notify("panels", self._panels(row))
        await self.notify("state", self.state())

    def _panels(self, row: dict) -> dict:
        layout = self.layout
        return {"time": self._now(), "axes": layout.axes_rows(row), "io": layout.io_values(row)}

    async def _stopped(self, stop: Stop) -> None:
        self.forever = stop.reason == "waits forever"
        if self.forever or stop.reason == "exited":
            # the run ends here: its last state is recorded, whatever the stride (the
            # row of cycle c is the state after it, the stop is at the start of the next)
            if self.history is not None and self.layout is not None:
                self.history.add(stop.position.cycle - 1, self.layout.live_row(), always=True)
        if self.forever:
            why = f": {stop.text}" if stop.text else ""
            self._err(f"the run waits forever at t = {stop.time:.3f} s (nothing left in it "
                      f"can change what it waits on){why}")  # fmt: skip
        body = {"reason": stop.reason, "time": stop.time, "cycle": stop.position.cycle,
                "text": stop.text, "file": None, "line": None, "thread": None}  # fmt: skip
        engine = self.engine
        if stop.thread is not None and engine is not None:
            frames = await self._call(engine.stack, stop.thread)
            if frames:
                body.update(file=frames[0].file, line=frames[0].line)
            body["thread"] = _key_text(stop.thread)
        await self.flush()
        await self.notify("stopped", body)

    # ---------------------------------------------------------------- running

    async def reset(self) -> dict:
        await self.pause()
        await self._call(self._build)
        self._lines.clear()
        if self.error and self.engine is None:
            self._err(self.error)
        await self.notify("reset", self.describe())
        await self.flush()
        return self.state()

    async def run(self, until: float | None = None) -> dict:
        """Run (to `until` seconds if given) on the server's task; answers at once."""
        engine = self._need()
        if self.running:
            return self.state()
        end = None
        if until is not None:
            if not (until >= 0 and math.isfinite(until)):
                raise StudioError(f"run to time: {until} is not a time >= 0 s")
            end = round(until / engine.controller.cycle_time)
            if end <= engine.position().cycle:
                stop = await self._move(engine.go_to, Position(end))
                await self._stopped(stop)
                return self.state()
        self.running, self._pause_asked = True, False
        self._task = asyncio.get_running_loop().create_task(self._loop(end))
        return self.state()

    async def pause(self) -> dict:
        if self._moving and self.engine is not None:
            self.engine.pause()
        if self._task is not None and not self._task.done():
            self._pause_asked = True
            await asyncio.wait({self._task})
        return self.state()

    async def _loop(self, end: int | None) -> None:
        engine = self.engine
        dt = engine.controller.cycle_time
        wall0, cycle0 = time.perf_counter(), engine.position().cycle
        chunk = 256
        sending = 0.0  # wall time the last update took to send [s]
        frame_end = time.perf_counter()  # the frames keep a steady pace
        stop: Stop | None = None
        try:
            await self.notify("state", self.state())
            while not self._pause_asked:
                frame_end += FRAME
                here = engine.position().cycle
                if self.speed is None:
                    target = here + chunk
                else:
                    ahead = cycle0 + int((time.perf_counter() - wall0) * self.speed / dt)
                    limit = here + max(1, int(self.speed * 0.25 / dt))
                    if ahead > limit:  # too far behind: no catching up
                        wall0, cycle0, ahead = time.perf_counter(), here, here + 1
                    target = max(ahead, here + 1)
                if end is not None:
                    target = min(target, end)
                started = time.perf_counter()
                # the target only paces: a run that can never end stops ("waits forever")
                stop = await self._call(engine.resume_to, Position(target), end is None)
                took = max(time.perf_counter() - started, 1e-4)
                if self.speed is None:
                    # most of a frame of running: the rest is for sending what it did
                    budget = max(FRAME * RUN_SHARE - sending, FRAME / 4)
                    chunk = int(min(max(chunk * budget / took, 16), 1 << 22))
                rate = (stop.position.cycle - here) / took  # cycles per wall second
                self.history.coarsen(math.ceil(rate / ROWS_PER_SECOND))
                if stop.reason != "goto" or (end is not None and stop.position.cycle >= end):
                    break
                stop = None
                self.frames += 1
                sent = time.perf_counter()
                await self.flush()
                now = time.perf_counter()
                sending = now - sent
                if now < frame_end:
                    await asyncio.sleep(frame_end - now)
                else:  # a late frame is not made up
                    frame_end = now
        except Exception as exc:  # noqa: BLE001 — shown; the run stays paused where it is
            self._err(f"motionvm studio: the run stopped: {exc}")
            stop = None
        finally:
            self.running = False
        if stop is not None:
            await self._stopped(stop)
        else:
            await self._stopped(Stop("pause", engine.position(), engine.controller.sim_time))

    def set_speed(self, factor: float | None) -> dict:
        if factor is not None and not (factor > 0 and math.isfinite(factor)):
            raise StudioError(f"speed: {factor} is not a factor > 0 (null: as fast as possible)")
        self.speed = factor
        return self.state()

    async def step_cycle(self, count: int = 1) -> dict:
        engine = self._idle()
        if count < 1:
            raise StudioError(f"step cycle: count must be 1 or more, got {count}")
        await self._stopped(await self._move(engine.step_cycle, count))
        return self.state()

    async def seek(self, cycle: int) -> dict:
        """Move the debugger to the start of `cycle` (a replay if it is earlier)."""
        engine = self._idle()
        stop = await self._move(engine.go_to, Position(max(0, int(cycle))))
        self._sent_cycle = min(self._sent_cycle, stop.position.cycle)
        await self._stopped(stop)
        return self.state()

    # ---------------------------------------------------------------- changing the run

    async def set_breakpoints(self, path: str, lines: list[int]) -> list[dict]:
        self.breakpoints[path] = [int(n) for n in lines]
        if self.engine is None:
            return [{"line": n, "verified": False, "message": self.error} for n in lines]
        specs = [BreakpointSpec(int(n)) for n in lines]
        bps = await self._call(self.engine.set_breakpoints, path, specs)
        return [{"line": b.line, "verified": b.verified, "message": b.message} for b in bps]

    async def force(self, name: str, value: object) -> dict:
        engine = self._need()

        def apply():
            engine.force_input(name, value)
            self.history.cut_after(engine.position().cycle)
            self._sent_cycle = min(self._sent_cycle, self.history.last_cycle)

        try:
            await self._call(apply)
        except (KeyError, ValueError, ExpressionError) as exc:
            raise StudioError(f"force {name}: {str(exc).strip(chr(39))}") from None
        await self.flush()
        return self.state()

    async def select_scope(self, names: list[str] | None) -> dict:
        """The scope's channels (None: the defaults), recorded from now on."""
        engine = self._need()
        if names is not None:
            try:
                engine.session.scope_registry().resolve_all(names)
            except ScopeError as exc:
                raise StudioError(str(exc)) from None
            names = list(dict.fromkeys(names))
        self.scope = names

        def apply():
            session = engine.session
            groups = self.layout.groups if self.layout is not None else None
            self.layout = Layout(session.controller, session.scope_registry(), self.scope, groups)
            self._recorder.set_getters(self.layout.getters)
            self._recorder.refresh = self.layout.watch_groups

        await self._call(apply)
        return {"scope": self.layout.scope, "units": self.layout.units}

    async def channels(self) -> list[dict]:
        engine = self._need()
        return await self._call(lambda: [
            {"name": n, "unit": u} for n, u in engine.session.scope_channels()
        ])  # fmt: skip

    # ---------------------------------------------------------------- recorded run

    def at(self, cycle: int, span: float | None = None) -> dict:
        """The panels as recorded at `cycle`, the scope's window of `span` seconds before
        it and the path up to it (nothing moves)."""
        history, layout = self.history, self.layout
        if history is None or layout is None or not len(history):
            raise StudioError(self.error or "nothing recorded yet")
        i = history.index_at(max(0, int(cycle)))
        i = 0 if i is None else i
        row = history.row(i)
        c = history.cycles[i]
        out = self._panels(row)
        out["time"] = round(c * history.cycle_time, 9)
        out["cycle"] = c
        first = 0 if span is None else max(0, c - round(span / history.cycle_time))
        t, values = history.window(first, c, layout.scope, SCOPE_POINTS * 2)
        out["scope"] = {"t": t, "values": values}
        pt, pv = history.window(0, c, layout.path, SCOPE_POINTS * 2)
        out["path"] = {"t": pt, "values": pv, "groups": layout.path_groups()}
        return out

    # ---------------------------------------------------------------- paused: inside

    async def threads(self) -> list[dict]:
        engine = self._idle()
        threads = await self._call(engine.threads)
        return [{"id": _key_text(t.key), "name": t.name} for t in threads]

    async def stack(self, thread: str) -> list[dict]:
        engine = self._idle()

        def frames():
            for t in engine.threads():
                if _key_text(t.key) == thread:
                    return engine.stack(t.key)
            raise StudioError(f"no thread '{thread}'")

        return [{"id": f.id, "name": f.name, "file": f.file, "line": f.line}
                for f in await self._call(frames)]  # fmt: skip

    async def variables(self, frame: int | None) -> dict:
        engine = self._idle()

        def read():
            out: dict[str, list[dict]] = {}
            if frame is not None:
                try:
                    python = engine.frame(frame).python
                except KeyError:
                    raise StudioError(f"no frame {frame} (ask for the stack again)") from None
                out["locals"] = _items(engine.locals_of(python))
                out["globals"] = _items(engine.globals_of(python))
            view = engine.machine_view()
            out["machine"] = _items({**view["system"], **view["io"]})
            return out

        return await self._call(read)

    async def evaluate(self, expression: str, frame: int | None) -> str:
        engine = self._idle()
        try:
            return _text(await self._call(engine.evaluate, expression, frame))
        except ExpressionError as exc:
            raise StudioError(str(exc)) from None

    async def close(self) -> None:
        self._pause_asked = True
        if self._moving and self.engine is not None:
            self.engine.pause()
        if self._task is not None and not self._task.done():
            self._task.cancel()
        engine = self.engine
        if engine is not None:
            await self._call(engine.close)
        self._executor.shutdown(wait=False)


def _key_text(key: tuple) -> str:
    return ":".join(str(k) for k in key)


def _items(values: dict) -> list[dict]:
    return [{"name": str(k), "value": _text(v)} for k, v in values.items()]


def _text(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, list | tuple) and len(value) > 16:
        return "[" + ", ".join(_text(v) for v in value[:16]) + f", ... ({len(value)} items)]"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_text(v) for v in value) + "]"
    return str(value)
