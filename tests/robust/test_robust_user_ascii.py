"""Careless User ASCII parsers (START_ASCII_AGENT): a parser's fault stops the agent, as
a task's fault stops the task; the controller and its other servers go on, and
stopping the servers while a client still waits prints no traceback."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "comm"))
from comm_helpers import LineClient, served  # noqa: E402

NO_AGENT = "ERR no ASCII agent is running (the program calls START_ASCII_AGENT)"
MAIN = "void main() { START_ASCII_AGENT(P); while (1) { Sleep(10); system_ltest0++; } }\n"


@pytest.mark.parametrize(
    ("parser", "error"),
    [
        (  # fills res without a terminator
            "void P(char *cmd, char *res) { int i; for (i = 0; i < 2048; i++) res[i] = 'a'; }",
            "ERR the ASCII agent stopped: res is not terminated by '\\0' within its 2048 bytes",
        ),
        (  # writes past the end of res
            "void P(char *cmd, char *res) { int i; for (i = 0; i < 5000; i++) res[i] = 'a'; }",
            "ERR the ASCII agent stopped: pointer 0x",
        ),
        (
            "void P(char *cmd, char *res) { int z = 0; res[0] = 'x' / z; }",
            "ERR the ASCII agent stopped: integer division by zero",
        ),
    ],
    ids=["unterminated", "overflow", "div0"],
)
def test_a_faulty_parser_stops_the_agent_not_the_controller(parser, error):
    with served(parser + "\n" + MAIN) as (sim, srv):
        user = LineClient(srv.ports["user-ascii"])
        native = LineClient(srv.ports["native-ascii"])
        try:
            assert user.ask("hello").startswith(error)
            assert user.ask("again") == NO_AGENT
            assert sim.fault_count == 1
            first = int(native.ask("system_ltest0"))
            for _ in range(100):  # bounded: 2 s; the main task still counts
                if int(native.ask("system_ltest0")) > first:
                    break
                time.sleep(0.02)
            assert int(native.ask("system_ltest0")) > first
        finally:
            user.close()
            native.close()


def test_stopping_while_a_client_waits_for_a_parser_prints_no_traceback(capfd, caplog):
    never = "void P(char *cmd, char *res) { while (1) { } }\n"
    with served(never + MAIN) as (_sim, srv):
        user = LineClient(srv.ports["user-ascii"])
        user.sock.settimeout(0.3)
        user.send(b"hello\r\n")
        with pytest.raises(TimeoutError):
            user.line()
    user.close()
    err = capfd.readouterr().err
    assert "Traceback" not in err and "CancelledError" not in err, err
    # asyncio reports a failed callback through logging (stderr outside pytest)
    assert not [r for r in caplog.records if r.exc_info], caplog.text


@pytest.mark.parametrize(
    ("agent", "count"), [("main", "0 parameters"), ("Q", "1 parameter"), ("R", "3 parameters")]
)
def test_a_parser_of_the_wrong_shape_is_a_runtime_error_of_its_task(agent, count):
    """START_ASCII_AGENT(main) used to be accepted; the first line crashed the controller."""
    program = (
        "int Q(int a) { return a; }\n"
        "void R(char *cmd, char *res, int x) { }\n"
        f"void main() {{ START_ASCII_AGENT({agent}); while (1) Sleep(10); }}\n"
    )
    with served(program) as (sim, srv):
        user = LineClient(srv.ports["user-ascii"])
        try:
            assert user.ask("hello") == NO_AGENT
        finally:
            user.close()
        assert [f.message for f in sim.fault_records] == [
            f"START_ASCII_AGENT: the parser takes (char *cmd, char *res); {agent} takes {count}"
        ]
