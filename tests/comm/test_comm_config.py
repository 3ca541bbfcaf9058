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
        "modbus_port = 1502\nclient_timeout_ms = 250\nidle_timeout = 2.5\n"
        'token = "open sesame"\nnative_ascii_read_only = true\nmodbus_read_only = false\n'
    )
    assert load_machine(path).comm == CommConfig(
        "0.0.0.0", 0, 14000, 1502, 250, 2.5, "open sesame", True, False
    )


def test_idle_timeout_is_30_s_and_0_turns_it_off(tmp_path):
    assert DEFAULT_MACHINE.comm.idle_timeout == 30.0
    path = tmp_path / "m.toml"
    path.write_text("[comm]\nidle_timeout = 0\n")
    assert load_machine(path).comm.idle_timeout == 0.0


def test_modbus_is_read_only_when_a_token_is_set_unless_told_otherwise():
    assert not CommConfig().read_only("modbus")
    assert CommConfig(token="t").read_only("modbus")
    assert not CommConfig(token="t", modbus_read_only=False).read_only("modbus")
    assert CommConfig(modbus_read_only=True).read_only("modbus")
    assert CommConfig(native_ascii_read_only=True).read_only("native-ascii")
    assert not CommConfig(token="t", native_ascii_read_only=False).read_only("native-ascii")
    assert not CommConfig(native_ascii_read_only=True).read_only("user-ascii")


@pytest.mark.parametrize("bind", ["127.0.0.1", "127.0.0.2", "::1"])
def test_no_warning_on_loopback(bind):
    assert CommConfig(bind=bind).exposure_warning() is None


def test_a_warning_beyond_loopback_says_what_is_open():
    bare = CommConfig(bind="0.0.0.0").exposure_warning()
    assert bare is not None and "without a token" in bare
    locked = CommConfig(bind="192.168.1.5", token="t").exposure_warning()
    assert locked is not None and "Modbus is read-only" in locked
    open_modbus = CommConfig(bind="::", token="t", modbus_read_only=False).exposure_warning()
    assert open_modbus is not None and "Modbus clients write without it" in open_modbus


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
            "idle_timeout = -1",
            "m.toml:2:1: error: idle_timeout = -1: must be a number of seconds from 0 (never) to 86400",
        ),
        (
            'idle_timeout = "30"',
            "m.toml:2:1: error: idle_timeout = '30': must be a number of seconds from 0 (never) to 86400",
        ),
        (
            "idle_timeout = nan",
            "m.toml:2:1: error: idle_timeout = nan: must be a number of seconds from 0 (never) to 86400",
        ),
        (
            "idle_timeout = true",
            "m.toml:2:1: error: idle_timeout = True: must be a number of seconds from 0 (never) to 86400",
        ),
        (
            'token = ""',
            "m.toml:2:1: error: token = '': must not be empty (leave the key out to ask no token)",
        ),
        ("token = 1234", "m.toml:2:1: error: token = 1234: must be a string"),
        (
            'token = "ab\\ncd"',
            "m.toml:2:1: error: token = 'ab\\ncd': must be printable ASCII (a client sends it as one line)",
        ),
        (
            'token = " secret"',
            "m.toml:2:1: error: token = ' secret': must not begin or end with a space",
        ),
        (
            f'token = "{"x" * 257}"',
            # (a quoted value longer than 64 characters is shown by its ends)
            "m.toml:2:1: error: token = 'xxxxxxxxxxxx...xxxxxx' (257 characters): is 257 "
            "characters long; at most 256",
        ),
        (
            'native_ascii_read_only = "yes"',
            "m.toml:2:1: error: native_ascii_read_only = 'yes': must be true or false",
        ),
        (
            "modbus_read_only = 1",
            "m.toml:2:1: error: modbus_read_only = 1: must be true or false",
        ),
        (
            "port = 1",
            "m.toml:2:1: error: unknown key 'port' in [comm] (known: bind, client_timeout_ms, idle_timeout, modbus_port, modbus_read_only, native_ascii_port, native_ascii_read_only, token, user_ascii_port)",
        ),
    ],
)
def test_a_bad_value_names_its_key(tmp_path, text, message):
    path = tmp_path / "m.toml"
    path.write_text(f"[comm]\n{text}\n")
    with pytest.raises(MachineFileError) as info:
        load_machine(path)
    assert info.value.messages == [message.replace("m.toml", str(path))]
