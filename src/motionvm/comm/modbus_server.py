"""The Modbus TCP server: pymodbus's framing and function codes on the register map.

pymodbus decodes the frames (MBAP header, function codes 1, 2, 3, 4, 5, 6, 15, 16, 22,
23; an unknown function code gets exception 01, a malformed frame an exception
response or a closed connection) and asks a server context for values; our context
(`_MapContext`) hands every read and write to the simulation thread through the hub
(comm/hub.py) and answers from the register map (comm/modbus_map.py). Any unit id is
served. A client may send requests before the replies of earlier ones (pipelining):
each is answered, in order. Counts, byte counts and coil values the Modbus specification
refuses get exception 03, and function codes other than those above exception 01
(pymodbus would answer diagnostics, FIFO and file records from made-up data) (`check_pdu`). At most `MAX_CLIENTS` connections: the next one is accepted and closed at once.
A frame whose header is not Modbus TCP's (protocol id 0, length 2..254), or more than
260 bytes that hold no complete frame, close the connection; pymodbus's log messages are
not printed (a NullHandler on its logger).

Every reply, an exception included, leaves in the order of the requests. A read-only
server answers the writing function codes (5, 6, 15, 16, 22, 23) with exception 01
(illegal function) without reaching the map. A client that sends no complete frame for
`idle_timeout` seconds while the server waits for it is closed (time spent answering
does not count), and so is one that reads no reply for as long.
"""

from __future__ import annotations

import asyncio
import collections
import logging
from collections.abc import Sequence

from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.pdu import ExceptionResponse
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler

from motionvm.comm import modbus_map
from motionvm.comm.hub import CommHub
from motionvm.comm.lineserver import MAX_CLIENTS, bound_send_buffer

MAX_PENDING = 16
"""Requests a connection may have waiting for their replies before it stops reading."""

# Counts the Modbus application protocol (1.1b3, section 6) allows per function code
_READ_MAX = {1: 2000, 2: 2000, 3: 125, 4: 125}
_COILS_MAX, _REGS_MAX, _RW_READ_MAX, _RW_WRITE_MAX = 1968, 123, 125, 121


SERVED = frozenset({1, 2, 3, 4, 5, 6, 15, 16, 22, 23})
WRITES = frozenset({5, 6, 15, 16, 22, 23})
"""The function codes that change the machine: a read-only server refuses them."""
"""The function codes the register map serves; pymodbus would answer others (8
diagnostics, 17 server id, 20/21 file records, 24 FIFO, 43 device id) from its own
made-up data."""


def check_pdu(pdu: bytes, read_only: bool = False) -> int | None:
    """The exception code of a request refused before the map sees it: 01 (illegal
    function) for a function code not served, or a write when `read_only`; 03 (illegal
    data value) for counts, a byte count or a value the Modbus specification refuses;
    None for a request to decode."""
    fc, n = (pdu[0], len(pdu)) if pdu else (0, 0)
    if fc not in SERVED or (read_only and fc in WRITES):
        return 0x01
    field = lambda i: int.from_bytes(pdu[i : i + 2], "big")  # noqa: E731
    if fc in _READ_MAX:
        return None if n == 5 and 1 <= field(3) <= _READ_MAX[fc] else 0x03
    if fc == 5:
        return None if n == 5 and field(3) in (0x0000, 0xFF00) else 0x03
    if fc == 6:
        return None if n == 5 else 0x03
    if fc in (15, 16):
        if n < 6:
            return 0x03
        count, size = field(3), pdu[5]
        ok = 1 <= count <= (_COILS_MAX if fc == 15 else _REGS_MAX)
        want = (count + 7) // 8 if fc == 15 else 2 * count
        return None if ok and size == want and n == 6 + size else 0x03
    if fc == 22:
        return None if n == 7 else 0x03
    if fc == 23:
        if n < 10:
            return 0x03
        reads, writes, size = field(3), field(7), pdu[9]
        ok = 1 <= reads <= _RW_READ_MAX and 1 <= writes <= _RW_WRITE_MAX
        return None if ok and size == 2 * writes and n == 10 + size else 0x03
    return None


# pymodbus logs every malformed frame a client sends; a server's stderr is not the place
logging.getLogger("pymodbus").addHandler(logging.NullHandler())


class _MapContext(ModbusServerContext):
    """A server context whose values live in the simulation (any unit id)."""

    def __init__(self, hub: CommHub) -> None:  # no super().__init__: no datastore of its own
        self.hub = hub
        self.old_simulator = True  # pymodbus: use this context's async_*Values as they are
        self.simdevices: list = []
        self._devices: dict = {}

    async def async_getValues(self, device_id: int, func_code: int, address: int, count: int = 1):
        hub = self.hub
        res = await asyncio.wrap_future(
            hub.post(lambda: modbus_map.read(hub, func_code, address, count))
        )
        return ExcCodes(res) if isinstance(res, int) else res

    async def async_setValues(
        self, device_id: int, func_code: int, address: int, values: Sequence[int] | Sequence[bool]
    ):
        hub = self.hub
        vals = list(values)
        res = await asyncio.wrap_future(
            hub.post(lambda: modbus_map.write(hub, func_code, address, vals))
        )
        return None if res is None else ExcCodes(res)

    def device_ids(self) -> list[int]:
        return [0]


class _Refuse(asyncio.Protocol):
    """A connection over the limit: closed as soon as it is made."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        transport.close()


class _Handler(ServerRequestHandler):
    """pymodbus's connection handler, made to answer every frame of a stream in order.

    pymodbus decodes one frame per received chunk (a second frame in the same chunk waits
    for more data) and answers from `self.last_pdu` a moment later (a request arriving
    in between replaces it): a client that sends its next request before the last reply
    lost requests. Here each complete frame is decoded on arrival and queued, with its
    own PDU or with its ready exception reply; the queue is answered in order (at most
    `MAX_PENDING` requests, then the connection stops reading until the queue drains), so
    a refused request never overtakes an earlier one. A request whose counts or values
    the Modbus specification refuses gets exception 03 without reaching the map, and an
    unknown function code exception 01 with that code (pymodbus says function 0)."""

    _pending: collections.deque | None = None
    _worker: asyncio.Task | None = None
    _paused = False
    _writable: asyncio.Event | None = None
    """Clear while the transport's send buffer is full (a client not reading its replies):
    no request is answered until it drains, so the queue fills and reading stops."""
    _refused: ExceptionResponse | None = None
    """pymodbus's exception reply to the frame being decoded (queued, not sent at once)."""
    _decoding = False
    _idle: asyncio.TimerHandle | None = None
    _last_request = 0.0
    """Event loop time [s wall] of the last complete frame or reply."""

    def callback_connected(self) -> None:
        super().callback_connected()
        if self.transport is not None:
            bound_send_buffer(self.transport.get_extra_info("socket"))
        self._touch()
        if self.server.idle_timeout:
            self._idle = self.loop.call_later(self.server.idle_timeout, self._check_idle)

    def _touch(self) -> None:
        self._last_request = asyncio.get_running_loop().time()

    def _check_idle(self) -> None:
        """Close the connection if it has sent no complete frame for `idle_timeout`
        seconds and has none waiting for its reply; else look again when it could be."""
        timeout = self.server.idle_timeout
        busy = bool(self._pending) or (self._worker is not None and not self._worker.done())
        if busy:
            self._touch()
        left = self._last_request + timeout - self.loop.time()
        if left > 0:
            self._idle = self.loop.call_later(left, self._check_idle)
        elif self.transport is not None:
            self._idle = None
            self.transport.close()

    def pause_writing(self) -> None:
        if self._writable is None:
            self._writable = asyncio.Event()
        self._writable.clear()

    def resume_writing(self) -> None:
        if self._writable is not None:
            self._writable.set()

    def callback_disconnected(self, exc: Exception | None) -> None:
        self.resume_writing()  # a worker waiting to write ends
        if self._idle is not None:
            self._idle.cancel()
            self._idle = None
        super().callback_disconnected(exc)

    def data_received(self, data: bytes) -> None:
        buf = self.recv_buffer + data
        self.recv_buffer = buf[self.callback_data(buf) :]
        # more than one frame's worth (260 bytes) without a complete frame: pymodbus would
        # drop it silently and wait; a client that cannot be understood is closed instead
        if len(self.recv_buffer) > self.max_buffer_size and self.transport is not None:
            self.recv_buffer = b""
            self.transport.close()

    def callback_data(self, data: bytes, addr: tuple | None = None) -> int:
        """Handle every complete frame at the start of `data`; the bytes used."""
        used = 0
        while len(data) - used >= 8:
            head = data[used : used + 6]
            protocol, length = int.from_bytes(head[2:4], "big"), int.from_bytes(head[4:6], "big")
            if protocol != 0 or not 2 <= length <= 254:
                # a header that is no Modbus TCP header: a stream that cannot be
                # resynchronised; close the connection rather than wait for more
                if self.transport is not None:
                    self.transport.close()
                return len(data)
            if len(data) - used < 6 + length:
                break
            frame = data[used : used + 6 + length]
            used += 6 + length
            self._one_frame(frame, addr)
        return used

    def _one_frame(self, frame: bytes, addr: tuple | None) -> None:
        self._touch()
        code = check_pdu(frame[7:], self.server.read_only)
        if code is not None:
            self._queue(_exception(frame, code), addr)
            return
        self._decoding, self._refused = True, None
        try:
            super().callback_data(frame, addr)  # decodes into last_pdu, or refuses it
        finally:
            self._decoding = False
        pdu, self.last_pdu = self.last_pdu, None  # no handle_later of pymodbus's
        if self._refused is not None:
            self._queue(_exception(frame, int(self._refused.exception_code)), addr)
        elif pdu is not None:
            self._queue(pdu, addr)

    def _queue(self, item, addr: tuple | None) -> None:
        """Answer `item` (a request PDU, or a ready exception reply) after every request
        queued before it."""
        if self._pending is None:
            self._pending = collections.deque()
        self._pending.append((item, addr))
        if len(self._pending) >= MAX_PENDING and self.transport is not None:
            self.transport.pause_reading()
            self._paused = True
        if self._worker is None or self._worker.done():
            self._worker = asyncio.get_running_loop().create_task(self._answer_all())

    def handle_later(self) -> None:
        """pymodbus's answer from `last_pdu`, which `_one_frame` has taken: nothing to do."""

    async def _answer_all(self) -> None:
        pending = self._pending
        while pending:
            if self._writable is not None and not await self._can_write():
                pending.clear()
                return
            item, addr = pending.popleft()
            if isinstance(item, ExceptionResponse):
                reply = item
            else:
                try:
                    reply = await item.datastore_update(self.server.context, item.dev_id)
                except Exception:  # noqa: BLE001 — a bug of ours: the client gets exception 04
                    reply = ExceptionResponse(item.function_code, ExcCodes.DEVICE_FAILURE)
                reply.transaction_id = item.transaction_id
                reply.dev_id = item.dev_id
            if self.transport is None or self.transport.is_closing():
                pending.clear()
                return
            super().server_send(reply, addr)
            self._touch()
            if self._paused and len(pending) < MAX_PENDING // 2:
                self._paused = False
                self.transport.resume_reading()

    async def _can_write(self) -> bool:
        """Wait until the send buffer drains; False (the connection dropped at once) if
        the client reads nothing for `idle_timeout` seconds."""
        assert self._writable is not None
        timeout = self.server.idle_timeout or None
        try:
            await asyncio.wait_for(self._writable.wait(), timeout)
        except TimeoutError:
            if self.transport is not None:
                self.transport.abort()  # close() would wait for the client to read
            return False
        return True

    def server_send(self, pdu, addr) -> None:
        if self._decoding and isinstance(pdu, ExceptionResponse):
            self._refused = pdu  # queued behind the earlier requests by _one_frame
            return
        super().server_send(pdu, addr)


def _exception(frame: bytes, code: int) -> ExceptionResponse:
    """The exception reply `code` to the request `frame` (its function code, transaction
    and unit id)."""
    reply = ExceptionResponse(frame[7], exception_code=ExcCodes(code))
    reply.transaction_id = int.from_bytes(frame[0:2], "big")
    reply.dev_id = frame[6]
    return reply


class _Server(ModbusTcpServer):
    read_only = False
    idle_timeout = 0.0

    def callback_new_connection(self):
        return _Handler(self, self.trace_packet, self.trace_pdu, self.trace_connect)

    def handle_new_connection(self):
        if len(self.active_connections) >= MAX_CLIENTS:
            return _Refuse()
        return super().handle_new_connection()


class ModbusServer:
    """The Modbus TCP server of one hub, on the servers' event loop."""

    def __init__(self, hub: CommHub, *, read_only: bool = False, idle_timeout: float = 0.0) -> None:
        self.hub = hub
        self.read_only = read_only
        """Writes get exception 01."""
        self.idle_timeout = idle_timeout
        """[s wall] without a complete frame before a client is closed; 0: never."""
        self._server: _Server | None = None

    async def start(self, host: str, port: int) -> int:
        """Listen on (host, port); the bound port (port 0: a free one)."""
        self._server = _Server(_MapContext(self.hub), address=(host, port))
        self._server.read_only = self.read_only
        self._server.idle_timeout = self.idle_timeout
        await self._server.serve_forever(background=True)
        listener = self._server.transport
        return listener.sockets[0].getsockname()[1]  # type: ignore[union-attr]

    async def stop(self) -> None:
        if self._server is not None:
            await self._server.shutdown()
