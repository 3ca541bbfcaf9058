"""A small Debug Adapter Protocol client for the tests: `motionvm debug` in a subprocess,
spoken to over its real stdin/stdout pipes; every wait bounded in time."""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
from pathlib import Path

import motionvm

TIMEOUT_S = 60.0
"""Wall-clock limit of any one wait [s]."""


class DapClient:
    def __init__(self, cwd: Path) -> None:
        env = dict(os.environ)
        src = str(Path(motionvm.__file__).resolve().parents[1])
        env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
        env["MOTIONVM_DATA_DIR"] = str(cwd / "data")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "motionvm", "debug"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            cwd=cwd,
            env=env,
        )
        self.seq = 0
        self.messages: queue.Queue = queue.Queue()
        self.events: list[dict] = []
        self._pending: list[dict] = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        stream = self.proc.stdout
        while True:
            header = b""
            while not header.endswith(b"\r\n\r\n"):
                ch = stream.read(1)
                if not ch:
                    self.messages.put(None)
                    return
                header += ch
            length = int(header.split(b"Content-Length:")[1].split(b"\r\n")[0])
            body = stream.read(length)
            self.messages.put(json.loads(body))

    def send(self, command: str, arguments: dict | None = None) -> int:
        self.seq += 1
        body = json.dumps(
            {"seq": self.seq, "type": "request", "command": command, "arguments": arguments or {}}
        ).encode()
        self.proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.proc.stdin.flush()
        return self.seq

    def _next(self) -> dict:
        if self._pending:
            return self._pending.pop(0)
        message = self.messages.get(timeout=TIMEOUT_S)
        assert message is not None, "the adapter closed its output"
        if message["type"] == "event":
            self.events.append(message)
        return message

    def request(self, command: str, arguments: dict | None = None) -> dict:
        """Send a request; its response (events that come first are kept)."""
        seq = self.send(command, arguments)
        skipped = []
        for _ in range(10_000):
            message = self._next()
            if message["type"] == "response" and message["request_seq"] == seq:
                self._pending = skipped + self._pending
                return message
            skipped.append(message)
        raise AssertionError(f"no response to {command}")

    def ok(self, command: str, arguments: dict | None = None) -> dict:
        response = self.request(command, arguments)
        assert response["success"], response
        return response.get("body", {})

    def wait_event(self, name: str) -> dict:
        for i, message in enumerate(self._pending):
            if message["type"] == "event" and message["event"] == name:
                return self._pending.pop(i)["body"]
        for _ in range(10_000):
            message = self.messages.get(timeout=TIMEOUT_S)
            assert message is not None, f"the adapter ended before a '{name}' event"
            if message["type"] == "event":
                self.events.append(message)
                if message["event"] == name:
                    return message.get("body", {})
            else:
                self._pending.append(message)
        raise AssertionError(f"no '{name}' event")

    def stdout(self) -> str:
        return "".join(
            e["body"]["output"]
            for e in self.events
            if e["event"] == "output" and e["body"].get("category") == "stdout"
        )

    def launch(self, program, stop_on_entry=False, **more) -> dict:
        caps = self.ok("initialize", {"adapterID": "motionvm", "linesStartAt1": True})
        self.ok("launch", {"program": program, "stopOnEntry": stop_on_entry, **more})
        self.wait_event("initialized")
        return caps

    def close(self) -> None:
        try:
            self.request("disconnect")
        except (AssertionError, queue.Empty, BrokenPipeError, OSError):
            pass
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
