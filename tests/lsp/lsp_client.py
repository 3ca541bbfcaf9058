"""A small LSP client for the tests: `motionvm lsp` as a subprocess, JSON-RPC over its real
pipes, every wait bounded in time."""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
import time
from pathlib import Path

TIMEOUT = 30.0
"""Longest wait for one answer [s] (wall clock: a loaded CI machine is slow)."""


class LspClient:
    """`motionvm lsp` in a subprocess; `request` waits for its answer, notifications the
    server sends are kept in `notes`."""

    def __init__(self, cwd: str | Path | None = None) -> None:
        env = dict(os.environ)
        src = str(Path(__file__).resolve().parents[2] / "src")
        env["PYTHONPATH"] = src + os.pathsep + env.get("PYTHONPATH", "")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "motionvm", "lsp"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            cwd=cwd,
            env=env,
        )
        self._next = 0
        self._answers: dict[int, queue.Queue] = {}
        self.notes: queue.Queue = queue.Queue()
        self._lock = threading.Lock()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self.stderr: list[bytes] = []
        threading.Thread(target=self._drain, daemon=True).start()

    # ------------------------------------------------------------ wire

    def _send(self, message: dict) -> None:
        body = json.dumps(message).encode()
        with self._lock:
            self.proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
            self.proc.stdin.flush()

    def send_raw(self, data: bytes) -> None:
        with self._lock:
            self.proc.stdin.write(data)
            self.proc.stdin.flush()

    def _read(self) -> None:
        out = self.proc.stdout
        while True:
            length = None
            while True:
                line = out.readline()
                if not line:
                    return
                if line in (b"\r\n", b"\n"):
                    break
                name, _, value = line.decode("ascii", "replace").partition(":")
                if name.lower() == "content-length":
                    length = int(value.strip())
            if length is None:
                continue
            message = json.loads(out.read(length))
            if "id" in message and "method" not in message:
                self._answers.setdefault(message["id"], queue.Queue()).put(message)
            elif "id" in message:  # a request of the server (e.g. workspace/configuration)
                self._send({"jsonrpc": "2.0", "id": message["id"], "result": None})
            else:
                self.notes.put(message)

    def _drain(self) -> None:
        for line in self.proc.stderr:
            self.stderr.append(line)

    # ------------------------------------------------------------ protocol

    def request(self, method: str, params: dict | None) -> dict:
        """The full answer (`result` or `error`) to one request."""
        self._next += 1
        rid = self._next
        box = self._answers.setdefault(rid, queue.Queue())
        self._send({"jsonrpc": "2.0", "id": rid, "method": method, "params": params})
        try:
            return box.get(timeout=TIMEOUT)
        except queue.Empty:
            raise AssertionError(f"no answer to {method} in {TIMEOUT} s") from None

    def result(self, method: str, params: dict | None):
        answer = self.request(method, params)
        assert "error" not in answer, answer
        return answer["result"]

    def notify(self, method: str, params: dict | None) -> None:
        self._send({"jsonrpc": "2.0", "method": method, "params": params})

    def initialize(self) -> dict:
        caps = self.result(
            "initialize",
            {"processId": os.getpid(), "rootUri": None, "capabilities": {}},
        )
        self.notify("initialized", {})
        return caps

    def diagnostics(self, uri: str, timeout: float = TIMEOUT) -> list[dict]:
        """The next diagnostics published for `uri` (other notifications are dropped)."""
        end = time.monotonic() + timeout
        while True:
            left = end - time.monotonic()
            if left <= 0:
                raise AssertionError(f"no diagnostics for {uri} in {timeout} s")
            try:
                note = self.notes.get(timeout=left)
            except queue.Empty:
                continue
            if note.get("method") == "textDocument/publishDiagnostics":
                if note["params"]["uri"] == uri:
                    return note["params"]["diagnostics"]

    def next_publish(self, timeout: float = TIMEOUT) -> dict:
        """The params of the next publishDiagnostics notification, whatever its uri."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                note = self.notes.get(timeout=max(0.01, end - time.monotonic()))
            except queue.Empty:
                break
            if note.get("method") == "textDocument/publishDiagnostics":
                return note["params"]
        raise AssertionError(f"no diagnostics in {timeout} s")

    def open(self, uri: str, text: str, language_id: str = "", version: int = 1) -> None:
        self.notify(
            "textDocument/didOpen",
            {"textDocument": {"uri": uri, "languageId": language_id, "version": version,
                              "text": text}},
        )  # fmt: skip

    def change(self, uri: str, version: int, changes: list[dict]) -> None:
        self.notify(
            "textDocument/didChange",
            {"textDocument": {"uri": uri, "version": version}, "contentChanges": changes},
        )

    def at(self, method: str, uri: str, line: int, character: int, **extra):
        params = {"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}
        params.update(extra)
        return self.result(method, params)

    def close(self) -> int:
        """Shut the server down; its exit code."""
        try:
            if self.proc.poll() is None:
                self.request("shutdown", None)
                self.notify("exit", None)
                return self.proc.wait(timeout=TIMEOUT)
        except (OSError, AssertionError):
            pass
        finally:
            if self.proc.poll() is None:
                self.proc.kill()
                self.proc.wait(timeout=TIMEOUT)
        return self.proc.returncode
