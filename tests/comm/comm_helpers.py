"""Helpers of the communication tests: served programs, line clients, a Modbus peer.

Everything talks over real loopback sockets (127.0.0.1) on free ports; every wait is
bounded in wall time (`WAIT`), every loop in count.
"""

from __future__ import annotations

import asyncio
import contextlib
import socket
import threading
import time
from collections.abc import Iterator

from motionvm.api import Simulation

WAIT = 30.0
"""The longest any test waits for one reply [s wall]: a bound, not an expectation (a
reply takes milliseconds; a CI machine running two test workers can stall a few
seconds)."""


class LineClient:
    """A raw TCP client of an ASCII server: send lines, read `\\r\\n`-ended replies."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
        self.buf = b""

    def send(self, data: bytes) -> None:
        self.sock.sendall(data)

    def line(self) -> str:
        """The next reply line, without its `\\r\\n`."""
        while b"\r\n" not in self.buf:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError(f"closed; pending {self.buf!r}")
            self.buf += chunk
        line, _, self.buf = self.buf.partition(b"\r\n")
        return line.decode("latin-1")

    def ask(self, request: str) -> str:
        self.send(request.encode("latin-1") + b"\r\n")
        return self.line()

    def close(self) -> None:
        self.sock.close()

    def rest(self) -> bytes:
        """Everything the server sends until it closes the connection (bounded by WAIT
        per read and by 64 KiB)."""
        data = self.buf
        while len(data) < 65536:
            chunk = self.sock.recv(4096)
            if not chunk:
                return data
            data += chunk
        raise AssertionError(f"still open after {len(data)} bytes")


@contextlib.contextmanager
def served(text: str, access: dict | None = None, **kw) -> Iterator[tuple[Simulation, object]]:
    """A one-task HMPL program served on free loopback ports: (simulation, Serving);
    `access`: `[comm]` keys for `Simulation.serve` (token, idle_timeout, ...)."""
    sim = Simulation.from_source(text, **kw)
    try:
        with sim.serve(**(access or {})) as srv:
            yield sim, srv
    finally:
        sim.close()


@contextlib.contextmanager
def modbus_peer() -> Iterator[int]:
    """A pymodbus TCP server on a free loopback port (its port): coils and discrete
    inputs 0-99, holding and input registers 0-99 (holding 0x1234, input 7, discrete
    inputs on); any unit id."""
    from pymodbus.server import ModbusTcpServer
    from pymodbus.simulator import DataType, SimData, SimDevice

    box: dict = {}
    ready = threading.Event()
    loop = asyncio.new_event_loop()

    async def start() -> None:
        device = SimDevice(
            id=0,
            simdata=(
                [SimData(0, count=100, values=False, datatype=DataType.BITS)],
                [SimData(0, count=100, values=True, datatype=DataType.BITS)],
                [SimData(0, count=100, values=0x1234, datatype=DataType.REGISTERS)],
                [SimData(0, count=100, values=7, datatype=DataType.REGISTERS)],
            ),
        )
        server = ModbusTcpServer(device, address=("127.0.0.1", 0))
        await server.serve_forever(background=True)
        box["server"] = server
        box["port"] = server.transport.sockets[0].getsockname()[1]

    def main() -> None:
        asyncio.set_event_loop(loop)
        loop.run_until_complete(start())
        ready.set()
        loop.run_forever()
        loop.run_until_complete(box["server"].shutdown())
        loop.close()

    thread = threading.Thread(target=main, daemon=True)
    thread.start()
    assert ready.wait(WAIT)
    try:
        yield box["port"]
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(WAIT)


@contextlib.contextmanager
def line_peer(
    replies: dict[bytes, bytes] | None = None, delay: float = 0.0
) -> Iterator[tuple[int, list[bytes]]]:
    """A raw TCP server on a free loopback port for the ASCII client functions: it
    records what it receives and answers each received chunk found in `replies`, after
    `delay` seconds [wall]; it sends `hello` on connect. Yields (port, received chunks)."""
    replies = replies or {}
    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(WAIT)
    port = listener.getsockname()[1]
    received: list[bytes] = []
    stop = threading.Event()

    def main() -> None:
        try:
            conn, _ = listener.accept()
        except OSError:
            return
        with conn:
            conn.settimeout(0.2)
            conn.sendall(b"hello")
            for _ in range(200):  # bounded: at most 200 * 0.2 s
                try:
                    data = conn.recv(4096)
                except TimeoutError:  # nothing pending: only now may the peer stop,
                    if stop.is_set():  # so what was sent before the stop is kept
                        return
                    continue
                except OSError:
                    return
                if not data:
                    return
                received.append(data)
                if data in replies:
                    time.sleep(delay)
                    conn.sendall(replies[data])

    thread = threading.Thread(target=main, daemon=True)
    thread.start()
    try:
        yield port, received
    finally:
        stop.set()
        listener.close()
        thread.join(WAIT)


def free_port() -> int:
    """A loopback port that nothing listens on (bound, then released)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
