"""The Modbus client built-ins against a peer that answers wrongly: a response that is
not the request's is eERR_MODBUS_JOB_FAIL (0x1840), one that trickles in past the
client timeout eERR_MODBUS_JOB_TIMEOUT (0x183F); never an internal error, never a
short answer taken as data. A raw loopback peer; every wait bounded."""

from __future__ import annotations

import socket
import threading
import time

import pytest

from motionvm.api import Simulation

JOB_FAIL, JOB_TIMEOUT = 0x1840, 0x183F
WAIT = 5.0


def peer(answer) -> tuple[int, threading.Thread]:
    """A one-connection peer on a free loopback port: `answer(conn, tid)` replies to the
    first request it receives."""
    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(WAIT)
    port = listener.getsockname()[1]

    def main() -> None:
        with listener:
            try:
                conn, _ = listener.accept()
            except OSError:
                return
            with conn:
                conn.settimeout(WAIT)
                try:
                    request = conn.recv(300)
                    answer(conn, request[:2])
                    time.sleep(0.1)
                except OSError:
                    pass

    thread = threading.Thread(target=main, daemon=True)
    thread.start()
    return port, thread


def drip(conn: socket.socket, tid: bytes) -> None:
    for byte in tid + b"\0\0\0\x07\x01\x03\x04\0\x01\0\x02":  # a good answer, 0.3 s a byte
        conn.sendall(bytes([byte]))
        time.sleep(0.3)


ANSWERS = {
    "only-the-function-code": (3, lambda c, tid: c.sendall(tid + b"\0\0\0\x02\x01\x03"), JOB_FAIL),
    "byte-count-lies": (3, lambda c, tid: c.sendall(tid + b"\0\0\0\x04\x01\x03\xff\x12"), JOB_FAIL),
    "fewer-registers": (3, lambda c, tid: c.sendall(tid + b"\0\0\0\x05\x01\x03\x02\0\x01"), JOB_FAIL),
    "write-not-echoed": (16, lambda c, tid: c.sendall(tid + b"\0\0\0\x02\x01\x10"), JOB_FAIL),
    "write-echo-differs": (16, lambda c, tid: c.sendall(tid + b"\0\0\0\x06\x01\x10\0\x09\0\x02"),
                           JOB_FAIL),
    "trickles-past-the-timeout": (3, drip, JOB_TIMEOUT),
}  # fmt: skip


@pytest.mark.parametrize(("fc", "answer", "code"), ANSWERS.values(), ids=ANSWERS.keys())
def test_a_response_that_does_not_answer_the_request_is_an_error_code(fc, answer, code):
    port, thread = peer(answer)
    call = (
        "Modbus_ClientWrite_HoldReg(sid, 0, 2, w, out, &n)"
        if fc == 16
        else "Modbus_ClientRead_HoldReg(sid, 0, 2, out, &n)"
    )
    program = f"""uint8_t out[300]; uint16_t w[4]; int n = -1; int sid;
void main() {{
    int r = Modbus_ClientConnect("127.0.0.1:{port}", &sid);
    Print("connect %x", r);
    r = {call};
    Print("r=%x n=%d", r, n);
}}
"""
    start = time.monotonic()
    with Simulation.from_source(program) as sim:
        sim.run(until=5.0)
        assert sim.fault_count == 0
        assert sim.messages == ["connect 0", f"r={code:x} n=-1"]
    assert time.monotonic() - start < 2.5  # the client timeout (1 s) bounds the wait
    thread.join(WAIT)
