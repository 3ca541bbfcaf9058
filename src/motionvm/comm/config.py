"""The `[comm]` table of a machine file: where the controller's TCP servers listen.

```toml
[comm]
bind = "127.0.0.1"        # address the servers listen on (loopback unless you say so)
native_ascii_port = 3999  # Native ASCII server (manual 21.1); 0: any free port
user_ascii_port = 4000    # User ASCII server (START_ASCII_AGENT)
modbus_port = 502         # Modbus TCP server
client_timeout_ms = 1000  # ASCII/Modbus client built-ins: connect, send, receive timeout
```
Every key is optional. The servers listen only under `motionvm serve` (or the host
API's `Simulation.serve`); the client timeout applies to every run.
"""

from __future__ import annotations

import ipaddress
from dataclasses import dataclass

COMM_KEYS = {"bind", "native_ascii_port", "user_ascii_port", "modbus_port", "client_timeout_ms"}
"""The keys of `[comm]`."""


@dataclass(frozen=True)
class CommConfig:
    """Addresses and timeouts of the controller's communication."""

    bind: str = "127.0.0.1"
    native_ascii_port: int = 3999
    user_ascii_port: int = 4000
    modbus_port: int = 502
    client_timeout_ms: int = 1000
    """How long a client built-in waits for the network [ms] before its timeout code."""

    @property
    def client_timeout(self) -> float:
        """The client timeout [s]."""
        return self.client_timeout_ms / 1000.0


def load_comm(table: object, problems) -> CommConfig:
    """The `[comm]` table (already checked for unknown keys); each bad value is reported to
    `problems` (`TomlProblems.at(section, key, message)`) and its default stands in."""
    if not isinstance(table, dict):
        return CommConfig()
    out: dict[str, object] = {}
    bind = table.get("bind")
    if bind is not None:
        try:
            addr = ipaddress.ip_address(bind if isinstance(bind, str) else "")
        except ValueError:
            problems.at(
                "comm", "bind", f'bind = {bind!r}: must be an IP address such as "127.0.0.1"'
            )
        else:
            # a TCP server listens on one host's address: a group or broadcast address
            # would "listen" where no client can ever connect
            if addr.is_multicast or addr == ipaddress.IPv4Address("255.255.255.255"):
                problems.at(
                    "comm",
                    "bind",
                    f"bind = {bind!r}: a multicast or broadcast address; a server listens "
                    'on an address of this host such as "127.0.0.1" (or "0.0.0.0": all)',
                )
            else:
                out["bind"] = bind
    for key in ("native_ascii_port", "user_ascii_port", "modbus_port"):
        value = table.get(key)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 65535:
            problems.at("comm", key, f"{key} = {value!r}: must be a port from 0 to 65535")
            continue
        out[key] = value
    timeout = table.get("client_timeout_ms")
    if timeout is not None:
        if isinstance(timeout, bool) or not isinstance(timeout, int) or not 1 <= timeout <= 600_000:
            problems.at(
                "comm",
                "client_timeout_ms",
                f"client_timeout_ms = {timeout!r}: must be an integer from 1 to 600000",
            )
        else:
            out["client_timeout_ms"] = timeout
    return CommConfig(**out)  # type: ignore[arg-type]
