"""The controller's communication hub: where the network meets the simulation's cycle.

Every effect a server has on the simulation happens inside the simulation thread at a
cycle boundary: a server thread `post`s a function and waits for its future; the hub,
a cycle client (runtime/clients.py) added first, runs the posted functions in
`begin_cycle`, in arrival order, before anything else of the cycle. So a request sees
the state the previous cycle left and its effect is seen by the whole next cycle.

The upper layers plug in through declared protocols (the session wires them):
- `NativeTable`: runs one Native ASCII request (a built-in call or a variable access)
  exactly as if a task had called it;
- `VariableTable`: reads and writes named controller variables (`system_ltest0`, ...);
- `AsciiAgentPort`: the program's User ASCII parser (START_ASCII_AGENT).

The client built-ins (ASCII and Modbus TCP clients) run their network work as a `Job`:
in an unpaced run at once, in the simulation thread (the simulated clock does not move
while the call waits, so a deterministic peer gives a deterministic run); in a paced run
on a worker thread while the calling task waits at a yield, taking the time the network
takes.
"""

from __future__ import annotations

import collections
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol

from motionvm.comm.config import CommConfig
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.clock import Clock

if TYPE_CHECKING:  # concurrent.futures costs 20 ms of every run's start: imported when used
    import concurrent.futures


class NativeTable(Protocol):
    """Runs Native ASCII requests (comm/native.py parses them) in the simulation thread."""

    def native_call(self, name: str, args: list) -> str:
        """The reply line of calling built-in `name` with literal `args` (without `\\r\\n`);
        raises `RequestError` for a request that cannot run."""
        ...

    def native_read(self, name: str) -> str:
        """The value of variable `name`, as a reply line."""
        ...

    def native_write(self, name: str, value: object) -> str:
        """Store `value` in variable `name`; the reply line (`OK`)."""
        ...

    def native_is_query(self, name: str, args: list) -> bool:
        """Whether calling built-in `name` with `args` only reads the machine (a
        read-only server serves nothing else)."""
        ...


class VariableTable(Protocol):
    """Named numeric variables of the controller (the Modbus register map's)."""

    def read_variable(self, name: str) -> int | float: ...

    def write_variable(self, name: str, value: int | float) -> None: ...


class AsciiAgentPort(Protocol):
    """The User ASCII parser of the running program."""

    def accept(self, line: str, reply: concurrent.futures.Future) -> None:
        """Queue `line` for the parser; `reply.set_result(text)` once it has answered."""
        ...


FIRST_SOCKET_ID = 10
"""The first client socket id of each kind (the manual's examples use socket 10)."""


class RequestError(Exception):
    """A request that cannot run: its reply is `ERR <message>`."""


class _Variables:
    """The test variables when no program provides them: system_ltest0..9 (int32) and
    system_dtest0..9 (double), all 0 at start."""

    def __init__(self) -> None:
        self.values: dict[str, int | float] = {f"system_ltest{i}": 0 for i in range(10)}
        self.values.update({f"system_dtest{i}": 0.0 for i in range(10)})

    def read_variable(self, name: str) -> int | float:
        return self.values[name]

    def write_variable(self, name: str, value: int | float) -> None:
        self.values[name] = value


class Job:
    """A client built-in's network work: `done()` once it has a result."""

    def __init__(self, future: concurrent.futures.Future) -> None:
        self._future = future

    def done(self) -> bool:
        return self._future.done()

    def result(self):
        return self._future.result()


class CommHub(PassiveClient):
    """The controller's communication state; a cycle client (see the module docstring)."""

    def __init__(self, clock: Clock, io, motion) -> None:
        self.clock = clock
        self.io = io
        """The controller's digital I/O (io/gpio.py)."""
        self.motion = motion
        """The motion kernel (its `axes`)."""
        self.config = CommConfig()
        """Ports, address and client timeout (the machine file's `[comm]`)."""
        self.native: NativeTable | None = None
        self.variables: VariableTable = _Variables()
        self.agent: AsciiAgentPort | None = None
        self._serving = False
        self.paced = False
        """The run is paced to the wall clock: client built-ins take network time."""
        self._inbox: collections.deque = collections.deque()
        self._broadcast: Callable[[bytes], None] | None = None
        self._pool: concurrent.futures.ThreadPoolExecutor | None = None
        self._lock = threading.Lock()
        self.sockets: dict[str, dict[int, object]] = {"ascii": {}, "modbus": {}}
        """Client connections of the built-ins by kind, then socket id."""
        self.busy_sockets: set[tuple[str, int]] = set()
        """(kind, id) of the client sockets with a job in flight."""

    @property
    def serving(self) -> bool:
        """Servers are listening: the run goes on after every task has ended."""
        return self._serving

    @serving.setter
    def serving(self, on: bool) -> None:
        self._serving = on
        self.work_changed()

    def has_work(self, hook: str) -> bool:
        """`begin_cycle` has work while servers listen or a posted function waits
        (runtime/clients.py): `post` tells the controller."""
        return self._serving or bool(self._inbox)

    @property
    def observes_motion(self) -> bool:
        """While servers listen, a request may read the axes at any cycle."""
        return self.serving

    # ------------------------------------------------------------ server side

    def post(self, fn: Callable[[], object]) -> concurrent.futures.Future:
        """Run `fn()` in the simulation thread at the next cycle boundary (any thread may
        call this); the future holds its result or its exception."""
        import concurrent.futures

        fut: concurrent.futures.Future = concurrent.futures.Future()
        self._inbox.append((fn, fut))
        self.work_changed()  # after the append: the controller then sees it (any thread)
        return fut

    def begin_cycle(self) -> None:
        inbox = self._inbox
        while inbox:
            fn, fut = inbox.popleft()
            if not fut.set_running_or_notify_cancel():
                continue
            try:
                fut.set_result(fn())
            except Exception as exc:  # noqa: BLE001 — handed to the waiting server
                fut.set_exception(exc)
        if not self._serving:
            self.work_changed()  # idle again (a post meanwhile is seen when taken again)

    def busy(self) -> bool:
        return self.serving

    def next_event(self) -> int | None:
        if self.serving or self._inbox:
            return self.clock.cycle
        return None

    def set_broadcast(self, send: Callable[[bytes], None] | None) -> None:
        """The User ASCII server's send-to-every-client (None: no server listens)."""
        self._broadcast = send

    def broadcast(self, data: bytes) -> None:
        """ASCII_ServerBroadcast: send `data` to every connected User ASCII client; nothing
        when no server listens or no client is connected."""
        send = self._broadcast
        if send is not None:
            send(data)

    # ------------------------------------------------------------ client side

    def start_job(self, fn: Callable[[], object]) -> Job:
        """Run `fn` (blocking network work) now in an unpaced run, else on a worker thread."""
        import concurrent.futures

        fut: concurrent.futures.Future = concurrent.futures.Future()
        if not self.paced:
            fut.set_running_or_notify_cancel()
            try:
                fut.set_result(fn())
            except Exception as exc:  # noqa: BLE001 — raised again by Job.result()
                fut.set_exception(exc)
            return Job(fut)
        with self._lock:
            if self._pool is None:
                self._pool = concurrent.futures.ThreadPoolExecutor(
                    max_workers=4, thread_name_prefix="motionvm-client"
                )
            return Job(self._pool.submit(fn))

    def add_socket(self, kind: str, sock: object, limit: int) -> int | None:
        """Register a connected client socket; its id (from FIRST_SOCKET_ID), None at
        `limit`."""
        table = self.sockets[kind]
        if len(table) >= limit:
            return None
        sid = FIRST_SOCKET_ID
        while sid in table:
            sid += 1
        table[sid] = sock
        return sid

    def close(self) -> None:
        """Close every client socket and the worker threads (the run is over)."""
        for table in self.sockets.values():
            for sock in table.values():
                try:
                    sock.close()  # type: ignore[attr-defined]
                except OSError:
                    pass
            table.clear()
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = None
