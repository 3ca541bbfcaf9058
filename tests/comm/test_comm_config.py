"""The machine file's `[comm]` table (comm/config.py via sim/machine.py)."""

from __future__ import annotations

import pytest

from motionvm.comm.config import CommConfig
from motionvm.sim.machine import DEFAULT_MACHINE, MachineFileError, load_machine


def test_the_defaults_are_the_manuals_ports_on_loopback():
    assert DEFAULT_MACHINE.comm == CommConfig("127.0.0.1", 3999, 4000, 502, 1000)
    assert DEFAULT_MACHINE.comm.client_timeout == 1.0


def test_every_key_is_read(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(
        '[comm]\nbind = "0.0.0.0"\nnative_ascii_port = 0\nuser_ascii_port = 14000\n'
        "modbus_port = 1502\nclient_timeout_ms = 250\n"
    )
    assert load_machine(path).comm == CommConfig("0.0.0.0", 0, 14000, 1502, 250)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            'bind = "my-host"',
            "m.toml:2:1: error: bind = 'my-host': must be an IP address such as \"127.0.0.1\"",
        ),
        (
            "native_ascii_port = -1",
            "m.toml:2:1: error: native_ascii_port = -1: must be a port from 0 to 65535",
        ),
        (
            'user_ascii_port = "4000"',
            "m.toml:2:1: error: user_ascii_port = '4000': must be a port from 0 to 65535",
        ),
        (
            "modbus_port = true",
            "m.toml:2:1: error: modbus_port = True: must be a port from 0 to 65535",
        ),
        (
            "client_timeout_ms = 0",
            "m.toml:2:1: error: client_timeout_ms = 0: must be an integer from 1 to 600000",
        ),
        (
            "port = 1",
            "m.toml:2:1: error: unknown key 'port' in [comm] (known: bind, client_timeout_ms, modbus_port, native_ascii_port, user_ascii_port)",
        ),
    ],
)
def test_a_bad_value_names_its_key(tmp_path, text, message):
    path = tmp_path / "m.toml"
    path.write_text(f"[comm]\n{text}\n")
    with pytest.raises(MachineFileError) as info:
        load_machine(path)
    assert info.value.messages == [message.replace("m.toml", str(path))]
