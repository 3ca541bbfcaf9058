"""A studio on a real socket for the tests: `motionvm studio`'s server (uvicorn on
127.0.0.1, port 0) in a thread of the test process, and a small protocol client over a
real WebSocket (the `websockets` library); every wait bounded in time."""

from __future__ import annotations

import asyncio
import json
import os
import threading
import time
from collections.abc import Callable
from pathlib import Path

from websockets.sync.client import connect

from motionvm.studio import Studio
from motionvm.studio.app import bind, new_token, serve

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CHROMIUM = "/usr/bin/chromium"
"""Debian's chromium (`playwright install` cannot download a browser here)."""
TIMEOUT_S = 30.0
"""Wall-clock limit of any one wait [s]."""


class StudioServer:
    """`with StudioServer(files, machine=...) as server:` a studio listening on
    `server.port` with `server.token`."""

    def __init__(self, files: list[str], data_dir: Path, **options) -> None:
        self.files, self.options, self.data_dir = files, options, data_dir
        self.token = new_token()
        self.url = ""
        self._stop: asyncio.Event | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._ready = threading.Event()
        self._thread = threading.Thread(target=self._main, name="studio-test", daemon=True)
        self.error: BaseException | None = None

    def _main(self) -> None:
        async def main() -> None:
            self._loop = asyncio.get_running_loop()
            self._stop = asyncio.Event()
            studio = Studio(self.files, **self.options)
            self.studio = studio

            def ready(url: str) -> None:
                self.url = url
                self._ready.set()

            await serve(studio, self.sock, self.token, ready, self._stop)

        try:
            asyncio.run(main())
        except BaseException as exc:  # noqa: BLE001 — shown by the test
            self.error = exc
            self._ready.set()

    def __enter__(self) -> StudioServer:
        self._old_data = os.environ.get("MOTIONVM_DATA_DIR")
        os.environ["MOTIONVM_DATA_DIR"] = str(self.data_dir)
        self.sock = bind(0)
        self.port = self.sock.getsockname()[1]
        self._thread.start()
        assert self._ready.wait(TIMEOUT_S), "the studio did not start"
        if self.error is not None:
            raise self.error
        return self

    def __exit__(self, *exc) -> None:
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        self._thread.join(TIMEOUT_S)
        if self._old_data is None:
            os.environ.pop("MOTIONVM_DATA_DIR", None)
        else:
            os.environ["MOTIONVM_DATA_DIR"] = self._old_data

    def ws_url(self, token: str | None = None) -> str:
        return f"ws://127.0.0.1:{self.port}/ws?token={self.token if token is None else token}"

    def client(self) -> StudioClient:
        return StudioClient(connect(self.ws_url(), max_size=None, open_timeout=TIMEOUT_S))


def connect_ws(url: str, **kwargs):
    """An open sync WebSocket (closed by the caller)."""
    return connect(url, open_timeout=TIMEOUT_S, **kwargs).__enter__()


class StudioClient:
    """Requests and their answers; notifications kept in arrival order."""

    def __init__(self, ws) -> None:
        self.ws = ws.__enter__()
        self.notes: list[dict] = []
        """Every notification since the last `notes.clear()`."""
        self._seen = 0
        self._id = 0

    def close(self) -> None:
        self.ws.close()

    def __enter__(self) -> StudioClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _next(self, deadline: float) -> dict:
        left = deadline - time.monotonic()
        assert left > 0, "timed out waiting for the studio"
        return json.loads(self.ws.recv(timeout=left))

    def request(self, method: str, params: dict | None = None) -> dict:
        """The whole answer (`result` or `error`)."""
        self._id += 1
        rid = self._id
        self.ws.send(json.dumps({"jsonrpc": "2.0", "id": rid, "method": method,
                                 "params": params or {}}))  # fmt: skip
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            message = self._next(deadline)
            if message.get("id") == rid:
                return message
            self.notes.append(message)

    def call(self, method: str, params: dict | None = None):
        answer = self.request(method, params)
        assert "error" not in answer, answer
        return answer["result"]

    def wait_for(self, method: str, test: Callable[[dict], bool] = lambda p: True) -> dict:
        """The params of the first notification `method` after the one the last wait
        found (kept or new) that passes `test`."""
        deadline = time.monotonic() + TIMEOUT_S
        self._seen = min(self._seen, len(self.notes))
        while True:
            while self._seen < len(self.notes):
                note = self.notes[self._seen]
                self._seen += 1
                if note.get("method") == method and test(note["params"]):
                    return note["params"]
            message = self._next(deadline)
            if "id" not in message:
                self.notes.append(message)

    def console_text(self) -> list[str]:
        return [line["text"] for n in self.notes if n.get("method") == "console"
                for line in n["params"]["lines"]]  # fmt: skip


def launch_chromium(playwright):
    """Debian's chromium, headless, through a started Playwright (`sync_playwright()`)."""
    return playwright.chromium.launch(
        executable_path=CHROMIUM,
        headless=True,
        args=["--no-sandbox", "--disable-background-networking", "--disable-component-update"],
    )


def inked(page, canvas: str) -> int:
    """Pixels drawn (not transparent) on the canvas `canvas` (a CSS selector) of a page."""
    return page.evaluate(
        """(selector) => {
            const c = document.querySelector(selector);
            const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
            let n = 0;
            for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++;
            return n;
        }""",
        canvas,
    )
