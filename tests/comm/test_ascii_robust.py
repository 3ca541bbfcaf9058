"""Both ASCII servers under abuse: long lines, floods, too many clients, vanishing
clients, bytes that are not text. Loops are bounded in count and wall time."""

from __future__ import annotations

import socket
import time

import pytest
from comm_helpers import WAIT, LineClient, served

from motionvm.comm.lineserver import MAX_CLIENTS, MAX_LINE

PROGRAM = """
void Echo(char *cmd, char *res) { StringCopy(res, cmd); }
void main() { START_ASCII_AGENT(Echo); }
"""


@pytest.fixture(scope="module")
def server():
    # no idle timeout (test_idle_timeout.py tests it): a CI machine stalled for 30 s
    # would drop a client that waits its turn and free a place the tests count on
    with served(PROGRAM, access={"idle_timeout": 0}) as (sim, srv):
        yield sim, srv


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_a_line_too_long_is_refused_and_the_next_one_served(server, name):
    c = LineClient(server[1].ports[name])
    c.send(b"x" * (MAX_LINE + 1) + b"\n")
    assert c.line() == "ERR line too long"
    c.send(b"y" * 5000)  # long before its end arrives: one refusal, the rest discarded
    assert c.line() == "ERR line too long"
    c.send(b"y" * 5000 + b"\r\n")
    expect = "0" if name == "native-ascii" else "ok"
    assert c.ask("IsTaskStop(5)" if name == "native-ascii" else "ok") in (expect, "1")
    c.close()


def test_a_line_of_exactly_the_limit_is_served(server):
    c = LineClient(server[1].ports["user-ascii"])
    assert c.ask("z" * MAX_LINE) == "z" * MAX_LINE
    c.close()


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_a_flood_of_requests_is_answered_in_order(server, name):
    n = 300
    c = LineClient(server[1].ports[name])
    if name == "native-ascii":
        lines = [f"system_ltest1 = {i}" if i % 2 == 0 else "system_ltest1" for i in range(n)]
        want = ["OK" if i % 2 == 0 else str(i - 1) for i in range(n)]
    else:
        lines = [f"line {i}" for i in range(n)]
        want = lines
    c.send(("\n".join(lines) + "\n").encode())
    got = [c.line() for _ in range(n)]
    assert got == want
    c.close()


def test_bytes_that_are_not_text_do_not_stop_the_server(server):
    c = LineClient(server[1].ports["native-ascii"])
    c.send(bytes(range(256)).replace(b"\n", b"").replace(b"\r", b"") + b"\n")
    assert c.line().startswith("ERR ")
    c.send(b"\x00\xff(\n")
    assert c.line().startswith("ERR ")
    assert c.ask("system_ltest9").lstrip("-").isdigit()
    c.close()


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_the_client_after_the_eighth_is_refused_politely(server, name):
    port = server[1].ports[name]
    clients = [LineClient(port) for _ in range(MAX_CLIENTS)]
    probe = "count" if name == "native-ascii" else "hi"
    for c in clients:  # every one of them is served
        c.ask(probe)
    extra = LineClient(port)
    assert extra.line() == f"ERR too many clients ({MAX_CLIENTS})"
    assert extra.sock.recv(100) == b""  # then closed
    extra.close()
    clients.pop().close()
    for _ in range(100):  # the freed slot is taken by the next client (bounded: 2 s)
        again = LineClient(port)
        again.send(probe.encode() + b"\n")
        reply = again.line()
        again.close()
        if not reply.startswith("ERR too many"):
            break
        time.sleep(0.02)
    assert not reply.startswith("ERR too many")
    for c in clients:
        c.close()


def test_a_client_vanishing_mid_request_loses_nothing(server):
    """Complete lines sent just before the client went away are still carried out."""
    port = server[1].ports["native-ascii"]
    s = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
    s.sendall(b"system_ltest5 = 42\nsystem_ltest6 = 43\nsystem_ltest7 = 4")  # last incomplete
    s.close()
    c = LineClient(port)
    for _ in range(100):  # bounded: 2 s
        if c.ask("system_ltest6") == "43":
            break
        time.sleep(0.02)
    assert c.ask("system_ltest5") == "42"
    assert c.ask("system_ltest6") == "43"
    assert c.ask("system_ltest7") == "0"  # an unterminated rest is no request
    c.close()


def test_a_reset_connection_leaves_the_controller_running(server):
    sim, srv = server
    port = srv.ports["user-ascii"]
    for _ in range(20):
        s = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
        s.sendall(b"abc\n")
        s.close()  # RST
    for _ in range(100):  # their lines are still carried out, then their slots free up
        c = LineClient(port)
        reply = c.ask("still here")
        c.close()
        if reply == "still here":
            break
        time.sleep(0.02)
    assert reply == "still here"
    assert srv.running and sim.fault_count == 0


def test_a_client_that_never_reads_its_replies_is_throttled(server):
    """A flood from a client that reads nothing: TCP flow control stops the server from
    reading more of it; the other clients are served meanwhile; nothing piles up."""
    port = server[1].ports["native-ascii"]
    flood = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
    flood.setblocking(False)
    line = b"system_ltest8 = 1\n"
    sent = 0
    deadline = time.monotonic() + 3.0
    while time.monotonic() < deadline and sent < 50_000_000:  # bounded in time and bytes
        try:
            sent += flood.send(line * 4096)
        except BlockingIOError:
            time.sleep(0.01)
    assert sent < 50_000_000  # the server stopped taking it in
    other = LineClient(port)
    assert other.ask("system_ltest8") == "1"
    other.close()
    flood.close()
