"""The Native ASCII server over raw loopback sockets: built-in calls, variables, errors."""

from __future__ import annotations

import time

import pytest
from comm_helpers import LineClient, served

from motionvm.api import Simulation
from motionvm.lang.hmpl.catalog import builtin_signatures
from motionvm.lang.hmpl.lib import implemented_builtins

PROGRAM = """
int count = 5;
void main() {
    Print("ready");
}
"""


@pytest.fixture(scope="module")
def server():
    with served(PROGRAM) as (sim, srv):
        yield sim, srv


@pytest.fixture
def client(server):
    c = LineClient(server[1].ports["native-ascii"])
    yield c
    c.close()


def poll(client: LineClient, request: str, want: str, tries: int = 250) -> str:
    """Ask `request` until it answers `want` (at most `tries` times, 20 ms apart)."""
    reply = ""
    for _ in range(tries):
        reply = client.ask(request)
        if reply == want:
            return reply
        time.sleep(0.02)
    return reply


def test_a_call_replies_its_return_value_then_its_out_parameters(client):
    reply = client.ask("GetFirmwareVer()")
    assert reply.startswith('0 "motionvm ') and reply.endswith('"')
    assert client.ask('StringLen("hello")') == "5"
    assert client.ask("IsTaskStop(0)") in ("0", "1")


def test_system_and_global_variables_read_and_write(client):
    assert client.ask("system_dtest0 = 1.5") == "OK"
    assert client.ask("system_dtest0") == "1.5"
    assert client.ask("system_dtest1 = 0.1;") == "OK"
    assert client.ask("system_dtest1") == "0.1"
    assert client.ask("system_ltest2 = 0x7fffffff") == "OK"
    assert client.ask("system_ltest2") == "2147483647"
    assert client.ask("system_ltest2 = 2147483648") == "OK"  # wraps as an int assignment
    assert client.ask("system_ltest2") == "-2147483648"
    assert client.ask("count") == "5"
    assert client.ask("count = 7") == "OK"
    assert client.ask("count") == "7"
    assert client.ask("system_dtest3 = PI") == "OK"
    assert float(client.ask("system_dtest3")) == pytest.approx(3.141592653589793)


def test_a_call_moves_an_axis_as_a_task_would(client):
    assert client.ask("Enable(0)") == "0"
    assert poll(client, "IsEnabled(0)", "1") == "1"
    assert client.ask("MoveAbs(0, 10.5)") == "0"
    assert poll(client, "GetPosFb(0)", "10.5") == "10.5"
    assert client.ask("HIMC_GPO(1, 1)") == "OK"
    assert client.ask("HIMC_GPO(1)") == "1"


def test_the_error_code_is_the_one_a_task_gets():
    """MoveAbs of a disabled axis returns the same code over Native ASCII as in a task."""
    with Simulation.from_source('void main() { Print("%d", MoveAbs(1, 10.5)); }') as sim:
        sim.run(until=0.01)
        in_task = sim.messages[0]
    with served("void main() { }") as (_sim, srv):
        c = LineClient(srv.ports["native-ascii"])
        assert c.ask("MoveAbs(1, 10.5)") == in_task
        c.close()
    assert int(in_task) != 0


def test_requests_that_cannot_run_get_err_with_a_reason(client):
    assert client.ask("GetPosFB(0)") == "ERR unknown function 'GetPosFB' (did you mean 'GetPosFb'?)"
    assert client.ask("MoveAbs(0)") == (
        "ERR MoveAbs takes 2 arguments, got 1 (int MoveAbs(int axis_id, double pos);)"
    )
    assert client.ask('MoveAbs("x", 1)') == (
        "ERR argument 'axis_id' of MoveAbs is an integer (int), got a string"
    )
    assert client.ask("Sleep(5)") == (
        "ERR Sleep only makes sense inside a task; it cannot be called over Native ASCII"
    )
    assert client.ask("Till(1)") == (
        "ERR Till waits inside a task; it cannot be called over Native ASCII"
    )
    assert client.ask("system_timeInMs = 0") == (
        "ERR system_timeInMs is read-only (the controller sets it every cycle)"
    )
    assert client.ask("cuont") == "ERR unknown variable 'cuont' (did you mean 'count'?)"
    assert client.ask("MoveAbs(0, HMPL_ABZ)").startswith("ERR unknown constant 'HMPL_ABZ'")
    assert client.ask("StringLen(0)") == "ERR null StringLen string pointer"
    assert client.ask("MoveAbs(0 10)") == "ERR expected ',' or ')' in the call of 'MoveAbs'"


def test_array_and_struct_variables_are_errors_about_the_variable():
    """The Native ASCII errors of a variable that is not one number name the variable
    and what a request can do, not a scope channel."""
    program = "int table[4]; int x; struct P { int a; } p;\nvoid main() { }\n"
    with served(program) as (_sim, srv):
        c = LineClient(srv.ports["native-ascii"])
        replies = {r: c.ask(r) for r in ("table", "table[9] = 1", "x[1]", "p", "p = 1")}
        c.close()
    assert replies == {
        "table": "ERR variable 'table' is an array of 4; read or write one element, "
        "e.g. 'table[0]'",
        "table[9] = 1": "ERR variable 'table[9]': index 9 is out of range for table[4] (0..3)",
        "x[1]": "ERR variable 'x[1]': 'x' is not an array",
        "p": "ERR variable 'p' is a struct P; Native ASCII reads and writes numbers only",
        "p = 1": "ERR variable 'p' is a struct P; Native ASCII reads and writes numbers only",
    }
    assert not any("scope" in r for r in replies.values())


def test_print_converts_a_wide_integer_as_a_task_would(server, client):
    """`%d` prints the low 32 bits of a 64-bit constant, `%lld` all of it, exactly what
    the same Print in a task prints; a constant beyond 64 bits is refused like in C."""
    sim = server[0]
    requests = [
        'Print("w %d", 4294967297)',
        'Print("w %d", 18446744073709551615)',
        'Print("w %lld", 9223372036854775807)',
        'Print("w %u", -1)',
    ]
    replies = [client.ask(r) for r in requests]
    assert all(not r.startswith("ERR") for r in replies), replies
    lines = []
    for _ in range(250):
        lines = [m for m in sim.messages if m.startswith("w ")]
        if len(lines) == 4:
            break
        time.sleep(0.02)
    task = Simulation.from_source("void main() {\n" + ";\n".join(requests) + ";\n}\n")
    task.run()
    assert lines == task.messages == ["w 1", "w -1", "w 9223372036854775807", "w 4294967295"]
    reply = client.ask('Print("%d", 99999999999999999999)')
    assert reply == (
        "ERR integer constant '99999999999999999999' is too large "
        "(the limit is 18446744073709551615)"
    )


def test_a_built_in_not_implemented_is_named(monkeypatch):
    # every built-in is implemented: take one away, as a library that failed to provide it
    name = "GetGrpCmdNum"
    impl = dict(implemented_builtins())
    del impl[name]
    monkeypatch.setattr("motionvm.lang.hmpl.rtcomm.implemented_builtins", lambda: impl)
    sig = builtin_signatures()[name]
    with served("void main() { }") as (_sim, srv):
        c = LineClient(srv.ports["native-ascii"])
        assert c.ask(f"{name}()") == f"ERR {name} (manual {sig.section}) is not implemented"
        c.close()


def test_cr_lf_and_crlf_each_end_a_line(client):
    client.send(b"system_ltest0 = 1\rsystem_ltest0\nsystem_ltest0 = 2\r\nsystem_ltest0\r\n")
    assert [client.line() for _ in range(4)] == ["OK", "1", "OK", "2"]


def test_the_controller_keeps_running_after_every_task_ended(server, client):
    sim, srv = server
    assert "ready" in sim.messages
    t0 = sim.time
    client.ask("count")
    time.sleep(0.05)
    client.ask("count")
    assert sim.time > t0 and srv.running
