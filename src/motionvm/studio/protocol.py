"""The studio's protocol: JSON-RPC 2.0 style messages over one WebSocket (docs/studio.md).

A request `{"jsonrpc": "2.0", "id": 7, "method": "run.start", "params": {...}}` gets one
answer with the same id: `{"jsonrpc": "2.0", "id": 7, "result": ...}` or `{"jsonrpc":
"2.0", "id": 7, "error": {"code": -32000, "message": "..."}}`. The server sends
notifications (no id) to every connected page: `state`, `console`, `scope`, `panels`,
`stopped`, `reset`, `diagnostics`. This module maps each method to the run and the
workspace; it decides nothing itself.
"""

from __future__ import annotations

import asyncio
import json
import math
from collections.abc import Awaitable, Callable

from motionvm import __version__
from motionvm.studio.run import StudioError, StudioRun
from motionvm.studio.workspace import Workspace, WorkspaceError, diagnostics

PARSE_ERROR, INVALID_REQUEST, NO_METHOD, BAD_PARAMS, INTERNAL, REFUSED = (
    -32700,
    -32600,
    -32601,
    -32602,
    -32603,
    -32000,
)
"""JSON-RPC error codes; REFUSED: a request the run cannot do now (the message says why);
INTERNAL: a failure of the studio itself (the request is answered all the same)."""

Send = Callable[[str], Awaitable[None]]


class Studio:
    """The files, the run and the connected pages of one `motionvm studio`."""

    def __init__(self, files: list[str], machine: str | None = None, scenario: str | None = None):
        self.workspace = Workspace(files)
        self.pages: set[Send] = set()
        self.run = StudioRun(self.workspace, self.broadcast, machine=machine, scenario=scenario)
        self._methods: dict[str, Callable[[dict], Awaitable[object]]] = {
            "studio.hello": self.hello,
            "file.open": self.file_open,
            "file.edit": self.file_edit,
            "file.save": self.file_save,
            "run.start": lambda p: self.run.run(),
            "run.pause": lambda p: self.run.pause(),
            "run.step_cycle": lambda p: self.run.step_cycle(int(p.get("count", 1))),
            "run.reset": lambda p: self.run.reset(),
            "run.to_time": lambda p: self.run.run(float(p["seconds"])),
            "run.speed": self.speed,
            "run.seek": self.seek,
            "breakpoints.set": lambda p: self.run.set_breakpoints(
                self.workspace.get(str(p["path"])).path, list(p.get("lines") or [])
            ),
            "io.force": lambda p: self.run.force(str(p["name"]), _value(p["value"])),
            "debug.threads": lambda p: self.run.threads(),
            "debug.stack": lambda p: self.run.stack(str(p["thread"])),
            "debug.variables": lambda p: self.run.variables(_opt_int(p.get("frame"))),
            "debug.evaluate": lambda p: self.run.evaluate(
                str(p["expression"]), _opt_int(p.get("frame"))
            ),
            "scope.channels": lambda p: self.run.channels(),
            "scope.select": lambda p: self.run.select_scope(
                None if p["channels"] is None else [str(c) for c in p["channels"]]
            ),
            "history.at": self.history_at,
        }

    async def start(self) -> None:
        """Compile and boot the run (paused at t = 0)."""
        await self.run.reset()

    async def close(self) -> None:
        await self.run.close()

    # ---------------------------------------------------------------- connections

    async def broadcast(self, method: str, params: dict) -> None:
        text = json.dumps({"jsonrpc": "2.0", "method": method, "params": params})
        for send in list(self.pages):
            try:
                await send(text)
            except Exception:  # noqa: BLE001 — a page that went away
                self.pages.discard(send)

    async def handle(self, text: str) -> str | None:
        """The answer to one message (None for a notification from the page)."""
        try:
            message = json.loads(text)
        except ValueError:
            return _error(None, PARSE_ERROR, "not JSON")
        if not isinstance(message, dict) or not isinstance(message.get("method"), str):
            return _error(message.get("id") if isinstance(message, dict) else None,
                          INVALID_REQUEST, "a request needs a method")  # fmt: skip
        rid = message.get("id")
        method = self._methods.get(message["method"])
        if method is None:
            return _error(rid, NO_METHOD, f"unknown method '{message['method']}'")
        params = message.get("params") or {}
        if not isinstance(params, dict):
            return _error(rid, BAD_PARAMS, "params must be an object")
        try:
            result = await method(params)
        except (StudioError, WorkspaceError) as exc:
            return _error(rid, REFUSED, str(exc))
        except (KeyError, TypeError, ValueError, OverflowError) as exc:
            what = f"missing parameter {exc}" if isinstance(exc, KeyError) else str(exc)
            return _error(rid, BAD_PARAMS, f"{message['method']}: {what}")
        except Exception as exc:  # noqa: BLE001 — answered: the page waits for every answer
            return _error(rid, INTERNAL, f"{message['method']}: {type(exc).__name__}: {exc}")
        if rid is None:
            return None
        return json.dumps({"jsonrpc": "2.0", "id": rid, "result": result})

    # ---------------------------------------------------------------- methods

    async def hello(self, params: dict) -> dict:
        return {"version": __version__, **self.run.describe()}

    async def file_open(self, params: dict) -> dict:
        f = self.workspace.open(str(params["path"]))
        found = await asyncio.to_thread(diagnostics, f.path, f.text)
        return {"path": f.path, "language": f.language, "text": f.text, "dirty": f.dirty,
                "diagnostics": found}  # fmt: skip

    async def file_edit(self, params: dict) -> dict:
        f = self.workspace.edit(str(params["path"]), _string(params, "text"))
        found = await asyncio.to_thread(diagnostics, f.path, f.text)
        await self.broadcast("diagnostics", {"path": f.path, "items": found})
        return {"path": f.path, "dirty": f.dirty, "diagnostics": found}

    async def file_save(self, params: dict) -> dict:
        path = str(params["path"])
        if "text" in params:
            self.workspace.edit(path, _string(params, "text"))
        f = self.workspace.save(path)
        return {"path": f.path, "dirty": f.dirty}

    async def speed(self, params: dict) -> dict:
        factor = params.get("factor")
        return self.run.set_speed(None if factor is None else float(factor))

    async def seek(self, params: dict) -> dict:
        if "cycle" in params:
            return await self.run.seek(int(params["cycle"]))
        engine = self.run.engine
        dt = engine.controller.cycle_time if engine is not None else 0.001
        return await self.run.seek(_cycle(params["time"], dt))

    async def history_at(self, params: dict) -> dict:
        span = params.get("span")
        if "cycle" in params:
            cycle = int(params["cycle"])
        else:
            history = self.run.history
            dt = history.cycle_time if history is not None else 0.001
            cycle = _cycle(params["time"], dt)
        return self.run.at(cycle, None if span is None else float(span))


def _error(rid, code: int, message: str) -> str:
    return json.dumps({"jsonrpc": "2.0", "id": rid, "error": {"code": code, "message": message}})


def _string(params: dict, name: str) -> str:
    value = params[name]
    if not isinstance(value, str):
        raise ValueError(f"'{name}' must be a string")
    return value


def _cycle(seconds, cycle_time: float) -> int:
    """The cycle at a time [s] (0 for a time before 0)."""
    cycles = max(0.0, float(seconds)) / cycle_time
    if not math.isfinite(cycles):
        raise ValueError(f"time {seconds} s is beyond any run")
    return round(cycles)


def _opt_int(value) -> int | None:
    return None if value is None else int(value)


def _value(value) -> object:
    """A forced value: a number, true/false, or "ON"/"OFF"."""
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int | float):
        return value
    text = str(value).strip().upper()
    if text in ("ON", "TRUE"):
        return 1
    if text in ("OFF", "FALSE"):
        return 0
    try:
        return float(text) if any(c in text for c in ".E") else int(text, 0)
    except ValueError:
        raise ValueError(f"'{value}' is not a value (a number, ON or OFF)") from None
