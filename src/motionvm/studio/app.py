"""The studio's web server: the page, its bundled assets and the protocol's WebSocket.

An ASGI app (Starlette) served by uvicorn on 127.0.0.1 only. Every HTTP request and
WebSocket must carry the studio's token (`?token=...`, which the page passes on to its
assets and its WebSocket); anything else is answered 403. A WebSocket whose `Origin` is
not this server's own page is refused too (another site open in the same browser could
otherwise drive the run); a client without an Origin (a script, an HMI) needs the token
only. Nothing is printed but the one line with the page's address (`serve`).
"""

from __future__ import annotations

import asyncio
import contextlib
import hmac
import secrets
import socket
from collections.abc import Callable
from importlib import resources
from urllib.parse import quote

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import HTMLResponse, PlainTextResponse, Response
from starlette.routing import Route, WebSocketRoute
from starlette.websockets import WebSocket, WebSocketDisconnect

from motionvm.studio.protocol import Studio

STATIC = resources.files("motionvm.studio") / "static"
_TYPES = {".js": "text/javascript", ".css": "text/css", ".svg": "image/svg+xml"}


def _asset(name: str) -> bytes | None:
    if "/" in name or name.startswith("."):
        return None
    f = STATIC / name
    return f.read_bytes() if f.is_file() else None


def create_app(studio: Studio, token: str, port: Callable[[], int]) -> Starlette:
    """The app of `studio`; `port()` gives the port it listens on (for the Origin rule)."""

    def allowed(conn) -> bool:
        given = conn.query_params.get("token", "")
        return hmac.compare_digest(given.encode(), token.encode())

    async def page(request: Request) -> Response:
        if not allowed(request):
            return PlainTextResponse("forbidden: this page needs the studio's token\n", 403)
        html = _asset("index.html")
        if html is None:
            return PlainTextResponse("the studio's page is missing from this install\n", 500)
        text = html.decode("utf-8").replace("{{token}}", quote(token, safe=""))
        return HTMLResponse(text, headers={"Cache-Control": "no-store"})

    async def static(request: Request) -> Response:
        if not allowed(request):
            return PlainTextResponse("forbidden\n", 403)
        name = request.path_params["name"]
        data = _asset(name)
        if data is None or name == "index.html":
            return PlainTextResponse("not found\n", 404)
        suffix = name[name.rfind(".") :]
        return Response(data, media_type=_TYPES.get(suffix, "application/octet-stream"))

    async def socket_(ws: WebSocket) -> None:
        origin = ws.headers.get("origin")
        own = {f"http://127.0.0.1:{port()}", f"http://localhost:{port()}"}
        if not allowed(ws) or (origin is not None and origin not in own):
            await ws.close(code=1008)  # before accept: the handshake is answered 403
            return
        await ws.accept()
        send = ws.send_text
        studio.pages.add(send)
        try:
            while True:
                text = await ws.receive_text()
                # each request on its own task: a slow one (a reset) leaves pause answerable
                asyncio.get_running_loop().create_task(_answer(studio, text, send))
        except WebSocketDisconnect:
            pass
        finally:
            studio.pages.discard(send)

    return Starlette(
        routes=[
            Route("/", page),
            Route("/static/{name}", static),
            WebSocketRoute("/ws", socket_),
        ]
    )


async def _answer(studio: Studio, text: str, send) -> None:
    answer = await studio.handle(text)
    if answer is not None:
        with contextlib.suppress(Exception):  # the page went away
            await send(answer)


def bind(port: int) -> socket.socket:
    """A listening socket on 127.0.0.1:`port` (0: a free one); OSError if taken."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind(("127.0.0.1", port))
        sock.listen(64)
    except OSError:
        sock.close()
        raise
    sock.setblocking(False)
    return sock


def new_token() -> str:
    return secrets.token_urlsafe(18)


async def serve(
    studio: Studio,
    sock: socket.socket,
    token: str,
    ready: Callable[[str], None] | None = None,
    stop: asyncio.Event | None = None,
) -> None:
    """Serve `studio` on the bound socket `sock` until `stop` is set (or the server is
    interrupted); `ready(url)` once it listens. uvicorn says nothing of its own."""
    import uvicorn

    port = sock.getsockname()[1]
    app = create_app(studio, token, lambda: port)
    config = uvicorn.Config(
        app, log_level="error", access_log=False, log_config=None, lifespan="off",
        ws_ping_interval=None, timeout_graceful_shutdown=1,
    )  # fmt: skip
    server = uvicorn.Server(config)
    await studio.start()

    async def watch() -> None:
        while not server.started:
            await asyncio.sleep(0.01)
        if ready is not None:
            ready(f"http://127.0.0.1:{port}/?token={token}")
        if stop is not None:
            await stop.wait()
            server.should_exit = True

    watcher = asyncio.get_running_loop().create_task(watch())
    try:
        await server.serve(sockets=[sock])
    finally:
        watcher.cancel()
        await studio.close()
