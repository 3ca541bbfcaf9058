"""The idle timeout of every server: clients that send no complete request for
`idle_timeout` seconds (a one-byte trickle included) are closed, so slow sockets cannot
hold every place for longer; a client that asks in time, or waits for a slow answer,
stays. Real loopback sockets, a short timeout, loops bounded in count and wall time."""

from __future__ import annotations

import socket
import struct
import time

import pytest
from comm_helpers import WAIT, LineClient, served
from pymodbus.client import ModbusTcpClient

from motionvm.comm.lineserver import MAX_CLIENTS

IDLE = 0.6
"""The servers' idle timeout in these tests [s wall]."""

PROGRAM = """
void Agent(char *cmd, char *res) {
    if (cmd[0] == 's') { Sleep(1500); }
    StringCopy(res, cmd);
}
void main() { START_ASCII_AGENT(Agent); }
"""

PROBES = [("native-ascii", "system_ltest0"), ("user-ascii", "hi")]
"""A request each ASCII server answers."""


@pytest.fixture(scope="module")
def server():
    with served(PROGRAM, access={"idle_timeout": IDLE}) as (sim, srv):
        yield sim, srv


def _trickle(socks: list[socket.socket], data: bytes, seconds: float) -> int:
    """Send `data` one byte each 0.1 s on every socket for `seconds` [wall] or until every
    one is closed; the number still open."""
    open_ = list(socks)
    for k in range(int(seconds / 0.1)):
        for s in list(open_):
            try:
                s.sendall(data[k % len(data) : k % len(data) + 1])
            except OSError:
                open_.remove(s)
        if not open_:
            break
        time.sleep(0.1)
    return len(open_)


def _closed(s: socket.socket) -> bool:
    """Whether the server has closed `s` (what it sent before is skipped)."""
    s.settimeout(WAIT)
    try:
        while True:
            chunk = s.recv(4096)
            if not chunk:
                return True
    except ConnectionResetError:
        return True
    except TimeoutError:
        return False


@pytest.mark.parametrize(("name", "probe"), PROBES)
def test_trickling_clients_are_dropped_and_their_places_freed(server, name, probe):
    port = server[1].ports[name]
    slow = [socket.create_connection(("127.0.0.1", port), timeout=WAIT) for _ in range(MAX_CLIENTS)]
    time.sleep(0.1)
    refused = LineClient(port)
    assert refused.line() == f"ERR too many clients ({MAX_CLIENTS})"
    refused.close()
    _trickle(slow, b"x", 3 * IDLE)  # never a whole line
    for s in slow:
        assert _closed(s)
        s.close()
    c = LineClient(port)
    assert c.ask(probe) != f"ERR too many clients ({MAX_CLIENTS})"
    c.close()


def test_the_idle_client_is_told_why(server):
    c = LineClient(server[1].ports["native-ascii"])
    c.send(b"coun")
    started = time.monotonic()
    assert c.line() == f"ERR idle for {IDLE:g} s: connection closed"
    assert IDLE * 0.9 <= time.monotonic() - started <= IDLE + 2.0
    assert c.rest() == b""
    c.close()


@pytest.mark.parametrize(("name", "probe"), PROBES)
def test_a_client_that_asks_in_time_stays(server, name, probe):
    c = LineClient(server[1].ports[name])
    for _ in range(int(3 * IDLE / 0.2)):
        assert not c.ask(probe).startswith("ERR idle")
        time.sleep(0.2)
    c.close()


def test_waiting_for_a_slow_answer_is_not_idle(server):
    c = LineClient(server[1].ports["user-ascii"])
    assert c.ask("slow") == "slow"  # the parser sleeps 1.5 s, longer than the timeout
    assert c.ask("again") == "again"
    c.close()


def test_modbus_drops_trickling_clients_and_frees_their_places(server):
    port = server[1].ports["modbus"]
    slow = [socket.create_connection(("127.0.0.1", port), timeout=WAIT) for _ in range(MAX_CLIENTS)]
    time.sleep(0.1)
    extra = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
    assert _closed(extra)  # over the limit
    extra.close()
    frame = struct.pack(">HHHBB", 1, 0, 254, 1, 16) + bytes(252)  # a frame of 254 bytes
    _trickle(slow, frame, 3 * IDLE)  # that never completes
    for s in slow:
        assert _closed(s)
        s.close()
    c = ModbusTcpClient("127.0.0.1", port=port, timeout=WAIT, retries=0)
    assert c.connect()
    assert not c.read_coils(0, count=1).isError()
    c.close()


def test_a_modbus_client_that_asks_in_time_stays(server):
    port = server[1].ports["modbus"]
    s = socket.create_connection(("127.0.0.1", port), timeout=WAIT)
    for i in range(int(3 * IDLE / 0.2)):
        s.sendall(struct.pack(">HHHBBHH", i, 0, 6, 1, 1, 0, 1))
        assert len(s.recv(64)) == 10  # the coil read's reply
        time.sleep(0.2)
    s.close()


def test_idle_timeout_0_never_drops():
    with served(PROGRAM, access={"idle_timeout": 0}) as (sim, srv):
        c = LineClient(srv.ports["native-ascii"])
        c.send(b"cou")
        c.sock.settimeout(1.0)
        with pytest.raises(TimeoutError):
            c.sock.recv(10)
        c.send(b"nt\r\n")
        c.sock.settimeout(WAIT)
        assert c.line().startswith("ERR unknown variable 'count'")
        c.close()


def _reset_within(s: socket.socket, data: bytes, seconds: float) -> bool:
    """Whether the server drops `s` within `seconds` [wall]: keep offering `data` without
    ever reading until a send fails."""
    s.setblocking(False)
    for _ in range(int(seconds / 0.05)):
        try:
            s.send(data)
        except BlockingIOError:  # the server does not read either: its buffers are full
            pass
        except OSError:  # reset, or a broken pipe
            return True
        time.sleep(0.05)
    return False


def _non_reader(port: int) -> socket.socket:
    """A client with a small receive buffer, so unread replies back up soon."""
    s = socket.socket()
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.settimeout(WAIT)
    s.connect(("127.0.0.1", port))
    return s


BIG_REPLY = """
void Agent(char *cmd, char *res) {
    int i = 0;
    for (; i < 2000; i++) { res[i] = 'y'; }
    res[i] = 0;
}
void main() { START_ASCII_AGENT(Agent); }
"""


def test_a_client_that_reads_no_reply_is_dropped():
    """Requests keep coming, replies are never read: once its replies fill the buffers,
    the client is idle as far as the server can serve it, and is dropped."""
    with served(BIG_REPLY, access={"idle_timeout": IDLE}) as (sim, srv):
        s = _non_reader(srv.ports["user-ascii"])
        assert _reset_within(s, b"a\n" * 50, 20.0)
        s.close()
        c = LineClient(srv.ports["user-ascii"])
        assert len(c.ask("a")) == 2000  # the server goes on
        c.close()


def test_a_modbus_client_that_reads_no_reply_is_dropped(server):
    port = server[1].ports["modbus"]
    s = _non_reader(port)
    read_40 = struct.pack(">HHHBBHH", 1, 0, 6, 1, 3, 100, 40)  # 89-byte replies
    assert _reset_within(s, read_40 * 20, 20.0)
    s.close()
