"""`motionvm debug`: the Debug Adapter Protocol server, on stdio or one TCP connection."""

from __future__ import annotations

import sys

from motionvm.cli.exits import UsageError


def cmd_debug(args) -> int:
    from motionvm.dap.server import serve_stdio, serve_tcp

    if args.port is None:
        return serve_stdio()

    def ready(port: int) -> None:
        print(f"motionvm debug: listening on 127.0.0.1:{port}", file=sys.stderr, flush=True)

    try:
        return serve_tcp(args.port, ready)
    except OSError as exc:
        raise UsageError(f"--port {args.port}: {exc.strerror or exc}") from None
