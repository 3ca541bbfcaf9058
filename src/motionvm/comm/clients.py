"""The controller as a TCP client: the ASCII client (21.2.3-21.2.6) and Modbus TCP client
(21.3) operations, in error codes of manual 18.1.1, for any language's built-ins.

Each operation returns a `Job` (comm/hub.py) whose result is the manual's return value
(0 or an error code) and the data; the language's built-in waits at a yield until the
job is done (at once in an unpaced run). The socket table lives in the hub; ids count
from 10 per kind (the manual's examples use socket 10). Decisions where the manual is silent:
- at most `CLIENT_LIMIT` connections of each kind: the next connect fails
  (0x17D5 / 0x1839, "or already reach limit");
- an unknown socket id gives eERR_HMPL_CLIENT_NOT_CONNECTED (0x1452), a length out of
  its range (ASCII 1..512) eERR_HMPL_ARG_OUT_OF_RANGE (0x138F);
- ASCII_ClientSend sends `length` bytes but stops at the string's end (its NUL):
  the manual's example passes 100 for an 11-character string; ASCII_ClientRecv waits
  for at least one byte and returns what has arrived, at most `length` bytes;
- the Modbus client sends unit id 1; an exception response is eERR_MODBUS_JOB_FAIL
  (0x1840), as is a response that does not answer the request (another byte count, a
  write not echoed); no complete answer within the timeout (however it trickles in)
  eERR_MODBUS_JOB_TIMEOUT (0x183F); a count over
  the manual's limit (or 0) is refused before anything is sent (0x183D);
- a second operation on a socket whose first has not finished: 0x17E0 (receive),
  0x17EA (send), 0x183E (Modbus).
"""

from __future__ import annotations

import ipaddress
import socket
import struct
import time

from motionvm.comm.hub import CommHub, Job

CLIENT_LIMIT = 8
ASCII_MAX_LENGTH = 512

CLIENT_NOT_CONNECTED = 0x1452
ARG_OUT_OF_RANGE = 0x138F
ASCII_CONNECT_TIMEOUT, ASCII_CONNECT_FAILED = 0x17D4, 0x17D5
ASCII_DISCONNECT_TIMEOUT = 0x17D8
ASCII_RECV_TIMEOUT, ASCII_RECV_FAIL, ASCII_MULTI_RECVING = 0x17DE, 0x17DF, 0x17E0
ASCII_SEND_TIMEOUT, ASCII_SEND_FAIL, ASCII_MULTI_SENDING = 0x17E8, 0x17E9, 0x17EA
MODBUS_CONNECT_TIMEOUT, MODBUS_CONNECT_FAILED = 0x1838, 0x1839
MODBUS_DATALENGTH_ERR, MODBUS_SOCKET_BUSY = 0x183D, 0x183E
MODBUS_JOB_TIMEOUT, MODBUS_JOB_FAIL = 0x183F, 0x1840

MODBUS_PORT = 502
MODBUS_UNIT = 1
MODBUS_LIMITS = {1: 2000, 2: 2000, 3: 125, 4: 125, 15: 1968, 16: 123}
"""Function code -> the most coils or registers one request may carry (manual 21.3)."""


def _done(value: object) -> Job:
    import concurrent.futures

    fut: concurrent.futures.Future = concurrent.futures.Future()
    fut.set_result(value)
    return Job(fut)


def _connect(host: str, port: int, timeout: float, codes: tuple[int, int]):
    """(0, socket) or (code, None): codes = (timeout, failed)."""
    try:
        sock = socket.create_connection((host, port), timeout=timeout)
    except TimeoutError:
        return codes[0], None
    except OSError:
        return codes[1], None
    sock.settimeout(timeout)
    return 0, sock


def parse_address(ip: str, port_text: str | None, default_port: int) -> tuple[str, int] | None:
    """(host, port) of an IPv4/IPv6 address and a port (`ip` may end in `:PORT` when
    `port_text` is None); None if either is malformed."""
    host = ip.strip()
    if port_text is None:
        if host.count(":") == 1:
            host, port_text = host.split(":")
        else:
            port_text = str(default_port)
    try:
        ipaddress.ip_address(host)
        port = int(port_text.strip(), 10)
    except ValueError:
        return None
    if not 0 < port <= 65535:
        return None
    return host, port


class ClientCommands:
    """The client operations on one hub's socket table."""

    def __init__(self, hub: CommHub) -> None:
        self.hub = hub
        self._tid = 0

    def _connect_job(self, kind: str, address, codes: tuple[int, int]) -> Job:
        if address is None:
            return _done((codes[1], 0))
        hub, timeout = self.hub, self.hub.config.client_timeout
        if len(hub.sockets[kind]) >= CLIENT_LIMIT:
            return _done((codes[1], 0))
        job = hub.start_job(lambda: _connect(address[0], address[1], timeout, codes))
        return _Registering(job, hub, kind, codes[1])

    # ------------------------------------------------------------ ASCII (21.2.3-21.2.6)

    def ascii_connect(self, ip: str, port: str) -> Job:
        """Result (code, socket id)."""
        address = parse_address(ip, port, 0)
        return self._connect_job("ascii", address, (ASCII_CONNECT_TIMEOUT, ASCII_CONNECT_FAILED))

    def ascii_recv(self, socket_id: int, length: int) -> Job:
        """Result (code, data bytes)."""
        sock = self.hub.sockets["ascii"].get(socket_id)
        if sock is None:
            return _done((CLIENT_NOT_CONNECTED, b""))
        if not 1 <= length <= ASCII_MAX_LENGTH:
            return _done((ARG_OUT_OF_RANGE, b""))
        return self._exclusive(
            "ascii", socket_id, (ASCII_MULTI_RECVING, b""), lambda: _recv(sock, length)
        )

    def ascii_send(self, socket_id: int, data: bytes) -> Job:
        """Result code."""
        sock = self.hub.sockets["ascii"].get(socket_id)
        if sock is None:
            return _done(CLIENT_NOT_CONNECTED)
        if len(data) > ASCII_MAX_LENGTH:
            return _done(ARG_OUT_OF_RANGE)
        return self._exclusive("ascii", socket_id, ASCII_MULTI_SENDING, lambda: _send(sock, data))

    def disconnect(self, kind: str, socket_id: int) -> int:
        """Close a client socket (either kind); 0, or 0x1452 for an unknown id."""
        sock = self.hub.sockets[kind].pop(socket_id, None)
        if sock is None:
            return CLIENT_NOT_CONNECTED
        try:
            sock.close()  # type: ignore[attr-defined]
        except OSError:
            pass
        return 0

    def _exclusive(self, kind: str, socket_id: int, busy_result: object, work) -> Job:
        key = (kind, socket_id)
        busy = self.hub.busy_sockets
        if key in busy:
            return _done(busy_result)
        busy.add(key)

        def run():
            try:
                return work()
            finally:
                busy.discard(key)

        return self.hub.start_job(run)

    # ------------------------------------------------------------ Modbus TCP (21.3)

    def modbus_connect(self, ip: str) -> Job:
        """Result (code, socket id); `ip` may end in `:PORT` (default 502)."""
        address = parse_address(ip, None, MODBUS_PORT)
        return self._connect_job("modbus", address, (MODBUS_CONNECT_TIMEOUT, MODBUS_CONNECT_FAILED))

    def modbus_request(self, socket_id: int, function_code: int, address: int, count: int,
                       words: list[int] | None = None) -> Job:  # fmt: skip
        """Read (function codes 1-4) or write (15: coils packed 16 to a word as in
        manual 21.3.8, 16: registers) `count` items at `address`. Result (code, the
        response's data bytes as on the wire)."""
        sock = self.hub.sockets["modbus"].get(socket_id)
        if sock is None:
            return _done((CLIENT_NOT_CONNECTED, b""))
        if not 1 <= count <= MODBUS_LIMITS[function_code]:
            return _done((MODBUS_DATALENGTH_ERR, b""))
        pdu = _modbus_pdu(function_code, address, count, words or [])
        self._tid = (self._tid + 1) & 0xFFFF
        tid = self._tid
        return self._exclusive(
            "modbus", socket_id, (MODBUS_SOCKET_BUSY, b""), lambda: _transact(sock, tid, pdu)
        )


class _Registering(Job):
    """A connect job whose socket joins the table when the built-in takes its result."""

    def __init__(self, job: Job, hub: CommHub, kind: str, failed: int) -> None:
        super().__init__(job._future)
        self.hub, self.kind, self.failed = hub, kind, failed

    def result(self):
        code, sock = super().result()
        if code:
            return code, 0
        sid = self.hub.add_socket(self.kind, sock, CLIENT_LIMIT)
        if sid is None:
            sock.close()
            return self.failed, 0
        return 0, sid


def _recv(sock: socket.socket, length: int) -> tuple[int, bytes]:
    try:
        data = sock.recv(length)
    except TimeoutError:
        return ASCII_RECV_TIMEOUT, b""
    except OSError:
        return ASCII_RECV_FAIL, b""
    if not data:
        return ASCII_RECV_FAIL, b""  # the server closed the connection
    return 0, data


def _send(sock: socket.socket, data: bytes) -> int:
    try:
        sock.sendall(data)
    except TimeoutError:
        return ASCII_SEND_TIMEOUT
    except OSError:
        return ASCII_SEND_FAIL
    return 0


def _modbus_pdu(function_code: int, address: int, count: int, words: list[int]) -> bytes:
    if function_code in (1, 2, 3, 4):
        return struct.pack(">BHH", function_code, address, count)
    if function_code == 16:
        data = b"".join(struct.pack(">H", w & 0xFFFF) for w in words[:count])
        return struct.pack(">BHHB", 16, address, count, len(data)) + data
    # 15: coil start+i is bit i%16 of words[i//16]: bytes LSB first, low byte of a word first
    nbytes = (count + 7) // 8
    packed = b"".join(struct.pack("<H", w & 0xFFFF) for w in words)[:nbytes]
    mask = (1 << (count % 8)) - 1 if count % 8 else 0xFF
    packed = packed[:-1] + bytes([packed[-1] & mask])
    return struct.pack(">BHHB", 15, address, count, nbytes) + packed


def _recv_exact(sock: socket.socket, n: int, deadline: float) -> bytes | None:
    """`n` bytes, None if the peer closes first; TimeoutError once `deadline` (monotonic
    clock) has passed, however the bytes trickle in."""
    buf = b""
    while len(buf) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return buf


def _transact(sock: socket.socket, tid: int, pdu: bytes) -> tuple[int, bytes]:
    """Send one request and read its response within the client timeout; (code, data
    bytes). A response that is not the request's (another function code, a byte count
    other than the request's, data it does not hold) is eERR_MODBUS_JOB_FAIL."""
    frame = struct.pack(">HHHB", tid, 0, len(pdu) + 1, MODBUS_UNIT) + pdu
    timeout = sock.gettimeout()
    deadline = time.monotonic() + (timeout if timeout is not None else 1.0)
    try:
        sock.sendall(frame)
        while True:
            head = _recv_exact(sock, 7, deadline)
            if head is None:
                return MODBUS_JOB_FAIL, b""
            rtid, _pid, length, _unit = struct.unpack(">HHHB", head)
            if not 2 <= length <= 260:
                return MODBUS_JOB_FAIL, b""
            body = _recv_exact(sock, length - 1, deadline)
            if body is None:
                return MODBUS_JOB_FAIL, b""
            if rtid == tid:
                break  # a late answer to an earlier, timed-out request is skipped
    except TimeoutError:
        return MODBUS_JOB_TIMEOUT, b""
    except OSError:
        return MODBUS_JOB_FAIL, b""
    finally:
        try:
            sock.settimeout(timeout)
        except OSError:
            pass
    return _response_data(pdu, body)


def _response_data(pdu: bytes, body: bytes) -> tuple[int, bytes]:
    """(0, data) of a response `body` that answers `pdu`, else (eERR_MODBUS_JOB_FAIL, b"")."""
    fc = body[0]
    if fc & 0x80 or fc != pdu[0]:
        return MODBUS_JOB_FAIL, b""
    count = int.from_bytes(pdu[3:5], "big")
    if fc in (1, 2, 3, 4):
        want = 2 * count if fc in (3, 4) else (count + 7) // 8
        if len(body) != 2 + want or body[1] != want:
            return MODBUS_JOB_FAIL, b""
        return 0, body[2:]
    if len(body) != 5 or body[1:5] != pdu[1:5]:  # a write echoes its address and count
        return MODBUS_JOB_FAIL, b""
    return 0, body[1:5]
