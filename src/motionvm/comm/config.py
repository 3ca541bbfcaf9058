"""The `[comm]` table of a machine file: where the controller's TCP servers listen, and
who may use them.

```toml
[comm]
bind = "127.0.0.1"        # address the servers listen on (loopback unless you say so)
native_ascii_port = 3999  # Native ASCII server (manual 21.1); 0: any free port
user_ascii_port = 4000    # User ASCII server (START_ASCII_AGENT)
modbus_port = 502         # Modbus TCP server
client_timeout_ms = 1000  # ASCII/Modbus client built-ins: connect, send, receive timeout
idle_timeout = 30         # [s] a server drops a client with no complete request this long; 0: never
token = "..."             # the ASCII servers' first line of every connection must be this
native_ascii_read_only = false  # true: Native ASCII serves variable reads and queries only
modbus_read_only = false  # true: Modbus serves reads only (default: true when a token is set)
```
Every key is optional. The servers listen only under `motionvm serve` (or the host
API's `Simulation.serve`); the client timeout applies to every run.
"""

from __future__ import annotations

import ipaddress
import math
from dataclasses import dataclass

COMM_KEYS = {
    "bind",
    "native_ascii_port",
    "user_ascii_port",
    "modbus_port",
    "client_timeout_ms",
    "idle_timeout",
    "token",
    "native_ascii_read_only",
    "modbus_read_only",
}
"""The keys of `[comm]`."""

MAX_IDLE_TIMEOUT = 86_400.0
"""The longest idle timeout [s] (a day)."""
MAX_TOKEN = 256
"""Characters of a token at most (it is one request line)."""


@dataclass(frozen=True)
class CommConfig:
    """Addresses, timeouts and access rules of the controller's communication."""

    bind: str = "127.0.0.1"
    native_ascii_port: int = 3999
    user_ascii_port: int = 4000
    modbus_port: int = 502
    client_timeout_ms: int = 1000
    """How long a client built-in waits for the network [ms] before its timeout code."""
    idle_timeout: float = 30.0
    """A server drops a client that has sent no complete request for this long [s wall];
    0: never."""
    token: str | None = None
    """The line a client of an ASCII server sends first (None: no token is asked)."""
    native_ascii_read_only: bool = False
    """Native ASCII serves variable reads and queries only."""
    modbus_read_only: bool | None = None
    """Modbus serves reads only; None: exactly when a token is set (Modbus cannot carry
    one, so a token alone would leave Modbus writes open to anyone)."""

    @property
    def client_timeout(self) -> float:
        """The client timeout [s]."""
        return self.client_timeout_ms / 1000.0

    def read_only(self, server: str) -> bool:
        """Whether `server` ("native-ascii", "user-ascii", "modbus") refuses requests that
        change the machine. User ASCII never does: its program's parser alone knows what
        a line does."""
        if server == "native-ascii":
            return self.native_ascii_read_only
        if server == "modbus":
            if self.modbus_read_only is None:
                return self.token is not None
            return self.modbus_read_only
        return False

    def exposure_warning(self) -> str | None:
        """A warning when the servers listen beyond this host (None on loopback)."""
        try:
            loopback = ipaddress.ip_address(self.bind).is_loopback
        except ValueError:  # a host name given through the host API
            loopback = self.bind == "localhost"
        if loopback:
            return None
        head = f"motionvm: warning: the servers listen on {self.bind}, beyond this host"
        if self.token is None:
            return (
                f"{head}, without a token: anyone who can connect can move the axes, set "
                'outputs and stop tasks (set [comm] token = "..." or bind = "127.0.0.1")'
            )
        modbus = (
            "Modbus is read-only"
            if self.read_only("modbus")
            else "Modbus clients write without it (modbus_read_only = false)"
        )
        return f"{head}: the token travels unencrypted, use a trusted network; {modbus}"


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
    idle = table.get("idle_timeout")
    if idle is not None:
        if (
            isinstance(idle, bool)
            or not isinstance(idle, (int, float))
            or not math.isfinite(idle)
            or not 0 <= idle <= MAX_IDLE_TIMEOUT
        ):
            problems.at(
                "comm",
                "idle_timeout",
                f"idle_timeout = {idle!r}: must be a number of seconds from 0 (never) "
                f"to {MAX_IDLE_TIMEOUT:g}",
            )
        else:
            out["idle_timeout"] = float(idle)
    token = table.get("token")
    if token is not None:
        why = _token_problem(token)
        if why:
            problems.at("comm", "token", f"token = {token!r}: {why}")
        else:
            out["token"] = token
    for key in ("native_ascii_read_only", "modbus_read_only"):
        value = table.get(key)
        if value is None:
            continue
        if not isinstance(value, bool):
            problems.at("comm", key, f"{key} = {value!r}: must be true or false")
            continue
        out[key] = value
    return CommConfig(**out)  # type: ignore[arg-type]


def _token_problem(token: object) -> str | None:
    """Why `token` cannot be a token (a client sends it as one request line), or None."""
    if not isinstance(token, str):
        return "must be a string"
    if not token:
        return "must not be empty (leave the key out to ask no token)"
    if len(token) > MAX_TOKEN:
        return f"is {len(token)} characters long; at most {MAX_TOKEN}"
    if not all(" " <= ch <= "~" for ch in token):
        return "must be printable ASCII (a client sends it as one line)"
    if token != token.strip():
        return "must not begin or end with a space"
    return None
