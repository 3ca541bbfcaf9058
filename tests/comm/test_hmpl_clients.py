"""The ASCII client (21.2.3-21.2.6) and Modbus TCP client (21.3) built-ins, against
servers on loopback: the manual's examples with the server's address changed, then
the error codes of 18.1.1. Unpaced runs: the network work happens while the simulated
clock stands still."""

from __future__ import annotations

from pathlib import Path

import pytest
from comm_helpers import WAIT, free_port, line_peer, modbus_peer
from pymodbus.client import ModbusTcpClient

from motionvm.api import Simulation

PROGRAMS = Path(__file__).parent / "programs"


def run_program(text: str, until: float = 10.0, machine=None) -> Simulation:
    sim = Simulation.from_source(text, machine=machine)
    sim.run(until=until)
    return sim


def example(name: str, port: int) -> str:
    return (PROGRAMS / name).read_text(encoding="utf-8").replace("@PORT@", str(port))


# ------------------------------------------------------------ Modbus client: the manual


@pytest.fixture(scope="module")
def peer():
    with modbus_peer() as port:
        yield port


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("modbus_21_3_1_connect.hmpl", ["Connect Sucess: Sock id 10"]),
        ("modbus_21_3_2_disconnect.hmpl", []),
        ("modbus_21_3_3_read_holdreg.hmpl", ["12", "34"]),  # register 30 = 0x1234
        ("modbus_21_3_4_read_inputreg.hmpl", ["0", "7"]),  # input register 30 = 7
        ("modbus_21_3_5_read_coils.hmpl", ["0"] * 5),  # 40 coils off: 5 bytes
        ("modbus_21_3_6_read_inputs.hmpl", ["ff"] * 5),  # 40 inputs on
        ("modbus_21_3_7_write_holdreg.hmpl", ["0", "1e", "0", "1"]),  # address 30, 1 register
        ("modbus_21_3_8_write_coils.hmpl", ["0", "1e", "0", "4"]),  # address 30, 4 coils
    ],
)
def test_the_manual_examples_of_21_3(peer, name, expected):
    with run_program(example(name, peer)) as sim:
        assert sim.messages == expected
        assert sim.fault_count == 0


def test_the_written_values_reach_the_server(peer):
    with run_program(example("modbus_21_3_8_write_coils.hmpl", peer)):
        pass
    with run_program(example("modbus_21_3_7_write_holdreg.hmpl", peer)):
        pass
    c = ModbusTcpClient("127.0.0.1", port=peer, timeout=WAIT, retries=0)
    assert c.connect()
    assert c.read_coils(30, count=5).bits[:5] == [1, 1, 1, 1, 0]  # data[0] = 15: bits 0-3
    assert c.read_holding_registers(30, count=1).registers == [1]
    c.close()


def test_coils_are_packed_sixteen_to_a_word(peer):
    program = f"""
    void main() {{
        char ip[32] = "127.0.0.1:{peer}";
        int s;
        Modbus_ClientConnect(ip, &s);
        uint16_t data[2] = {{0x8001, 0x0003}};
        uint8_t bufs[16];
        int len = 0;
        Print("%d", Modbus_ClientWrite_Coils(s, 50, 18, data, bufs, &len));
        Print("%d", Modbus_ClientRead_Coils(s, 50, 18, bufs, &len));
        Print("%d: %x %x %x", len, bufs[0], bufs[1], bufs[2]);
        Modbus_ClientDisconnect(s);
    }}
    """
    with run_program(program) as sim:
        assert sim.messages == ["0", "0", "3: 1 80 3"]


def test_the_simulated_clock_stands_still_while_a_call_waits(peer):
    program = f"""
    void main() {{
        char ip[32] = "127.0.0.1:{peer}";
        int s;
        int t0 = system_timeInMs;
        Modbus_ClientConnect(ip, &s);
        uint8_t bufs[8];
        int len;
        Modbus_ClientRead_HoldReg(s, 0, 1, bufs, &len);
        Print("%d ms", system_timeInMs - t0);
    }}
    """
    with run_program(program) as sim:
        assert sim.messages == ["0 ms"]


# ------------------------------------------------------------ Modbus client: errors


def test_modbus_error_codes(peer):
    port = free_port()
    program = f"""
    void main() {{
        char ip[32] = "127.0.0.1:{peer}";
        int s = 0;
        uint8_t bufs[512];
        uint16_t data[130];
        int len = -1;
        Print("refused %x", Modbus_ClientConnect("127.0.0.1:{port}", &s));
        Print("bad ip %x", Modbus_ClientConnect("127.0.0.x", &s));
        Print("connect %x", Modbus_ClientConnect(ip, &s));
        Print("126 regs %x len %d", Modbus_ClientRead_HoldReg(s, 0, 126, bufs, &len), len);
        Print("0 regs %x", Modbus_ClientRead_InputReg(s, 0, 0, bufs, &len));
        Print("124 writes %x", Modbus_ClientWrite_HoldReg(s, 0, 124, data, bufs, &len));
        Print("2001 coils %x", Modbus_ClientRead_Coils(s, 0, 2001, bufs, &len));
        Print("1969 coils %x", Modbus_ClientWrite_Coils(s, 0, 1969, data, bufs, &len));
        Print("exception %x", Modbus_ClientRead_HoldReg(s, 200, 1, bufs, &len));
        Print("unknown %x", Modbus_ClientRead_Inputs(s + 1, 0, 1, bufs, &len));
        Print("disconnect %x", Modbus_ClientDisconnect(s));
        Print("again %x", Modbus_ClientDisconnect(s));
        Print("closed %x", Modbus_ClientRead_HoldReg(s, 0, 1, bufs, &len));
    }}
    """
    with run_program(program) as sim:
        assert sim.messages == [
            "refused 1839",
            "bad ip 1839",
            "connect 0",
            "126 regs 183d len -1",
            "0 regs 183d",
            "124 writes 183d",
            "2001 coils 183d",
            "1969 coils 183d",
            "exception 1840",
            "unknown 1452",
            "disconnect 0",
            "again 1452",
            "closed 1452",
        ]


def test_a_refused_count_sends_nothing_and_a_silent_server_times_out(tmp_path):
    machine = tmp_path / "m.toml"
    machine.write_text("[comm]\nclient_timeout_ms = 200\n")
    with line_peer() as (port, received):
        program = f"""
        void main() {{
            int s;
            uint8_t bufs[512];
            int len;
            Print("%x", Modbus_ClientConnect("127.0.0.1:{port}", &s));
            Print("%x", Modbus_ClientRead_HoldReg(s, 0, 126, bufs, &len));
            Print("%x", Modbus_ClientRead_HoldReg(s, 0, 1, bufs, &len));
        }}
        """
        with run_program(program, machine=str(machine)) as sim:
            assert sim.messages == ["0", "183d", "183f"]
    assert received == [bytes.fromhex("0001 0000 0006 01 03 0000 0001")]


def test_the_ninth_connection_fails(peer):
    program = f"""
    void main() {{
        int s[9];
        for (int i = 0; i < 9; i++) {{
            Print("%x %d", Modbus_ClientConnect("127.0.0.1:{peer}", &s[i]), i < 8 ? s[i] : 0);
        }}
    }}
    """
    with run_program(program) as sim:
        assert sim.messages == [f"0 {10 + i}" for i in range(8)] + ["1839 0"]


# ------------------------------------------------------------ ASCII client


def test_the_manual_examples_of_21_2_3_to_21_2_6():
    with line_peer() as (port, received):
        with run_program(example("ascii_client_examples.hmpl", port)) as sim:
            assert sim.messages == [
                "Connect Sucess: Sock id 10",
                "Recv = hello",
                "Send OK = Test String",
            ]
            assert sim.fault_count == 0
    assert b"".join(received) == b"Test String"  # up to the string's end, not 100 bytes


def test_ascii_client_round_trip_and_error_codes(tmp_path):
    machine = tmp_path / "m.toml"
    machine.write_text("[comm]\nclient_timeout_ms = 200\n")
    refused = free_port()
    with line_peer({b"ping\r\n": b"pong\r\n"}) as (port, received):
        program = f"""
        void main() {{
            char buf[600];
            int s = -1;
            Print("refused %x", ASCII_ClientConnect("127.0.0.1", "{refused}", &s));
            Print("bad port %x", ASCII_ClientConnect("127.0.0.1", "http", &s));
            Print("connect %x %d", ASCII_ClientConnect("127.0.0.1", "{port}", &s), s);
            Print("recv %x", ASCII_ClientRecv(s, 3, buf));
            Print("[%s]", buf);
            Print("recv %x", ASCII_ClientRecv(s, 512, buf));
            Print("[%s]", buf);
            Print("send %x", ASCII_ClientSend(s, 6, "ping\\r\\n"));
            Print("recv %x", ASCII_ClientRecv(s, 100, buf));
            Print("[%d]", StringLen(buf));
            Print("timeout %x", ASCII_ClientRecv(s, 100, buf));
            Print("too long %x", ASCII_ClientRecv(s, 513, buf));
            Print("unknown %x", ASCII_ClientSend(s + 1, 4, "ping"));
            Print("disconnect %x", ASCII_ClientDisconnect(s));
            Print("again %x", ASCII_ClientDisconnect(s));
        }}
        """
        with run_program(program, machine=str(machine)) as sim:
            assert sim.messages == [
                "refused 17d5",
                "bad port 17d5",
                "connect 0 10",
                "recv 0",
                "[hel]",
                "recv 0",
                "[lo]",
                "send 0",
                "recv 0",
                "[6]",
                "timeout 17de",
                "too long 138f",
                "unknown 1452",
                "disconnect 0",
                "again 1452",
            ]
    assert received == [b"ping\r\n"]


def test_a_closed_server_gives_recv_fail():
    with line_peer() as (port, _received):
        program = f"""
        void main() {{
            char buf[64];
            int s;
            ASCII_ClientConnect("127.0.0.1", "{port}", &s);
            ASCII_ClientRecv(s, 5, buf);
            Sleep(300);
            Print("%x", ASCII_ClientRecv(s, 5, buf));
        }}
        """
        sim = Simulation.from_source(program)
        sim.run(until=0.1)  # connected, "hello" received, sleeping
    with sim:  # the peer has closed the connection
        sim.run(until=10)
        assert sim.messages == ["17df"]


SLOW_PROGRAM = """
void main() {
    char buf[64];
    int s;
    ASCII_ClientConnect("127.0.0.1", "PORT", &s);
    ASCII_ClientRecv(s, 5, buf);
    ASCII_ClientSend(s, 5, "slow\\n");
    int t0 = system_timeInMs;
    ASCII_ClientRecv(s, 60, buf);
    system_ltest1 = system_timeInMs - t0;
    Print("%s", buf);
    system_ltest0 = 1;
}
"""


def test_an_unpaced_run_does_not_advance_the_clock_while_the_network_works():
    with line_peer({b"slow\n": b"answer"}, delay=0.3) as (port, _received):
        with run_program(SLOW_PROGRAM.replace("PORT", str(port))) as sim:
            assert sim.messages == ["answer"]
            assert sim.read("system_ltest1") == 0


def test_a_paced_run_takes_the_time_the_network_takes():
    """Served (paced), the call waits 0.3 s of wall time: 0.3 s of simulated time pass
    while the task waits at a yield, and the other tasks go on."""
    with line_peer({b"slow\n": b"answer"}, delay=0.3) as (port, _received):
        sim = Simulation.from_source(SLOW_PROGRAM.replace("PORT", str(port)))
        with sim, sim.serve() as srv:
            for _ in range(250):  # bounded: 5 s
                if sim.read("system_ltest0") == 1:
                    break
                srv.wait(0.02)
            assert sim.messages == ["answer"]
            assert sim.read("system_ltest1") >= 250  # [ms], the peer's 300 ms less slack


def test_the_same_run_gives_the_same_stamped_output():
    runs = []
    with modbus_peer() as port:  # a deterministic peer of its own
        for _ in range(2):
            program = example("modbus_21_3_3_read_holdreg.hmpl", port)
            with Simulation.from_source(program, stamp=True) as sim:
                sim.run(until=10)
                runs.append(list(sim.messages))
    assert runs[0] == runs[1] == ["[t=5.000000][task 0] 12", "[t=5.000000][task 0] 34"]
