"""The Modbus TCP server: pymodbus's client against the register map, every function
code it serves, exceptions for unmapped addresses and unknown function codes, malformed
frames, the client limit. Loopback only, bounded loops.

The I/O bits are set and read through `modbus_map.gpio_index` (manual numbers from 1),
the one adapter between the map and the controller's I/O lists.
"""

from __future__ import annotations

import socket
import struct
import time

import pytest
from comm_helpers import WAIT, served
from pymodbus.client import ModbusTcpClient

from motionvm.comm.lineserver import MAX_CLIENTS
from motionvm.comm.modbus_map import gpio_index

PROGRAM = """
void main() {
    system_ltest3 = -2;
    system_dtest2 = 0.1;
    Enable(0);
    Enable(1);
    Till(IsEnabled(0) && IsEnabled(1));
    MoveAbs(0, 10.5);
    MoveAbs(1, -3.25);
}
"""


def words_of(value: float) -> list[int]:
    return list(struct.unpack(">HHHH", struct.pack(">d", value)))


def double_of(words: list[int]) -> float:
    return struct.unpack(">d", struct.pack(">HHHH", *words))[0]


@pytest.fixture(scope="module")
def server():
    with served(PROGRAM) as (sim, srv):
        for _ in range(250):  # bounded: until both axes have arrived (5 s)
            if sim.axis(0).pos_fb == 10.5 and sim.axis(1).pos_fb == -3.25:
                break
            time.sleep(0.02)
        yield sim, srv


@pytest.fixture
def client(server):
    c = ModbusTcpClient("127.0.0.1", port=server[1].ports["modbus"], timeout=WAIT, retries=0)
    assert c.connect()
    yield c
    c.close()


def test_coils_are_outputs_1_to_8(server, client):
    io = server[0].controller.io.gpio
    io.outputs[gpio_index(1)] = 1
    io.outputs[gpio_index(3)] = 1
    time.sleep(0.01)
    assert client.read_coils(0, count=8).bits[:8] == [1, 0, 1, 0, 0, 0, 0, 0]  # fc 1
    assert not client.write_coil(1, True).isError()  # fc 5: lands before the reply
    assert io.outputs[gpio_index(2)] == 1
    assert not client.write_coils(4, [True, False, True, True]).isError()  # fc 15
    assert [io.outputs[gpio_index(n)] for n in range(1, 9)] == [1, 1, 1, 0, 1, 0, 1, 1]
    assert not client.write_coils(0, [False] * 8).isError()
    assert client.read_coils(0, count=8).bits[:8] == [0] * 8


def test_discrete_inputs_are_inputs_1_to_8(server, client):
    io = server[0].controller.io.gpio
    io.inputs[gpio_index(2)] = 1
    io.inputs[gpio_index(8)] = 1
    time.sleep(0.01)
    assert client.read_discrete_inputs(0, count=8).bits[:8] == [0, 1, 0, 0, 0, 0, 0, 1]  # fc 2
    assert client.read_discrete_inputs(7, count=1).bits[0] == 1


def test_holding_registers_are_ltest_as_int32_high_word_first(server, client):
    sim = server[0]
    assert client.read_holding_registers(6, count=2).registers == [0xFFFF, 0xFFFE]  # fc 3
    assert not client.write_registers(0, [0x0001, 0x0002]).isError()  # fc 16
    assert sim.read("system_ltest0") == 0x00010002
    assert not client.write_register(1, 0x0005).isError()  # fc 6: the low word only
    assert sim.read("system_ltest0") == 0x00010005
    assert not client.write_registers(18, [0x8000, 0x0000]).isError()
    assert sim.read("system_ltest9") == -(2**31)


def test_holding_registers_100_on_are_dtest_as_float64(server, client):
    sim = server[0]
    regs = client.read_holding_registers(108, count=4).registers
    assert double_of(regs) == 0.1
    assert not client.write_registers(100, words_of(-1.25e-3)).isError()
    assert sim.read("system_dtest0") == -1.25e-3
    assert not client.write_registers(136, words_of(1e300)).isError()
    assert sim.read("system_dtest9") == 1e300
    assert double_of(client.read_holding_registers(136, count=4).registers) == 1e300


def test_read_write_multiple_registers(server, client):
    res = client.readwrite_registers(  # fc 23
        read_address=104, read_count=4, write_address=104, values=words_of(2.5)
    )
    assert double_of(res.registers) == 2.5
    assert server[0].read("system_dtest1") == 2.5


def test_input_registers_are_axis_feedback(server, client):
    assert double_of(client.read_input_registers(1000, count=4).registers) == 10.5  # fc 4
    assert double_of(client.read_input_registers(1004, count=4).registers) == -3.25
    assert double_of(client.read_input_registers(2000, count=4).registers) == 0.0
    assert client.read_input_registers(1002, count=2).registers == words_of(10.5)[2:]


@pytest.mark.parametrize(
    ("call", "args", "kwargs"),
    [
        ("read_coils", (8,), {}),
        ("read_coils", (6,), {"count": 3}),
        ("read_discrete_inputs", (8,), {}),
        ("read_holding_registers", (20,), {}),
        ("read_holding_registers", (18,), {"count": 3}),
        ("read_holding_registers", (99,), {}),
        ("read_holding_registers", (140,), {}),
        ("read_input_registers", (999,), {}),
        ("read_input_registers", (1000 + 4 * 8,), {}),
        ("read_input_registers", (2000 + 4 * 8,), {}),
        ("write_coil", (8, True), {}),
        ("write_register", (20, 1), {}),
        ("write_registers", (139, [1, 2]), {}),
    ],
)
def test_addresses_outside_the_map_get_exception_02(client, call, args, kwargs):
    res = getattr(client, call)(*args, **kwargs)
    assert res.isError()
    assert res.exception_code == 2


def test_an_unmapped_write_changes_nothing(server, client):
    sim = server[0]
    before = sim.read("system_dtest9")
    assert client.write_registers(138, [1, 2, 3]).exception_code == 2
    assert sim.read("system_dtest9") == before


def _raw(port: int) -> socket.socket:
    return socket.create_connection(("127.0.0.1", port), timeout=WAIT)


def _reply(sock: socket.socket) -> bytes:
    head = b""
    while len(head) < 7:
        chunk = sock.recv(7 - len(head))
        if not chunk:
            return b""
        head += chunk
    length = struct.unpack(">H", head[4:6])[0]
    body = b""
    while len(body) < length - 1:
        body += sock.recv(length - 1 - len(body))
    return head + body


def test_an_unknown_function_code_gets_exception_01(server):
    s = _raw(server[1].ports["modbus"])
    s.sendall(struct.pack(">HHHBB", 7, 0, 2, 1, 0x41))
    assert _reply(s) == struct.pack(">HHHBBB", 7, 0, 3, 1, 0xC1, 0x01)
    s.close()


def test_a_literal_frame_reads_a_register(server):
    s = _raw(server[1].ports["modbus"])
    s.sendall(bytes.fromhex("00 2a 00 00 00 06 01 03 00 06 00 02"))
    assert _reply(s) == bytes.fromhex("00 2a 00 00 00 07 01 03 04 ff ff ff fe")
    s.close()


@pytest.mark.parametrize(
    "junk",
    [
        b"hello modbus\r\n",
        bytes(range(256)),
        struct.pack(">HHHB", 1, 0, 0xFFFF, 1) + b"\x03" * 300,
        struct.pack(">HHHBBHH", 1, 0, 6, 1, 3, 0, 0),  # a count of 0
        struct.pack(">HHHBBHH", 1, 0, 6, 1, 3, 0, 200),  # more than 125 registers
    ],
)
def test_malformed_frames_get_an_exception_or_a_closed_connection(server, junk):
    port = server[1].ports["modbus"]
    s = _raw(port)
    s.settimeout(1.0)
    s.sendall(junk)
    try:
        reply = _reply(s)
    except (TimeoutError, ConnectionError):
        reply = b""
    if reply:
        assert reply[7] & 0x80  # an exception response
    else:  # or a closed connection
        assert s.recv(10) == b""
    s.close()
    c = ModbusTcpClient("127.0.0.1", port=port, timeout=WAIT, retries=0)  # still serving
    assert c.connect()
    assert c.read_holding_registers(6, count=2).registers == [0xFFFF, 0xFFFE]
    c.close()


def test_the_client_after_the_eighth_is_closed(server):
    port = server[1].ports["modbus"]
    clients = []
    for _ in range(MAX_CLIENTS):
        c = ModbusTcpClient("127.0.0.1", port=port, timeout=WAIT, retries=0)
        assert c.connect()
        assert not c.read_coils(0, count=1).isError()
        clients.append(c)
    extra = _raw(port)
    extra.settimeout(WAIT)
    assert extra.recv(10) == b""
    extra.close()
    for c in clients:
        c.close()


@pytest.mark.parametrize("refused", [0x2B, 0x41])
def test_an_exception_reply_keeps_its_place_behind_an_earlier_request(server, refused):
    """A read, then a request refused before the map (FC 0x2B, an unknown code), in ONE
    packet: the replies come back in request order, every time."""
    s = _raw(server[1].ports["modbus"])
    for i in range(20):
        read = struct.pack(">HHHBBHH", 2 * i, 0, 6, 1, 3, 6, 2)
        other = struct.pack(">HHHBBBBB", 2 * i + 1, 0, 5, 1, refused, 0x0E, 1, 0)
        s.sendall(read + other)
        first, second = _reply(s), _reply(s)
        assert first == struct.pack(">HHHBBB", 2 * i, 0, 7, 1, 3, 4) + b"\xff\xff\xff\xfe"
        assert second == struct.pack(">HHHBBB", 2 * i + 1, 0, 3, 1, refused | 0x80, 0x01)
    s.close()
