"""A User ASCII client that never reads while the program broadcasts: the server keeps
at most `MAX_BACKLOG` unread bytes for it and drops the rest (the backlog grew without
bound, about 12 MB a second for a program broadcasting every cycle)."""

from __future__ import annotations

import asyncio
import socket

from motionvm.comm.lineserver import MAX_BACKLOG, LineServer


async def _echo(line: str) -> str:
    return line


def test_a_client_that_never_reads_misses_broadcasts_beyond_the_backlog():
    async def main() -> tuple[list[int], bytes]:
        server = LineServer("user-ascii", _echo)
        port = await server.start("127.0.0.1", 0)
        sleeper = socket.socket()
        sleeper.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        sleeper.connect(("127.0.0.1", port))
        sleeper.setblocking(False)
        for _ in range(100):  # bounded: until the server has the connection
            if server.writers:
                break
            await asyncio.sleep(0.01)
        message = b"x" * 128
        for _ in range(20_000):  # 2.5 MB, none of it read
            server.send_all(message)
            await asyncio.sleep(0)
        sizes = [w.transport.get_write_buffer_size() for w in server.writers]
        first = sleeper.recv(16)
        sleeper.close()
        await server.stop()
        return sizes, first

    sizes, first = asyncio.run(main())
    assert sizes and all(size <= MAX_BACKLOG + 128 for size in sizes), sizes
    assert first == b"x" * 16  # what it was sent arrives, in order
