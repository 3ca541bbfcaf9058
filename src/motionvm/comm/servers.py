"""The controller's three TCP servers on one asyncio event loop in a background thread.

    servers = CommServers(hub, config)       # config: the machine file's [comm]
    ports = servers.start()                  # {"native-ascii": 3999, "user-ascii": 4000, "modbus": 502}
    ...                                      # the simulation runs, paced, in its own thread
    servers.stop()

The server thread never touches the simulation: it parses lines and frames and hands
the work to the simulation thread through the hub (comm/hub.py), whose futures it
awaits. Native ASCII (comm/native.py) replies with a built-in's results; User ASCII
passes each line to the program's parser (START_ASCII_AGENT) and sends back what it
wrote; Modbus TCP serves the register map (comm/modbus_map.py). The config's access
rules apply to each: the idle timeout to all three, the token to both ASCII servers
(comm/gate.py), read-only mode to Native ASCII (comm/native.py) and Modbus.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import os
import threading

from motionvm.comm import native
from motionvm.comm.config import CommConfig
from motionvm.comm.hub import CommHub
from motionvm.comm.lineserver import LineServer

SERVER_NAMES = ("native-ascii", "user-ascii", "modbus")
NO_AGENT = "ERR no ASCII agent is running (the program calls START_ASCII_AGENT)"


class CommError(Exception):
    """A server could not start (its port is taken, the address does not exist)."""


class CommServers:
    """Native ASCII, User ASCII and Modbus TCP servers of one hub."""

    def __init__(self, hub: CommHub, config: CommConfig | None = None) -> None:
        self.hub = hub
        self.config = config or hub.config
        self.ports: dict[str, int] = {}
        """Bound port of each server, by name (SERVER_NAMES)."""
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._servers: list = []

    def start(self) -> dict[str, int]:
        """Start listening; the bound ports. CommError if a server cannot listen."""
        ready: concurrent.futures.Future = concurrent.futures.Future()
        self._thread = threading.Thread(
            target=self._thread_main, args=(ready,), name="motionvm-servers", daemon=True
        )
        self._thread.start()
        try:
            self.ports = ready.result(timeout=30)
        except CommError:
            self._thread.join(timeout=5)
            raise
        self.hub.serving = True
        return self.ports

    def stop(self) -> None:
        """Close every server and connection; the hub stops serving. Idempotent."""
        self.hub.serving = False
        self.hub.set_broadcast(None)
        loop, thread = self._loop, self._thread
        if loop is None or thread is None:
            return
        self._loop = None
        try:
            asyncio.run_coroutine_threadsafe(self._stop_all(), loop).result(timeout=5)
        except (concurrent.futures.TimeoutError, RuntimeError):
            pass
        loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout=5)

    def __enter__(self) -> CommServers:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # ------------------------------------------------------------ server thread

    def _thread_main(self, ready: concurrent.futures.Future) -> None:
        loop = asyncio.new_event_loop()
        asyncio.set_event_loop(loop)
        try:
            ports = loop.run_until_complete(self._start_all())
        except OSError as exc:
            loop.run_until_complete(self._stop_all())
            loop.close()
            ready.set_exception(CommError(str(exc)))
            return
        self._loop = loop
        ready.set_result(ports)
        try:
            loop.run_forever()
        finally:
            for task in asyncio.all_tasks(loop):
                task.cancel()
            loop.run_until_complete(asyncio.sleep(0))
            loop.close()

    async def _start_all(self) -> dict[str, int]:
        from motionvm.comm.modbus_server import ModbusServer  # pymodbus: only when serving

        cfg = self.config
        native_srv = LineServer(
            "native-ascii", self._native, token=cfg.token, idle_timeout=cfg.idle_timeout
        )
        user_srv = LineServer(
            "user-ascii", self._user, token=cfg.token, idle_timeout=cfg.idle_timeout
        )
        modbus_srv = ModbusServer(
            self.hub, read_only=cfg.read_only("modbus"), idle_timeout=cfg.idle_timeout
        )
        ports: dict[str, int] = {}
        for name, srv, port in (
            ("native-ascii", native_srv, cfg.native_ascii_port),
            ("user-ascii", user_srv, cfg.user_ascii_port),
            ("modbus", modbus_srv, cfg.modbus_port),
        ):
            try:
                ports[name] = await srv.start(cfg.bind, port)
            except OSError as exc:
                why = os.strerror(exc.errno) if exc.errno else str(exc)
                raise OSError(f"{name} server cannot listen on {cfg.bind}:{port}: {why}") from None
            except RuntimeError as exc:  # pymodbus: "Could not start listen"
                raise OSError(f"{name} server cannot listen on {cfg.bind}:{port}: {exc}") from None
            self._servers.append(srv)
        loop = asyncio.get_running_loop()
        self.hub.set_broadcast(lambda data: loop.call_soon_threadsafe(user_srv.send_all, data))
        return ports

    async def _stop_all(self) -> None:
        for srv in self._servers:
            try:
                await srv.stop()
            except Exception:  # noqa: BLE001 — closing anyway
                pass
        self._servers = []

    async def _native(self, line: str) -> str:
        req = native.handle_line(line)
        if isinstance(req, str):
            return req
        hub = self.hub
        read_only = self.config.read_only("native-ascii")
        return await asyncio.wrap_future(hub.post(lambda: native.execute(hub, req, read_only)))

    async def _user(self, line: str) -> str:
        hub = self.hub
        reply: concurrent.futures.Future = concurrent.futures.Future()

        def accept() -> None:
            if hub.agent is None:
                reply.set_result(NO_AGENT)
            else:
                hub.agent.accept(line, reply)

        await asyncio.wrap_future(hub.post(accept))
        return await asyncio.wrap_future(reply)
