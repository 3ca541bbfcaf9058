"""`[comm]` bind addresses where no TCP client can connect (a multicast group, the
broadcast address) are exit 3 naming the key; they used to "listen" there."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize("bind", ["224.0.0.1", "239.255.255.250", "255.255.255.255", "ff02::1"])
def test_a_multicast_or_broadcast_bind_address_is_exit_3(cli, bind):
    r = cli("serve", "--until", "0.01", "--machine", "m.toml", "a.hmpl",
            m__toml=f'[comm]\nbind = "{bind}"\n', a__hmpl="void main() { }\n")  # fmt: skip
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.splitlines()[0] == (
        f"m.toml:2:1: error: bind = '{bind}': a multicast or broadcast address; a server "
        'listens on an address of this host such as "127.0.0.1" (or "0.0.0.0": all)'
    )


def test_all_addresses_and_loopback_still_serve(cli):
    for bind in ("0.0.0.0", "127.0.0.1"):
        table = f'[comm]\nbind = "{bind}"\nnative_ascii_port = 0\nuser_ascii_port = 0\nmodbus_port = 0\n'
        r = cli("serve", "--until", "0.01", "--machine", "m.toml", "a.hmpl",
                m__toml=table, a__hmpl="void main() { }\n")  # fmt: skip
        assert r.code == 0, r.stderr
        assert f"native-ascii listening on {bind}:" in r.stderr
