"""A TCP server of text lines on asyncio: the transport of both ASCII servers.

One request per line: CR, LF or CRLF ends it (an empty line is skipped, so CRLF is one
terminator); each reply is one line sent with `\\r\\n`. A connection's lines are handled
one at a time, in order, so a client that floods the server without reading its
replies is slowed by TCP flow control, and the server's memory per connection stays
bounded (one read chunk and one line of at most `MAX_LINE` bytes).

Limits: at most `MAX_CLIENTS` connections per server (the next one gets
`ERR too many clients (8)` and is closed); a line longer than `MAX_LINE` bytes gets
`ERR line too long` and is discarded up to its terminator. A client that goes away
loses nothing: the complete lines it sent before are still carried out (their replies
are dropped). A broadcast (`send_all`) goes to every client whose unread backlog is at
most `MAX_BACKLOG` bytes: a client that never reads misses broadcasts instead of
growing the server's memory without bound.

Access (comm/gate.py): a line that looks like HTTP closes the connection, and with a
token the first request line must be it. A client that sends no complete request for
`idle_timeout` seconds while the server waits for it (a slow trickle of bytes included)
gets `ERR idle for N s` and is closed, and so is a client that reads no reply for as long
(its unread replies fill the send buffer): clients that stay connected without asking
or reading cannot hold the `MAX_CLIENTS` places for longer. Time spent answering a request does
not count; only a request line served (a token included) restarts the count, not an
empty line nor one too long.
"""

from __future__ import annotations

import asyncio
import socket
from collections.abc import Awaitable, Callable

from motionvm.comm import gate

MAX_CLIENTS = 8
"""Connections per server."""
MAX_LINE = 1024
"""Bytes per request line, terminator excluded."""
MAX_BACKLOG = 64 * 1024
"""Bytes of broadcasts a client may leave unread before it misses the next ones."""
SEND_BUFFER = 64 * 1024
"""The kernel's send buffer of each connection [bytes] (Linux doubles it; without a size
it grows to megabytes for a client that reads nothing, which then takes that long to be
found out)."""
_CHUNK = 4096

Handler = Callable[[str], Awaitable[str | None]]
"""A request line (terminator stripped, decoded as Latin-1) -> its reply (None: none)."""


class LineServer:
    """Accepts connections and feeds their lines to `handler`, one at a time each."""

    def __init__(
        self, name: str, handler: Handler, *, token: str | None = None, idle_timeout: float = 0.0
    ) -> None:
        self.name = name
        self.handler = handler
        self.token = token
        """The first line each connection must send (None: none asked)."""
        self.idle_timeout = idle_timeout
        """[s wall] without a complete request before a client is closed; 0: never."""
        self.writers: set[asyncio.StreamWriter] = set()
        """Every open connection."""
        self.members: set[asyncio.StreamWriter] = set()
        """The connections past the token (they receive broadcasts)."""
        self.server: asyncio.base_events.Server | None = None

    async def start(self, host: str, port: int) -> int:
        """Listen on (host, port); the bound port (port 0: a free one)."""
        self.server = await asyncio.start_server(self._serve, host, port, limit=_CHUNK * 2)
        return self.server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        if self.server is not None:
            self.server.close()
        for w in list(self.writers):
            w.close()
        if self.server is not None:
            await self.server.wait_closed()

    def send_all(self, data: bytes) -> None:
        """Send `data` to every connected client (event loop thread); a client with more
        than `MAX_BACKLOG` bytes it has not read yet misses it."""
        for w in list(self.members):
            if not w.is_closing() and w.transport.get_write_buffer_size() <= MAX_BACKLOG:
                w.write(data)

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        if len(self.writers) >= MAX_CLIENTS:
            writer.write(f"ERR too many clients ({MAX_CLIENTS})\r\n".encode())
            try:
                await writer.drain()
            except ConnectionError:
                pass
            writer.close()
            return
        bound_send_buffer(writer.get_extra_info("socket"))
        self.writers.add(writer)
        if self.token is None:
            self.members.add(writer)
        try:
            await self._lines(reader, writer)
        except (ConnectionError, asyncio.IncompleteReadError):
            pass
        except asyncio.CancelledError:
            # the servers stop while this connection waits for a reply (a parser that
            # never returns): end quietly, not as a cancelled task asyncio reports
            pass
        except Exception as exc:  # noqa: BLE001 — a bug of ours: tell the client, close
            await self._reply(writer, f"ERR internal error of motionvm (a bug): {exc}", True)
        finally:
            self.writers.discard(writer)
            self.members.discard(writer)
            writer.close()

    async def _lines(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        buf = bytearray()
        discarding = False  # inside a line that was too long, until its terminator
        alive = True  # the client can still receive replies
        idle = self.idle_timeout
        loop = asyncio.get_running_loop()
        deadline = loop.time() + idle
        while True:
            if idle:
                try:
                    chunk = await asyncio.wait_for(
                        reader.read(_CHUNK), max(0.0, deadline - loop.time())
                    )
                except TimeoutError:
                    await self._reply(writer, f"ERR idle for {idle:g} s: connection closed", alive)
                    return
            else:
                chunk = await reader.read(_CHUNK)
            eof = not chunk
            buf += chunk
            while True:
                cut = _terminator(buf)
                if cut < 0:
                    break
                line = bytes(buf[:cut])
                del buf[: cut + 1]
                if discarding:
                    discarding = False
                    continue
                if len(line) > MAX_LINE:
                    alive = await self._reply(writer, "ERR line too long", alive)
                    continue
                if not line:
                    continue
                text = line.decode("latin-1")
                if gate.looks_like_http(text):
                    await self._reply(writer, gate.HTTP_REFUSED, alive)
                    return  # nothing after it runs
                if writer not in self.members:
                    if not gate.token_matches(text, self.token or ""):
                        await self._reply(writer, gate.WRONG_TOKEN, alive)
                        return
                    self.members.add(writer)
                    reply: str | None = "OK"
                else:
                    reply = await self.handler(text)
                if reply is not None:
                    alive = await self._reply(writer, reply, alive)
                deadline = loop.time() + idle
            if len(buf) > MAX_LINE:
                if not discarding:
                    alive = await self._reply(writer, "ERR line too long", alive)
                discarding = True
                buf.clear()
            if eof:
                return  # an unterminated rest is not a request

    async def _reply(self, writer: asyncio.StreamWriter, text: str, alive: bool) -> bool:
        """Send one reply line; False once the client is gone (later replies are dropped).
        A client that reads none of it for `idle_timeout` seconds (its unread replies
        fill the send buffer) is dropped at once, as an idle one."""
        if not alive or writer.is_closing():
            return False
        try:
            writer.write(text.encode("latin-1", "replace") + b"\r\n")
            if self.idle_timeout:
                await asyncio.wait_for(writer.drain(), self.idle_timeout)
            else:
                await writer.drain()
        except TimeoutError:
            writer.transport.abort()  # close() would wait for the client to read
            return False
        except (ConnectionError, OSError):
            return False
        return True


def bound_send_buffer(sock: object) -> None:
    """Give a connection's socket `SEND_BUFFER` bytes of send buffer."""
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER)  # type: ignore[attr-defined]
    except (AttributeError, OSError):  # not a socket of this system's kind: its default
        pass


def _terminator(buf: bytearray) -> int:
    """Index of the first CR or LF in `buf`, -1 if none."""
    cr, lf = buf.find(b"\r"), buf.find(b"\n")
    if cr < 0:
        return lf
    if lf < 0:
        return cr
    return min(cr, lf)
