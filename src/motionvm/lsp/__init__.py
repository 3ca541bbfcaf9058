"""The language server (`motionvm lsp`): LSP over stdin/stdout or TCP, built on pygls.

A face: it translates the Language Server Protocol to the language interface
(`motionvm.lang`) and the session's `check`, and decides nothing of its own. Each open
document is checked exactly as `motionvm check` checks its file (with the editor's unsaved
text), and indexed once per version (`documents.py`); `features.py` answers the requests
from that index; `convert.py` turns the interface's records into LSP's; `server.py` wires
them to pygls.
"""

from __future__ import annotations

import os
import sys

__all__ = ["serve"]


def serve(tcp_port: int | None = None, host: str = "127.0.0.1") -> None:
    """Run the server until the client exits: on stdin/stdout, or on `host:tcp_port`."""
    from motionvm.lsp.server import build_server

    server = build_server()
    if tcp_port is not None:
        server.start_tcp(host, tcp_port)
        return
    # The protocol gets its own handles on stdin/stdout; anything else that would print
    # to stdout (a stray print) goes to stderr instead of corrupting the protocol.
    stdin = os.fdopen(os.dup(sys.stdin.fileno()), "rb")
    stdout = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    saved = sys.stdout
    sys.stdout = sys.stderr
    try:
        server.start_io(stdin, stdout)
    finally:
        sys.stdout = saved
