"""Who may use the servers: the token handshake of the ASCII servers, read-only Native
ASCII and Modbus, the warning when the servers listen beyond loopback, and the access
keys through `Simulation.serve`. Real loopback sockets, bounded waits."""

from __future__ import annotations

import time

import pytest
from comm_helpers import WAIT, LineClient, served
from pymodbus.client import ModbusTcpClient

from motionvm.api import Simulation
from motionvm.comm.config import CommConfig
from motionvm.comm.gate import WRONG_TOKEN
from motionvm.comm.modbus_map import gpio_index

TOKEN = "s3cret token"

PROGRAM = """
void Agent(char *cmd, char *res) {
    HIMC_GPO(2) = 1;
    StringCopy(res, cmd);
}
void main() {
    START_ASCII_AGENT(Agent);
    while (1) {
        Till(system_ltest9 != 0);
        ASCII_ServerBroadcast("news", 4);
        system_ltest9 = 0;
    }
}
"""


def _modbus(port: int) -> ModbusTcpClient:
    c = ModbusTcpClient("127.0.0.1", port=port, timeout=WAIT, retries=0)
    assert c.connect()
    return c


@pytest.fixture(scope="module")
def locked():
    with served(PROGRAM, access={"token": TOKEN}) as (sim, srv):
        yield sim, srv


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_a_wrong_token_closes_the_connection_and_nothing_after_it_runs(locked, name):
    sim, srv = locked
    c = LineClient(srv.ports[name])
    c.send(b"HIMC_GPO(1, 1)\r\nsystem_ltest0 = 7\r\n")
    assert c.rest() == WRONG_TOKEN.encode() + b"\r\n"
    c.close()
    gpo = sim.controller.io.gpio.outputs
    assert (gpo[gpio_index(1)], gpo[gpio_index(2)]) == (0, 0)
    assert sim.read("system_ltest0") == 0


def test_the_token_then_requests(locked):
    sim, srv = locked
    native = LineClient(srv.ports["native-ascii"])
    assert native.ask(TOKEN) == "OK"
    assert native.ask("system_ltest1 = 3") == "OK"
    assert native.ask("system_ltest1") == "3"
    native.close()
    user = LineClient(srv.ports["user-ascii"])
    assert user.ask(TOKEN) == "OK"
    assert user.ask("hello") == "hello"
    user.close()


def test_a_broadcast_reaches_only_connections_past_the_token(locked):
    sim, srv = locked
    member, stranger = LineClient(srv.ports["user-ascii"]), LineClient(srv.ports["user-ascii"])
    assert member.ask(TOKEN) == "OK"
    native = LineClient(srv.ports["native-ascii"])
    assert native.ask(TOKEN) == "OK"
    assert native.ask("system_ltest9 = 1") == "OK"
    member.sock.settimeout(WAIT)
    assert member.sock.recv(4) == b"news"
    stranger.sock.settimeout(0.3)
    with pytest.raises(TimeoutError):
        stranger.sock.recv(4)
    for c in (member, stranger, native):
        c.close()


def test_with_a_token_modbus_reads_but_refuses_writes(locked):
    sim, srv = locked
    c = _modbus(srv.ports["modbus"])
    assert not c.read_holding_registers(0, count=2).isError()
    for res in (
        c.write_coil(0, True),
        c.write_register(0, 5),
        c.write_registers(100, [1, 2, 3, 4]),
        c.readwrite_registers(read_address=0, read_count=2, write_address=0, values=[1, 2]),
    ):
        assert res.isError() and res.exception_code == 1
    c.close()
    assert sim.controller.io.gpio.outputs[gpio_index(1)] == 0
    assert sim.read("system_ltest0") == 0
    assert sim.read("system_dtest0") == 0.0


def test_modbus_may_write_with_a_token_when_told():
    with served(PROGRAM, access={"token": TOKEN, "modbus_read_only": False}) as (sim, srv):
        c = _modbus(srv.ports["modbus"])
        assert not c.write_register(1, 5).isError()
        c.close()
        assert sim.read("system_ltest0") == 5


READ_ONLY = """
int count = 4;
void main() { HIMC_GPO(3) = 1; }
"""


@pytest.fixture(scope="module")
def read_only():
    access = {"native_ascii_read_only": True, "modbus_read_only": True}
    with served(READ_ONLY, access=access) as (sim, srv):
        for _ in range(250):  # bounded: until the task has set output 3 (5 s)
            if sim.controller.io.gpio.outputs[gpio_index(3)]:
                break
            time.sleep(0.02)
        yield sim, srv


@pytest.mark.parametrize(
    ("request_", "reply"),
    [
        ("count", "4"),
        ("system_ltest0", "0"),
        ("HIMC_GPO(3)", "1"),
        ("HIMC_GPI(1)", "0"),
        ("IsEnabled(0)", "0"),
        ("GetPosFb(0)", "0.0"),
        ('StringLen("abc")', "3"),
    ],
)
def test_read_only_native_ascii_serves_reads_and_queries(read_only, request_, reply):
    c = LineClient(read_only[1].ports["native-ascii"])
    assert c.ask(request_) == reply
    c.close()


@pytest.mark.parametrize(
    ("request_", "reply"),
    [
        ("count = 5", "ERR read-only server: 'count' cannot be written"),
        ("HIMC_GPO(1, 1)", "ERR read-only server: HIMC_GPO may change the machine"),
        ("Enable(0)", "ERR read-only server: Enable may change the machine"),
        ("MoveAbs(0, 10)", "ERR read-only server: MoveAbs may change the machine"),
        ("EStop()", "ERR read-only server: EStop may change the machine"),
        ("StopAllTask()", "ERR read-only server: StopAllTask may change the machine"),
        ("SaveUserTable()", "ERR read-only server: SaveUserTable may change the machine"),
    ],
)
def test_read_only_native_ascii_refuses_what_changes_the_machine(
    read_only, request_, reply, data_dir
):
    sim, srv = read_only
    c = LineClient(srv.ports["native-ascii"])
    assert c.ask(request_).startswith(reply)
    assert c.ask("count") == "4"  # the connection goes on
    c.close()
    assert sim.read("count") == 4
    assert sim.controller.io.gpio.outputs[gpio_index(1)] == 0
    assert not sim.axis(0).enabled
    assert not any(data_dir.iterdir())


def test_read_only_modbus_refuses_writes_with_exception_01(read_only):
    sim, srv = read_only
    c = _modbus(srv.ports["modbus"])
    assert c.read_coils(0, count=3).bits[:3] == [0, 0, 1]
    res = c.write_coils(0, [True, True])
    assert res.isError() and res.exception_code == 1
    assert c.read_coils(0, count=3).bits[:3] == [0, 0, 1]
    c.close()


def test_user_ascii_has_no_read_only_mode():
    assert not CommConfig(native_ascii_read_only=True, token="t").read_only("user-ascii")


def test_serve_takes_the_machine_files_access_keys(tmp_path):
    machine = tmp_path / "m.toml"
    machine.write_text(f'[comm]\ntoken = "{TOKEN}"\nidle_timeout = 5\n')
    sim = Simulation.from_source(READ_ONLY, machine=str(machine))
    with sim, sim.serve() as srv:
        c = LineClient(srv.ports["native-ascii"])
        c.send(b"count\r\n")
        assert c.rest() == WRONG_TOKEN.encode() + b"\r\n"
        c.close()


def test_serve_checks_its_access_arguments():
    with Simulation.from_source(READ_ONLY) as sim:
        with pytest.raises(ValueError, match="idle_timeout = -1: must be a number"):
            sim.serve(idle_timeout=-1)
        with pytest.raises(ValueError, match="token = '': must not be empty"):
            sim.serve(token="")
        with pytest.raises(TypeError, match="'tokn'"):
            sim.serve(tokn="x")


def test_serving_beyond_loopback_reports_a_warning(monkeypatch):
    """The warning goes where the run's notes go (stderr under `motionvm serve`). The
    servers listen on loopback here: the test only pretends they do not."""
    monkeypatch.setattr(CommConfig, "exposure_warning", lambda self: "motionvm: warning: W")
    with Simulation.from_source(READ_ONLY) as sim, sim.serve():
        pass
    assert "motionvm: warning: W" in [str(f) for f in sim.faults]
