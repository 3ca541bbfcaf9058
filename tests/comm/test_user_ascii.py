"""The User ASCII server: START_ASCII_AGENT's two manual examples and
ASCII_ServerBroadcast, over raw loopback sockets."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from comm_helpers import LineClient, served

from motionvm.api import SessionError, Simulation

PROGRAMS = Path(__file__).parent / "programs"


def _serve_file(name: str):
    sim = Simulation.from_files([PROGRAMS / name])
    return sim, sim.serve()


def test_example_1_adds_one_to_each_character():
    """Manual 21.2.1 example 1 as printed ('hello' -> 'ifmmp'; the manual's comment
    'ifmp' drops a letter)."""
    sim, srv = _serve_file("ascii_agent_example1.hmpl")
    with sim, srv:
        c = LineClient(srv.ports["user-ascii"])
        assert c.ask("hello") == "ifmmp"
        assert c.ask("asdf") == "bteg"
        c.send(b"abc\rxyz\r\n")
        assert [c.line(), c.line()] == ["bcd", "yz{"]
        c.close()
        assert sim.fault_count == 0


def test_example_2_parses_commands_that_move_an_axis():
    """Manual 21.2.1 example 2 (repaired): ENABLE 0, MOVEABS 0 0.05, MOVEREL 0 0.01."""
    sim, srv = _serve_file("ascii_agent_example2.hmpl")
    with sim, srv:
        c = LineClient(srv.ports["user-ascii"])
        assert c.ask("ENABLE 0") == ""  # the parser writes no response
        assert sim.messages[-3:] == ["ENABLE", "0", "token number: 2"]
        for _ in range(100):  # bounded: 2 s of wall time
            if sim.axis(0).enabled:
                break
            time.sleep(0.02)
        assert c.ask("MOVEABS 0 0.05") == ""
        for _ in range(100):
            if abs(sim.axis(0).pos_fb - 0.05) < 1e-9:
                break
            time.sleep(0.02)
        assert abs(sim.axis(0).pos_fb - 0.05) < 1e-9
        assert sim.messages[-4:] == ["MOVEABS", "0", "0.05", "token number: 3"]
        assert c.ask("MOVEREL 0 0.01") == ""
        for _ in range(100):
            if abs(sim.axis(0).pos_fb - 0.06) < 1e-9:
                break
            time.sleep(0.02)
        assert abs(sim.axis(0).pos_fb - 0.06) < 1e-9
        assert c.ask("STOP 0") == ""
        c.close()
        assert sim.fault_count == 0


def test_without_an_agent_a_line_gets_err():
    with served("void main() { }") as (_sim, srv):
        c = LineClient(srv.ports["user-ascii"])
        assert c.ask("hello") == (
            "ERR no ASCII agent is running (the program calls START_ASCII_AGENT)"
        )
        c.close()


def test_a_parser_that_waits_answers_later_without_stopping_the_others():
    program = """
    void Slow(char *cmd, char *res) {
        Sleep(50);
        StringCopy(res, "done ");
        StringCat(res, cmd);
    }
    void main() {
        START_ASCII_AGENT(Slow);
        while (1) { system_ltest0 = system_ltest0 + 1; Sleep(1); }
    }
    """
    with served(program) as (sim, srv):
        c = LineClient(srv.ports["user-ascii"])
        before = sim.read("system_ltest0")
        assert c.ask("x") == "done x"
        assert sim.read("system_ltest0") >= before + 40  # task 0 ran on meanwhile
        c.close()


def test_a_parser_fault_is_reported_and_stops_the_agent():
    program = """
    void Bad(char *cmd, char *res) { char *p = 0; res[0] = p[0]; }
    void main() { START_ASCII_AGENT(Bad); }
    """
    with served(program) as (sim, srv):
        c = LineClient(srv.ports["user-ascii"])
        assert c.ask("x").startswith("ERR the ASCII agent stopped: ")
        assert c.ask("y") == "ERR no ASCII agent is running (the program calls START_ASCII_AGENT)"
        c.close()
        assert sim.fault_count == 1
        assert "runtime error in task 0" in str(sim.faults[0])


def test_a_second_agent_is_refused():
    program = """
    void A(char *cmd, char *res) { }
    void B(char *cmd, char *res) { }
    void main() { START_ASCII_AGENT(A); START_ASCII_AGENT(A); START_ASCII_AGENT(B); }
    """
    with Simulation.from_source(program) as sim:
        sim.run(until=0.01)
        assert sim.fault_count == 1
        assert "an ASCII agent is already running" in str(sim.faults[0])
        assert "0x1392" in str(sim.faults[0])


def test_broadcast_reaches_every_connected_client():
    """Manual 21.2.2's example, sent when input 1 rises."""
    program = """
    void Echo(char *cmd, char *res) { StringCopy(res, cmd); }
    void main() {
        START_ASCII_AGENT(Echo);
        Till(HIMC_GPI(1));
        char buf[128] = {0};
        StringCopy(buf, "test\\n\\r");
        int len = StringLen(buf);
        ASCII_ServerBroadcast(buf, len);
        ASCII_ServerBroadcast("0123456789", 4);
    }
    """
    with served(program) as (sim, srv):
        clients = [LineClient(srv.ports["user-ascii"]) for _ in range(3)]
        for c in clients:  # connected (the server has accepted them)
            assert c.ask("hi") == "hi"
        sim.set_input(1, 1)
        for c in clients:
            data = b""
            for _ in range(50):  # bounded
                data += c.sock.recv(100)
                if data.endswith(b"0123"):
                    break
            assert data == b"test\n\r0123"
            c.close()


def test_broadcast_without_a_server_or_a_client_does_nothing():
    program = """
    void main() {
        ASCII_ServerBroadcast("hello", 5);
        Print("sent");
        ASCII_ServerBroadcast("hello", 129);
    }
    """
    with Simulation.from_source(program) as sim:
        sim.run(until=0.01)
        assert sim.messages == ["sent"]
        assert "length 129 is out of range (0..128)" in str(sim.faults[0])


def test_serve_twice_is_refused_and_close_stops_serving():
    sim = Simulation.from_source("void main() { }")
    srv = sim.serve(until=100.0)
    with pytest.raises(SessionError, match="already being served"):
        sim.serve()
    sim.close()  # stops the served run first
    assert not srv.running
    assert srv.result is not None and srv.result.reason == "stopped"
