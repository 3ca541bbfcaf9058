"""`motionvm debug --port N`: the same protocol on one TCP connection of 127.0.0.1."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
from pathlib import Path

import motionvm


def _frame(message: dict) -> bytes:
    body = json.dumps(message).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def _read(stream) -> dict:
    length = 0
    while True:
        line = stream.readline()
        assert line, "the adapter closed the connection"
        if line == b"\r\n":
            break
        if line.lower().startswith(b"content-length:"):
            length = int(line.split(b":")[1])
    return json.loads(stream.read(length))


def test_one_client_over_tcp(tmp_path):
    (tmp_path / "a.hmpl").write_text('void main()\n{\n    Print("hi");\n}\n')
    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(motionvm.__file__).resolve().parents[1])
    proc = subprocess.Popen([sys.executable, "-m", "motionvm", "debug", "--port", "0"],
                            cwd=tmp_path, env=env, stderr=subprocess.PIPE)  # fmt: skip
    try:
        line = proc.stderr.readline().decode()
        assert line.startswith("motionvm debug: listening on 127.0.0.1:")
        port = int(line.rsplit(":", 1)[1])
        with socket.create_connection(("127.0.0.1", port), timeout=60) as sock:
            stream = sock.makefile("rwb")
            requests = [
                {"seq": 1, "type": "request", "command": "initialize", "arguments": {}},
                {"seq": 2, "type": "request", "command": "launch",
                 "arguments": {"program": str(tmp_path / "a.hmpl")}},
                {"seq": 3, "type": "request", "command": "configurationDone"},
            ]  # fmt: skip
            for r in requests:
                stream.write(_frame(r))
            stream.flush()
            seen = []
            for _ in range(50):
                message = _read(stream)
                seen.append(message)
                if message.get("event") == "terminated":
                    break
            events = [m.get("event") for m in seen if m["type"] == "event"]
            assert events[0] == "initialized" and events[-2:] == ["exited", "terminated"]
            out = [m["body"]["output"] for m in seen if m.get("event") == "output"]
            assert out == ["hi\n"]
            stream.write(_frame({"seq": 4, "type": "request", "command": "disconnect"}))
            stream.flush()
        assert proc.wait(timeout=30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
