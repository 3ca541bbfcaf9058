"""HMPL communication functions of manual chapter 21: the User ASCII agent, broadcasts,
the ASCII client and the Modbus TCP client.

They marshal only: the connections, limits and error codes of 18.1.1 are in
`motionvm.comm.clients`, the servers in `motionvm.comm`; START_ASCII_AGENT's parser runs
in `lang/hmpl/rtcomm.py`. The client functions wait at a yield while the network works
(only the calling task waits; in an unpaced run no simulated time passes).
ASCII_ServerBroadcast sends `length` bytes of `message` (at most 128, and no further
than its end) to every connected User ASCII client; with none connected it does nothing.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.runtime.errors import RuntimeFault

BROADCAST_MAX = 128


class CommLib(Library):
    """Chapter 21: START_ASCII_AGENT ... Modbus_ClientWrite_Coils."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        self.hub = rt.controller.comm
        self._clients = None

    @property
    def clients(self):
        """The client operations (`comm.clients`, imported by the first client call)."""
        if self._clients is None:
            from motionvm.comm.clients import ClientCommands

            self._clients = ClientCommands(self.hub)
        return self._clients

    def _text(self, addr: int, length: int, what: str) -> bytes:
        """Up to `length` bytes of the string at `addr`, stopping at its NUL."""
        if addr == 0:
            raise RuntimeFault(f"null {what} pointer")
        if length <= 0:
            return b""
        n = min(length, self.mem.extent(addr))
        if n == 0:
            raise RuntimeFault(f"{what} 0x{addr:x} points outside any object")
        data = self.mem.read_bytes(addr, n)
        end = data.find(b"\0")
        return data if end < 0 else data[:end]

    def _wait(self, job):
        while not job.done():
            yield None
        return job.result()

    # ------------------------------------------------------------ server side (21.2.1-2)

    @builtin()
    def START_ASCII_AGENT(self, parser) -> None:
        agent = self.hub.agent
        if agent is None or not hasattr(agent, "start_agent"):
            raise RuntimeFault("START_ASCII_AGENT: this run has no ASCII agent support")
        agent.start_agent(parser, self.rt.current_task_id)

    @builtin()
    def ASCII_ServerBroadcast(self, message: int, length: int) -> None:
        if not 0 <= length <= BROADCAST_MAX:
            raise RuntimeFault(
                f"ASCII_ServerBroadcast: length {length} is out of range (0..{BROADCAST_MAX})"
            )
        data = self._text(message, length, "message")
        if data:
            self.hub.broadcast(data)

    # ------------------------------------------------------------ ASCII client (21.2.3-6)

    @builtin(blocking=True)
    def ASCII_ClientConnect(self, ip: int, port: int, socket_id: int):
        ip_text = self.mem.read_cstr(ip, "ip").decode("latin-1")
        port_text = self.mem.read_cstr(port, "port").decode("latin-1")
        self.mem.check(socket_id, 4, "socket_id pointer")
        code, sid = yield from self._wait(self.clients.ascii_connect(ip_text, port_text))
        if code == 0:
            self.mem.store(socket_id, "i32", sid)
        return code

    @builtin(blocking=True)
    def ASCII_ClientRecv(self, socket_id: int, length: int, buffer: int):
        code, data = yield from self._wait(self.clients.ascii_recv(socket_id, length))
        if code == 0:
            self.mem.write_bytes(buffer, data + b"\0", "buffer")
        return code

    @builtin(blocking=True)
    def ASCII_ClientSend(self, socket_id: int, length: int, buffer: int):
        data = self._text(buffer, length, "buffer")
        return (yield from self._wait(self.clients.ascii_send(socket_id, data)))

    @builtin()
    def ASCII_ClientDisconnect(self, socket_id: int) -> int:
        return self.clients.disconnect("ascii", socket_id)

    # ------------------------------------------------------------ Modbus client (21.3)

    @builtin(blocking=True)
    def Modbus_ClientConnect(self, ip: int, socket_id: int):
        ip_text = self.mem.read_cstr(ip, "ip").decode("latin-1")
        self.mem.check(socket_id, 4, "socket_id pointer")
        code, sid = yield from self._wait(self.clients.modbus_connect(ip_text))
        if code == 0:
            self.mem.store(socket_id, "i32", sid)
        return code

    @builtin()
    def Modbus_ClientDisconnect(self, socket_id: int) -> int:
        return self.clients.disconnect("modbus", socket_id)

    def _modbus(self, socket_id, fc, start, count, output_buf, use_length, words=None):
        self.mem.check(use_length, 4, "use_length pointer")
        job = self.clients.modbus_request(socket_id, fc, start, count, words)
        code, data = yield from self._wait(job)
        if code == 0:
            if data:
                self.mem.write_bytes(output_buf, data, "output_buf")
            self.mem.store(use_length, "i32", len(data))
        return code

    def _words(self, addr: int, n: int) -> list[int]:
        self.mem.check(addr, 2 * n, "write_data")
        return [self.mem.load(addr + 2 * i, "u16") for i in range(n)]

    @builtin(blocking=True)
    def Modbus_ClientRead_HoldReg(self, socket_id, start_addr, num_regs, output_buf, use_length):
        return (yield from self._modbus(socket_id, 3, start_addr, num_regs, output_buf, use_length))

    @builtin(blocking=True)
    def Modbus_ClientRead_InputReg(self, socket_id, start_addr, num_regs, output_buf, use_length):
        return (yield from self._modbus(socket_id, 4, start_addr, num_regs, output_buf, use_length))

    @builtin(blocking=True)
    def Modbus_ClientRead_Coils(self, socket_id, start_addr, num_coils, output_buf, use_length):
        return (
            yield from self._modbus(socket_id, 1, start_addr, num_coils, output_buf, use_length)
        )

    @builtin(blocking=True)
    def Modbus_ClientRead_Inputs(self, socket_id, start_addr, num_inputs, output_buf, use_length):
        return (
            yield from self._modbus(socket_id, 2, start_addr, num_inputs, output_buf, use_length)
        )

    @builtin(blocking=True)
    def Modbus_ClientWrite_HoldReg(
        self, socket_id, start_addr, num_regs, write_data, output_buf, use_length
    ):
        words = self._words(write_data, num_regs) if 1 <= num_regs <= 123 else []
        return (
            yield from self._modbus(
                socket_id, 16, start_addr, num_regs, output_buf, use_length, words
            )
        )

    @builtin(blocking=True)
    def Modbus_ClientWrite_Coils(
        self, socket_id, start_addr, num_coils, write_data, output_buf, use_length
    ):
        words = self._words(write_data, (num_coils + 15) // 16) if 1 <= num_coils <= 1968 else []
        return (
            yield from self._modbus(
                socket_id, 15, start_addr, num_coils, output_buf, use_length, words
            )
        )
