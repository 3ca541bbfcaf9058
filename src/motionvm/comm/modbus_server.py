"""The Modbus TCP server: pymodbus's framing and function codes on the register map.

pymodbus decodes the frames (MBAP header, function codes 1, 2, 3, 4, 5, 6, 15, 16, 22,
23; an unknown function code gets exception 01, a malformed frame an exception
response or a closed connection) and asks a server context for values; our context
(`_MapContext`) hands every read and write to the simulation thread through the hub
(comm/hub.py) and answers from the register map (comm/modbus_map.py). Any unit id is
served. At most `MAX_CLIENTS` connections: the next one is accepted and closed at once.
A frame whose header is not Modbus TCP's (protocol id 0, length 2..254), or more than
260 bytes that hold no complete frame, close the connection; pymodbus's log messages are not printed (a NullHandler on its logger).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Sequence

from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.pdu import ExceptionResponse
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler

from motionvm.comm import modbus_map
from motionvm.comm.hub import CommHub
from motionvm.comm.lineserver import MAX_CLIENTS

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
    """pymodbus's connection handler, answering an unknown function code with that code
    (pymodbus says function 0: `0x80 0x01`; a client expects `fc|0x80 0x01`)."""

    _frame = b""

    def data_received(self, data: bytes) -> None:
        # more than one frame's worth (260 bytes) without a complete frame: pymodbus would
        # drop it silently and wait; a client that cannot be understood is closed instead
        if len(self.recv_buffer) + len(data) > self.max_buffer_size:
            if self.transport is not None:
                self.transport.close()
            return
        super().data_received(data)

    def callback_data(self, data: bytes, addr: tuple | None = None) -> int:
        # `data` starts at a frame boundary: a header that is no Modbus TCP header (a
        # protocol id other than 0, a length outside 2..254) means a stream that cannot
        # be resynchronised: close the connection rather than wait for more
        if len(data) >= 6:
            protocol, length = int.from_bytes(data[2:4], "big"), int.from_bytes(data[4:6], "big")
            if protocol != 0 or not 2 <= length <= 254:
                if self.transport is not None:
                    self.transport.close()
                return len(data)
        self._frame = data
        return super().callback_data(data, addr)

    def server_send(self, pdu, addr) -> None:
        frame = self._frame
        if isinstance(pdu, ExceptionResponse) and pdu.function_code == 0x80 and len(frame) > 7:
            pdu.function_code = frame[7] | 0x80
            pdu.transaction_id = int.from_bytes(frame[0:2], "big")
            pdu.dev_id = frame[6]
        super().server_send(pdu, addr)


class _Server(ModbusTcpServer):
    def callback_new_connection(self):
        return _Handler(self, self.trace_packet, self.trace_pdu, self.trace_connect)

    def handle_new_connection(self):
        if len(self.active_connections) >= MAX_CLIENTS:
            return _Refuse()
        return super().handle_new_connection()


class ModbusServer:
    """The Modbus TCP server of one hub, on the servers' event loop."""

    def __init__(self, hub: CommHub) -> None:
        self.hub = hub
        self._server: _Server | None = None

    async def start(self, host: str, port: int) -> int:
        """Listen on (host, port); the bound port (port 0: a free one)."""
        self._server = _Server(_MapContext(self.hub), address=(host, port))
        await self._server.serve_forever(background=True)
        listener = self._server.transport
        return listener.sockets[0].getsockname()[1]  # type: ignore[union-attr]

    async def stop(self) -> None:
        if self._server is not None:
            await self._server.shutdown()
