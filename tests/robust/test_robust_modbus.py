"""Hostile Modbus TCP clients: pipelined requests, counts and values the specification
refuses, generated malformed frames. Every request gets its reply or exception, in order,
and the server keeps serving. Real loopback sockets; every wait bounded."""

from __future__ import annotations

import random
import socket
import struct
import sys
import threading
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "comm"))
from comm_helpers import served  # noqa: E402

PROGRAM = 'void main() { Print("ready"); }\n'
FRAMES = 120
"""Generated malformed frames (about 2 s)."""


@pytest.fixture(scope="module")
def server():
    with served(PROGRAM) as (sim, srv):
        yield sim, srv.ports["modbus"]


def connect(port: int, timeout: float = 5.0) -> socket.socket:
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    s.settimeout(timeout)
    return s


def reply(sock: socket.socket) -> bytes:
    """One response frame (what came if the server closed before its end)."""
    data = _recv(sock, 6)
    if len(data) < 6:
        return data
    return data + _recv(sock, struct.unpack(">H", data[4:6])[0])


def _recv(sock: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            break
        data += chunk
    return data


def frame(tid: int, pdu: bytes, unit: int = 1) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


def read_regs(tid: int, start: int, count: int) -> bytes:
    return frame(tid, struct.pack(">BHH", 3, start, count))


def test_requests_sent_together_are_all_answered_in_order(server):
    _sim, port = server
    s = connect(port)
    try:
        s.sendall(frame(0, struct.pack(">BHHBHH", 16, 2, 2, 4, 0x1234, 0x5678)))  # ltest1
        assert reply(s) == frame(0, struct.pack(">BHH", 16, 2, 2))
        s.sendall(b"".join(read_regs(tid, 2, 2) for tid in (1, 2, 3)))
        for tid in (1, 2, 3):
            assert reply(s) == frame(tid, bytes.fromhex("03 04 12 34 56 78"))
        for tid in range(10, 15):  # each sent before the last one's reply
            s.sendall(read_regs(tid, 2, 2))
        for tid in range(10, 15):
            assert reply(s) == frame(tid, bytes.fromhex("03 04 12 34 56 78"))
    finally:
        s.close()


def test_a_client_that_pipelines_many_requests_gets_every_reply(server):
    _sim, port = server
    s = connect(port)
    try:
        s.sendall(b"".join(read_regs(tid, 0, 1) for tid in range(200)))
        tids = [struct.unpack(">H", reply(s)[:2])[0] for _ in range(200)]
        assert tids == list(range(200))
    finally:
        s.close()


@pytest.mark.parametrize(
    "pdu",
    [
        struct.pack(">BHH", 3, 0, 0),  # no registers
        struct.pack(">BHH", 3, 0, 126),  # more than 125
        struct.pack(">BHH", 1, 0, 0),
        struct.pack(">BHH", 2, 0, 2001),
        struct.pack(">BHH", 5, 0, 0x1234),  # a coil value other than 0x0000 / 0xFF00
        struct.pack(">BHHB", 16, 0, 2, 2) + b"\x00\x05",  # byte count says 1 register
        struct.pack(">BHHB", 16, 0, 1, 4) + b"\x00\x05\x00\x07",
        struct.pack(">BHHB", 16, 0, 0, 0),
        struct.pack(">BHHB", 15, 0, 9, 1) + b"\xff",  # 9 coils need 2 bytes
        struct.pack(">BHHB", 15, 0, 8, 0),
        struct.pack(">BHHHHB", 23, 0, 2, 0, 0, 0),  # nothing to write
    ],
    ids=["fc3-0", "fc3-126", "fc1-0", "fc2-2001", "fc5-0x1234", "fc16-bytes-short",
         "fc16-bytes-long", "fc16-0", "fc15-bytes-short", "fc15-bytes-0", "fc23-0"],
)  # fmt: skip
def test_counts_and_values_the_specification_refuses_get_exception_03_and_change_nothing(
    server, pdu
):
    _sim, port = server
    s = connect(port)
    try:
        s.sendall(frame(1, struct.pack(">BHHBHH", 16, 0, 2, 4, 0, 7)))  # system_ltest0 = 7
        s.sendall(frame(2, struct.pack(">BHH", 5, 0, 0)))  # output 1 off
        assert [reply(s)[:2] for _ in range(2)] == [b"\0\1", b"\0\2"]
        s.sendall(frame(9, pdu))
        assert reply(s) == frame(9, bytes([pdu[0] | 0x80, 0x03]))
        s.sendall(read_regs(3, 0, 2) + frame(4, struct.pack(">BHH", 1, 0, 1)))
        assert reply(s) == frame(3, bytes.fromhex("03 04 00 00 00 07"))
        assert reply(s) == frame(4, bytes.fromhex("01 01 00"))
    finally:
        s.close()


def test_generated_malformed_frames_get_an_answer_or_a_close_and_the_server_serves_on(server):
    _sim, port = server
    rng = random.Random(15)
    start = time.monotonic()
    for k in range(FRAMES):
        pdu = _pdu(rng)
        length = len(pdu) + 1
        if rng.random() < 0.15:  # a length field that lies
            length = rng.choice([0, 1, 2, length - 1, length + 1, 254, 255, 0xFFFF])
        data = struct.pack(">HHHB", k, 0, length & 0xFFFF, rng.choice([0, 1, 255])) + pdu
        s = connect(port, timeout=0.3)
        s.sendall(data)
        try:
            got = reply(s)
        except TimeoutError:  # an incomplete frame: the server waits for the rest
            got = b""
        s.close()
        if len(got) >= 8:
            assert got[:2] == data[:2], (data.hex(), got.hex())  # its transaction id
        c = connect(port)
        c.sendall(read_regs(42, 0, 1))
        assert reply(c)[:9] == frame(42, b"\x03\x02\0\0")[:9], data.hex()
        c.close()
        assert time.monotonic() - start < 30
    assert _sim.fault_count == 0


def _pdu(rng: random.Random) -> bytes:
    fc = rng.choice([1, 2, 3, 4, 5, 6, 15, 16, 22, 23, 0, 7, 8, 0x2B, 0x80, 0xFF, 17, 24])
    addr = rng.choice([0, 1, 7, 8, 19, 20, 100, 139, 1000, 2000, 65535])
    count = rng.choice([0, 1, 2, 8, 9, 121, 122, 125, 126, 2000, 2001, 65535])
    if fc in (1, 2, 3, 4):
        pdu = struct.pack(">BHH", fc, addr, count)
    elif fc in (5, 6):
        pdu = struct.pack(">BHH", fc, addr, rng.choice([0, 0xFF00, 1, 0xFFFF]))
    elif fc in (15, 16):
        size = rng.choice([0, 1, 2, count * 2 & 0xFF, (count + 7) // 8 & 0xFF, 255])
        body = rng.randbytes(rng.choice([0, 1, size, size + 3]))
        pdu = struct.pack(">BHHB", fc, addr, count, size) + body
    elif fc == 22:
        pdu = struct.pack(">BHHH", fc, addr, rng.randrange(65536), rng.randrange(65536))
    elif fc == 23:
        writes = rng.choice([0, 1, 2, 121, 122])
        size = rng.choice([0, 2, writes * 2 & 0xFF, 255])
        pdu = struct.pack(">BHHHHB", fc, addr, count, 0, writes, size)
        pdu += rng.randbytes(rng.choice([0, size, 3]))
    else:
        pdu = bytes([fc]) + rng.randbytes(rng.randrange(10))
    if rng.random() < 0.2:  # truncated
        pdu = pdu[: rng.randrange(1, len(pdu) + 1)]
    return pdu


def test_clients_that_send_many_requests_and_vanish_leave_the_server_serving(server):
    _sim, port = server
    for _ in range(5):
        s = connect(port)
        s.sendall(b"".join(read_regs(tid, 0, 1) for tid in range(100)))
        s.close()  # before any reply
    c = connect(port)
    try:
        c.sendall(read_regs(7, 0, 1))
        assert reply(c)[:9] == frame(7, b"\x03\x02\0\0")[:9]
    finally:
        c.close()


@pytest.mark.parametrize(
    "pdu",
    [
        struct.pack(">BHH", 8, 0, 0x1234),  # diagnostics: echo
        struct.pack(">BHH", 8, 4, 0),  # diagnostics: force listen-only mode
        b"\x07",  # read exception status
        b"\x11",  # report server id ("Pymodbus")
        struct.pack(">BH", 24, 0),  # read FIFO queue (made-up values)
        b"\x15\x09\x06\x00\x01\x00\x00\x00\x01\x00\x05",  # write file record (did nothing)
        b"\x2b\x0e\x01\x00",  # read device identification
    ],
    ids=["fc8-echo", "fc8-listen-only", "fc7", "fc17", "fc24", "fc21", "fc43"],
)
def test_function_codes_the_map_does_not_serve_get_exception_01(server, pdu):
    _sim, port = server
    s = connect(port)
    try:
        s.sendall(frame(5, pdu))
        assert reply(s) == frame(5, bytes([pdu[0] | 0x80, 0x01]))
    finally:
        s.close()


def test_a_client_that_reads_its_replies_late_gets_every_one(server):
    """Its unread replies fill the server's send buffer: the server stops answering (and
    then reading) until they drain, and loses none."""
    _sim, port = server
    s = connect(port)
    try:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        requests = b"".join(frame(tid, struct.pack(">BHH", 4, 1000, 125)) for tid in range(600))
        sender = threading.Thread(target=s.sendall, args=(requests,), daemon=True)
        sender.start()  # 600 replies of 257 bytes: more than the buffers hold
        time.sleep(1.0)
        tids = [struct.unpack(">H", reply(s)[:2])[0] for _ in range(600)]
        sender.join(5.0)
        assert tids == list(range(600))
    finally:
        s.close()
