"""The Debug Adapter Protocol's wire format: JSON messages framed by a Content-Length header.

    Content-Length: 119\\r\\n
    \\r\\n
    {"seq": 1, "type": "request", "command": "initialize", "arguments": {...}}

`read_message` reads one message from a binary stream (None at the end of the stream;
ProtocolError when the framing is lost, BadMessage for a body that is not a JSON object);
`Writer` writes messages with increasing `seq` numbers from any thread, one at a time.
"""

from __future__ import annotations

import json
import threading
from typing import BinaryIO

MAX_MESSAGE = 16 * 1024 * 1024
"""The largest message body accepted [bytes]."""


class ProtocolError(Exception):
    """A malformed frame: the connection cannot go on."""


class BadMessage(Exception):
    """A well-framed message that is not a JSON object: skipped, the connection goes on."""


def read_message(stream: BinaryIO) -> dict | None:
    """One message, or None at the end of the stream."""
    length = None
    while True:
        line = stream.readline(65536)
        if not line:
            return None
        line = line.rstrip(b"\r\n")
        if not line:
            if length is None:
                continue  # stray blank lines between messages
            break
        name, _, value = line.partition(b":")
        if name.strip().lower() == b"content-length":
            try:
                length = int(value.strip())
            except ValueError:
                raise ProtocolError(f"bad Content-Length {value!r}") from None
            if not 0 <= length <= MAX_MESSAGE:
                raise ProtocolError(f"Content-Length {length} out of range")
    body = b""
    while len(body) < length:
        chunk = stream.read(length - len(body))
        if not chunk:
            return None
        body += chunk
    try:
        message = json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise BadMessage(f"a message that is not JSON: {exc}") from None
    if not isinstance(message, dict):
        raise BadMessage("a message that is not a JSON object")
    return message


class Writer:
    """Writes framed messages, numbering them."""

    def __init__(self, stream: BinaryIO) -> None:
        self._stream = stream
        self._seq = 0
        self._lock = threading.Lock()

    def send(self, message: dict) -> None:
        with self._lock:
            self._seq += 1
            message = {"seq": self._seq, **message}
            body = json.dumps(message, default=str).encode("utf-8")
            try:
                self._stream.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
                self._stream.flush()
            except (BrokenPipeError, ValueError, OSError):
                pass  # the client went away

    def event(self, name: str, body: dict | None = None) -> None:
        self.send({"type": "event", "event": name, "body": body or {}})

    def respond(self, request: dict, body: dict | None = None, error: str | None = None) -> None:
        out = {
            "type": "response",
            "request_seq": request.get("seq", 0),
            "command": request.get("command", ""),
            "success": error is None,
        }
        if error is not None:
            out["message"] = error
            out["body"] = {"error": {"id": 1, "format": error}}
        else:
            out["body"] = body or {}
        self.send(out)
