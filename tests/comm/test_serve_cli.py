"""`motionvm serve` in a subprocess: bound ports on stderr, clients served, Ctrl-C and
--until as normal ends, bad [comm] tables and taken ports as command-line errors."""

from __future__ import annotations

import re
import signal
import socket
import subprocess
import sys
import threading

from comm_helpers import WAIT, LineClient

PROGRAM = """
void Up(char *cmd, char *res) {
    int i = 0;
    for (; cmd[i] != 0; i++) { res[i] = (cmd[i] >= 'a' && cmd[i] <= 'z') ? cmd[i] - 32 : cmd[i]; }
    res[i] = 0;
}
void main() {
    START_ASCII_AGENT(Up);
    Print("serving");
}
"""

FREE_PORTS = "[comm]\nnative_ascii_port = 0\nuser_ascii_port = 0\nmodbus_port = 0\n"


def start(tmp_path, machine: str = FREE_PORTS, *extra: str) -> tuple[subprocess.Popen, dict]:
    """`motionvm serve` on PROGRAM; the process and its ports (from its stderr; a line
    that names no port is kept in `ports["stderr"]`)."""
    (tmp_path / "prog.hmpl").write_text(PROGRAM)
    (tmp_path / "m.toml").write_text(machine)
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionvm", "serve", "--machine", "m.toml", "prog.hmpl", *extra],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    ports: dict[str, int] = {}
    timer = threading.Timer(60, proc.kill)  # bounded: a server that never listens
    timer.start()
    try:
        while len(ports) < 3:
            line = proc.stderr.readline()  # type: ignore[union-attr]
            if not line:
                break
            m = re.fullmatch(r"(\S+) listening on 127\.0\.0\.1:(\d+)\n", line)
            if m is None:  # an error: the caller reads the rest
                ports["stderr"] = line  # type: ignore[assignment]
                break
            ports[m.group(1)] = int(m.group(2))
    finally:
        timer.cancel()
    return proc, ports


def test_serve_prints_its_ports_and_stops_on_ctrl_c(tmp_path):
    proc, ports = start(tmp_path)
    try:
        assert set(ports) == {"native-ascii", "user-ascii", "modbus"}
        # the agent is registered once the task has run (servers listen from the start)
        assert proc.stdout.readline() == "serving\n"  # type: ignore[union-attr]
        user = LineClient(ports["user-ascii"])
        assert user.ask("hello") == "HELLO"
        native = LineClient(ports["native-ascii"])
        assert native.ask("system_dtest4 = 2.5") == "OK"
        assert native.ask("system_dtest4") == "2.5"
        user.close()
        native.close()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=WAIT * 3)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert out == ""
    assert "Traceback" not in err


def test_serve_until_ends_by_itself(tmp_path):
    proc, ports = start(tmp_path, FREE_PORTS, "--until", "0.5")
    try:
        out, err = proc.communicate(timeout=WAIT * 3)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert out == "serving\n"
    assert len(ports) == 3


def test_a_taken_port_is_a_command_line_error(tmp_path):
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        machine = f"[comm]\nnative_ascii_port = 0\nuser_ascii_port = {port}\nmodbus_port = 0\n"
        proc, ports = start(tmp_path, machine)
        try:
            _out, err = proc.communicate(timeout=WAIT * 3)
        finally:
            proc.kill()
    assert proc.returncode == 3
    assert ports["stderr"] == (
        f"motionvm: error: user-ascii server cannot listen on 127.0.0.1:{port}: "
        "Address already in use\n"
    )
    assert "Traceback" not in err


def test_a_bad_comm_table_names_the_key(tmp_path):
    machine = '[comm]\nbind = "localhost:80"\nmodbus_port = 70000\nfoo = 1\n'
    (tmp_path / "prog.hmpl").write_text(PROGRAM)
    (tmp_path / "m.toml").write_text(machine)
    res = subprocess.run(
        [sys.executable, "-m", "motionvm", "serve", "--machine", "m.toml", "prog.hmpl"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 3
    lines = [line for line in res.stderr.splitlines() if "error:" in line]
    assert lines == [
        "m.toml:2:1: error: bind = 'localhost:80': must be an IP address such as \"127.0.0.1\"",
        "m.toml:3:1: error: modbus_port = 70000: must be a port from 0 to 65535",
        "m.toml:4:1: error: unknown key 'foo' in [comm] (known: bind, client_timeout_ms, "
        "idle_timeout, modbus_port, modbus_read_only, native_ascii_port, "
        "native_ascii_read_only, token, user_ascii_port)",
    ]
