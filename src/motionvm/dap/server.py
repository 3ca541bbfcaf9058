"""`motionvm debug`: the Debug Adapter Protocol in front of the debug engine.

A face: it translates DAP requests to `motionvm.debug.DebugEngine` calls and the
engine's stops to DAP events, nothing more. Requests are read on the calling thread;
a request that runs the program (continue, next, stepIn, stepOut, stepBack,
reverseContinue, the custom `stepCycle {count}` and `goToTime {seconds}`) is answered
at once and run by a runner thread, whose stop becomes a `stopped` event (or `exited`
and `terminated` at the end of the run). The program's lines arrive as `output` events
(stdout), diagnostics and faults as `output` events (stderr); the exit code is that of
`motionvm run`. Launch arguments: `program` (a file or a list of files), `machine`,
`scenario`, `stopOnEntry`, `noDebug`, `cwd`. A custom `lastChange {expression}`
answers when a value last changed.
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Callable
from typing import BinaryIO

from motionvm.dap.protocol import BadMessage, ProtocolError, Writer, read_message
from motionvm.debug import BreakpointSpec, DebugEngine, ExpressionError, Stop
from motionvm.session import CompileFailed, RunSpec, Session, SessionError, Source

CAPABILITIES = {
    "supportsConfigurationDoneRequest": True,
    "supportsConditionalBreakpoints": True,
    "supportsHitConditionalBreakpoints": True,
    "supportsLogPoints": True,
    "supportsStepBack": True,
    "supportsSetVariable": True,
    "supportsEvaluateForHovers": True,
    "supportsDataBreakpoints": True,
    "supportsExceptionInfoRequest": True,
    "supportsTerminateRequest": True,
    "exceptionBreakpointFilters": [
        {"filter": "runtime", "label": "Runtime errors", "default": True},
        {"filter": "axis", "label": "Axis and group errors", "default": False},
    ],
}

_REASONS = {"goto": "goto", "data breakpoint": "data breakpoint"}
_MACHINE_REF = 1
"""The variables reference of the Machine scope."""


class DapServer:
    """One debug session over one connection (`serve`)."""

    def __init__(self, reader: BinaryIO, writer: BinaryIO) -> None:
        self.reader = reader
        self.out = Writer(writer)
        self.engine: DebugEngine | None = None
        self.launch_args: dict = {}
        self._runner: threading.Thread | None = None
        self._thread_ids: dict[tuple, int] = {}
        self._refs: dict[int, Callable[[], list[tuple[str, object]]]] = {}
        self._ref_kind: dict[int, tuple[str, int | None]] = {}
        self._done = False
        self._exit_sent = False
        self._no_debug = False
        self._running = False
        self._terminated = False

    # ---------------------------------------------------------------- the loop

    def serve(self) -> int:
        while not self._done:
            try:
                message = read_message(self.reader)
            except BadMessage as exc:  # framed right: the next message can be read
                self._stderr(f"motionvm debug: {exc} (skipped)")
                continue
            except ProtocolError as exc:
                self.out.event(
                    "output", {"category": "stderr", "output": f"motionvm debug: {exc}\n"}
                )
                break
            if message is None:
                break
            if message.get("type") != "request":
                continue
            self._handle(message)
        if self._runner is not None:
            self._runner.join(timeout=5)
        if self.engine is not None:
            self.engine.close()
        return 0

    def _handle(self, request: dict) -> None:
        command = str(request.get("command", ""))
        handler = getattr(self, "do_" + command, None)
        if handler is None:
            self.out.respond(request, error=f"unsupported request '{command}'")
            return
        args = request.get("arguments") or {}
        try:
            body = handler(args if isinstance(args, dict) else {}, request)
        except (SessionError, ExpressionError, KeyError, ValueError, IndexError, TypeError) as exc:
            text = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            self.out.respond(request, error=str(text))
            return
        except _Answered:
            return
        except Exception as exc:  # noqa: BLE001 — a request the adapter did not foresee
            self.out.respond(request, error=f"{command}: {type(exc).__name__}: {exc}")
            return
        self.out.respond(request, body)

    # ---------------------------------------------------------------- setup

    def do_initialize(self, args: dict, request: dict) -> dict:
        return CAPABILITIES

    def do_launch(self, args: dict, request: dict) -> dict:
        if self.engine is not None or self._no_debug:
            raise ValueError("launch: a program was launched already (disconnect first)")
        self.launch_args = args
        cwd = args.get("cwd")
        if cwd:
            if not os.path.isdir(str(cwd)):
                raise ValueError(f"launch: cwd '{cwd}' is not a folder")
            os.chdir(str(cwd))
        program = args.get("program")
        files = [program] if isinstance(program, str) else list(program or [])
        if not files:
            raise ValueError("launch: 'program' names no file")
        spec = RunSpec(
            [Source(str(f)) for f in files],
            machine=args.get("machine"),
            scenario=args.get("scenario"),
        )
        self._no_debug = bool(args.get("noDebug"))
        if self._no_debug:
            self.out.respond(request)
            self.out.event("initialized")
            self._spec = spec
            raise _Answered()
        try:
            self.engine = DebugEngine(spec, emit=self._stdout, report=self._stderr)
        except CompileFailed:
            self.out.respond(request, error="the program does not compile (see the output)")
            self._exit(2)
            raise _Answered() from None
        except SessionError as exc:
            self._stderr(str(exc))
            self.out.respond(request, error=str(exc))
            self._exit(3)
            raise _Answered() from None
        self.out.respond(request)
        self.out.event("initialized")
        raise _Answered()

    def do_configurationDone(self, args: dict, request: dict) -> dict:
        if not self._no_debug:
            self._engine()  # launched first
        if self._runner is not None:
            raise ValueError("configurationDone: the run has started already")
        self.out.respond(request)
        if self._no_debug:
            self._start_runner(self._run_plain)
        else:
            entry = bool(self.launch_args.get("stopOnEntry"))
            self._start_runner(lambda: self.engine.start(stop_on_entry=entry))
        raise _Answered()

    def _run_plain(self) -> Stop | None:
        """noDebug: the run as `motionvm run` makes it."""
        try:
            session = Session(self._spec, emit=self._stdout, report=self._stderr)
        except CompileFailed:
            self._exit(2)
            return None
        except SessionError as exc:
            self._stderr(str(exc))
            self._exit(3)
            return None
        try:
            session.run()
            code = 1 if session.fault_count else 0
        finally:
            session.close()
        self._exit(code)
        return None

    def do_disconnect(self, args: dict, request: dict) -> dict:
        self._done = True
        if self.engine is not None:
            self.engine.pause()
        return {}

    def do_terminate(self, args: dict, request: dict) -> dict:
        self.out.respond(request)  # the client's `disconnect` comes next: it ends the loop
        self._terminated = True
        if self.engine is not None:
            self.engine.pause()
        self._exit(self.engine.exit_code if self.engine else 0)
        raise _Answered()

    # ---------------------------------------------------------------- breakpoints

    def do_setBreakpoints(self, args: dict, request: dict) -> dict:
        path = (args.get("source") or {}).get("path", "")
        specs = [
            BreakpointSpec(
                int(b["line"]),
                b.get("condition") or None,
                b.get("hitCondition") or None,
                b.get("logMessage"),
            )  # fmt: skip
            for b in args.get("breakpoints") or []
        ]
        bps = self._engine().set_breakpoints(path, specs)
        return {
            "breakpoints": [
                {
                    "id": b.id,
                    "verified": b.verified,
                    "line": b.line,
                    "source": {"path": path},
                    **({"message": b.message} if b.message else {}),
                }  # fmt: skip
                for b in bps
            ]
        }

    def do_setExceptionBreakpoints(self, args: dict, request: dict) -> dict:
        filters = args.get("filters") or []
        if not isinstance(filters, list):
            raise ValueError("setExceptionBreakpoints: 'filters' must be a list")
        self._engine().set_exception_filters([str(f) for f in filters])
        return {}

    def do_dataBreakpointInfo(self, args: dict, request: dict) -> dict:
        name = str(args.get("name", ""))
        return {"dataId": name, "description": f"{name} changes", "accessTypes": ["write"],
                "canPersist": True}  # fmt: skip

    def do_setDataBreakpoints(self, args: dict, request: dict) -> dict:
        ids = [str(b.get("dataId")) for b in args.get("breakpoints") or []]
        found = self._engine().set_data_breakpoints(ids)
        return {
            "breakpoints": [
                {"verified": ok, **({"message": m} if m else {})} for _e, ok, m in found
            ]
        }

    # ---------------------------------------------------------------- running

    def do_continue(self, args: dict, request: dict) -> dict:
        self._run_request(request, lambda e: e.resume())
        return {"allThreadsContinued": True}

    def do_next(self, args: dict, request: dict) -> dict:
        return self._step(args, request, "over")

    def do_stepIn(self, args: dict, request: dict) -> dict:
        return self._step(args, request, "in")

    def do_stepOut(self, args: dict, request: dict) -> dict:
        return self._step(args, request, "out")

    def _step(self, args: dict, request: dict, kind: str) -> dict:
        key = self._key_of(args.get("threadId"))
        self._run_request(request, lambda e: e.step(kind, key))
        return {}

    def do_stepBack(self, args: dict, request: dict) -> dict:
        self._run_request(request, lambda e: e.step_back())
        return {}

    def do_reverseContinue(self, args: dict, request: dict) -> dict:
        self._run_request(request, lambda e: e.reverse_continue())
        return {}

    def do_stepCycle(self, args: dict, request: dict) -> dict:
        count = int(args.get("count", 1))
        if count < 1:
            raise ValueError(f"stepCycle: count must be 1 or more, got {count}")
        self._run_request(request, lambda e: e.step_cycle(count))
        return {}

    def do_goToTime(self, args: dict, request: dict) -> dict:
        seconds = float(args.get("seconds", 0.0))
        if not (seconds >= 0 and math.isfinite(seconds)):
            raise ValueError(f"goToTime: seconds must be >= 0, got {seconds}")
        self._run_request(request, lambda e: e.go_to_time(seconds))
        return {}

    def do_pause(self, args: dict, request: dict) -> dict:
        engine = self._engine()
        if self._running:  # paused already: nothing to stop (the next run would stop at once)
            engine.pause()
        return {}

    def do_lastChange(self, args: dict, request: dict) -> dict:
        self._paused()
        found = self._engine().last_change(str(args.get("expression", "")))
        if found is None:
            return {"changed": False}
        t, before, after = found
        return {"changed": True, "time": t, "before": _text(before), "after": _text(after)}

    def _run_request(self, request: dict, call: Callable[[DebugEngine], Stop]) -> None:
        self._paused()
        engine = self._engine()
        self.out.respond(
            request, {"allThreadsContinued": True} if request.get("command") == "continue" else {}
        )
        self._start_runner(lambda: call(engine))
        raise _Answered()

    def _start_runner(self, call: Callable[[], Stop | None]) -> None:
        def run() -> None:
            try:
                stop = call()
            except Exception as exc:  # noqa: BLE001 — shown, the session goes on paused
                self._running = False
                self._stderr(f"motionvm debug: {exc}")
                return
            self._running = False
            if stop is not None:
                self._stopped(stop)

        self._running = True
        self._runner = threading.Thread(target=run, name="motionvm-dap-run", daemon=True)
        self._runner.start()

    def _paused(self) -> None:
        if self._terminated:
            raise ValueError("the debug session was terminated")
        if self._running:
            raise ValueError("the program is running (pause it first)")

    def _stopped(self, stop: Stop) -> None:
        if self._terminated:
            return
        self._refs.clear()
        self._ref_kind.clear()
        if stop.reason == "exited" and not self._exit_sent:
            self._exit(self.engine.exit_code)
            return
        body = {
            "reason": _REASONS.get(stop.reason, stop.reason),
            "description": f"{stop.reason} at t={stop.time:.6f} s (cycle {stop.position.cycle})",
            "allThreadsStopped": True,
            "threadId": self._thread_id(stop.thread) if stop.thread else self._any_thread(),
        }
        if stop.text:
            body["text"] = stop.text
        if stop.breakpoints:
            body["hitBreakpointIds"] = list(stop.breakpoints)
        self.out.event("stopped", body)

    def _exit(self, code: int) -> None:
        if self._exit_sent:
            return
        self._exit_sent = True
        self.out.event("exited", {"exitCode": code})
        self.out.event("terminated")

    # ---------------------------------------------------------------- inspection

    def do_threads(self, args: dict, request: dict) -> dict:
        if self.engine is None or self._running:
            return {"threads": [{"id": 1, "name": "controller"}]}
        threads = [{"id": self._thread_id(t.key), "name": t.name} for t in self.engine.threads()]
        return {"threads": threads or [{"id": 1, "name": "controller"}]}

    def do_stackTrace(self, args: dict, request: dict) -> dict:
        self._paused()
        key = self._key_of(args.get("threadId"))
        frames = self._engine().stack(key) if key is not None else []
        out = [
            {
                "id": f.id,
                "name": f.name,
                "line": f.line,
                "column": 1,
                "source": {"name": os.path.basename(f.file), "path": os.path.abspath(f.file)},
            }  # fmt: skip
            for f in frames
        ]
        first = max(0, int(args.get("startFrame") or 0))
        levels = int(args.get("levels") or 0)  # 0: all
        shown = out[first : first + levels] if levels > 0 else out[first:]
        return {"stackFrames": shown, "totalFrames": len(out)}

    def do_scopes(self, args: dict, request: dict) -> dict:
        self._paused()
        engine = self._engine()
        fid = int(args.get("frameId", 0))
        scopes = [
            {"name": "Machine", "variablesReference": self._machine_ref(), "expensive": False}
        ]
        try:
            frame = engine.frame(fid)
        except KeyError:
            return {"scopes": scopes}
        local_ref = self._new_ref(
            lambda: sorted(engine.locals_of(frame.python).items()), ("local", fid)
        )
        glob_ref = self._new_ref(
            lambda: sorted(engine.globals_of(frame.python).items()), ("global", fid)
        )
        return {
            "scopes": [
                {"name": "Locals", "variablesReference": local_ref, "expensive": False},
                {"name": "Globals", "variablesReference": glob_ref, "expensive": False},
                *scopes,
            ]
        }

    def _machine_ref(self) -> int:
        engine = self._engine()

        def machine():
            view = engine.machine_view()
            return [(group, values) for group, values in view.items()]

        self._refs[_MACHINE_REF] = machine
        self._ref_kind[_MACHINE_REF] = ("machine", None)
        return _MACHINE_REF

    def _new_ref(self, items: Callable[[], list[tuple[str, object]]], kind: tuple) -> int:
        ref = max([_MACHINE_REF, *self._refs]) + 1
        self._refs[ref] = items
        self._ref_kind[ref] = kind
        return ref

    def do_variables(self, args: dict, request: dict) -> dict:
        self._paused()
        ref = int(args.get("variablesReference", 0))
        items = self._refs.get(ref)
        if items is None:
            return {"variables": []}
        kind = self._ref_kind.get(ref, ("value", None))
        out = []
        for name, value in items():
            child = 0
            if isinstance(value, dict):
                child = self._new_ref(lambda v=value: list(v.items()), ("machine", None))
            elif isinstance(value, list | tuple):
                child = self._new_ref(
                    lambda v=value, n=name: [(f"[{i}]", x) for i, x in enumerate(v)], ("item", None)
                )
                value = f"array[{len(value)}]"
            out.append({"name": str(name), "value": _text(value), "variablesReference": child,
                        "evaluateName": str(name) if kind[0] != "item" else ""})  # fmt: skip
        return {"variables": out}

    def do_setVariable(self, args: dict, request: dict) -> dict:
        self._paused()
        engine = self._engine()
        ref = int(args.get("variablesReference", 0))
        name = str(args.get("name", ""))
        value = _parse_value(str(args.get("value", "")))
        kind, fid = self._ref_kind.get(ref, ("machine", None))
        if kind == "global":
            engine.set_value(engine.global_channel(name, fid), value)
        else:
            engine.set_value(name, value, fid if kind == "local" else None)
        shown = engine.evaluate(name, fid) if kind != "machine" else value
        return {"value": _text(shown)}

    def do_evaluate(self, args: dict, request: dict) -> dict:
        self._paused()
        fid = args.get("frameId")
        value = self._engine().evaluate(str(args.get("expression", "")), fid)
        return {"result": _text(value), "variablesReference": 0}

    def do_exceptionInfo(self, args: dict, request: dict) -> dict:
        stop = self._engine().stop
        text = stop.text if stop is not None else ""
        kind = "axis" if text.startswith("axis ") else "runtime"
        return {"exceptionId": kind, "description": text, "breakMode": "always"}

    # ---------------------------------------------------------------- helpers

    def _engine(self) -> DebugEngine:
        if self.engine is None:
            raise ValueError("no program was launched")
        return self.engine

    def _thread_id(self, key: tuple) -> int:
        if key not in self._thread_ids:
            self._thread_ids[key] = len(self._thread_ids) + 2
        return self._thread_ids[key]

    def _any_thread(self) -> int:
        threads = self.engine.threads() if self.engine else []
        return self._thread_id(threads[0].key) if threads else 1

    def _key_of(self, thread_id) -> tuple | None:
        for key, tid in self._thread_ids.items():
            if tid == thread_id:
                return key
        return None

    def _stdout(self, line: str) -> None:
        self.out.event("output", {"category": "stdout", "output": line + "\n"})

    def _stderr(self, line: str) -> None:
        self.out.event("output", {"category": "stderr", "output": str(line) + "\n"})


class _Answered(Exception):
    """The handler answered the request itself."""


def _parse_value(text: str) -> object:
    t = text.strip()
    if t.upper() in ("ON", "TRUE"):
        return 1
    if t.upper() in ("OFF", "FALSE"):
        return 0
    try:
        return int(t, 0)
    except ValueError:
        pass
    try:
        return float(t)
    except ValueError:
        raise ValueError(f"'{text}' is not a number") from None


def _text(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int) and value.bit_length() > 64:
        return f"an integer of {value.bit_length()} bits"
    return str(value)


def serve_stdio() -> int:
    import sys

    return DapServer(sys.stdin.buffer, sys.stdout.buffer).serve()


def serve_tcp(port: int, ready: Callable[[int], None] | None = None) -> int:
    """Listen on 127.0.0.1:`port` (0: a free one), serve one client, then end."""
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as listener:
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listener.bind(("127.0.0.1", port))
        listener.listen(1)
        if ready is not None:
            ready(listener.getsockname()[1])
        conn, _addr = listener.accept()
        with conn:
            stream = conn.makefile("rwb", buffering=0)
            return DapServer(stream, stream).serve()
