"""What a connection to an ASCII server passes before its lines run: the refusal of HTTP
and the token handshake (comm/lineserver.py applies them).

HTTP: a web page in a browser on the same machine can send an HTTP request to any
loopback port (`fetch("http://127.0.0.1:3999", {mode: "no-cors", method: "POST",
body: ...})`); the browser sends it whatever the answer, so each of its lines would be
run as a request. A line that is an HTTP request line (`GET / HTTP/1.1`) or a header a
browser or an HTTP client sends (`Host: ...`, `Origin: ...`, `Sec-Fetch-Mode: ...`)
closes the connection; nothing after it runs.

Token: with `[comm] token = "..."`, the first request line of a connection must be the
token (compared in constant time); the server replies `OK` and serves the connection,
or replies `ERR wrong token` and closes it.
"""

from __future__ import annotations

import hmac
import re

_REQUEST_LINE = re.compile(r"[A-Z]+ \S+ HTTP/\d(?:\.\d)?\s*")
"""`METHOD TARGET HTTP/x.y`: the first line of every HTTP/1 request (and HTTP/2's preface)."""
_HEADER = re.compile(r"\s*([A-Za-z][A-Za-z0-9-]*)\s*:")
HTTP_HEADERS = frozenset(
    """host origin referer user-agent accept accept-encoding accept-language accept-charset
    content-type content-length content-encoding transfer-encoding connection keep-alive
    upgrade cookie authorization cache-control pragma dnt te priority expect range
    if-match if-none-match if-modified-since if-unmodified-since x-requested-with
    x-forwarded-for forwarded proxy-connection proxy-authorization""".split()
)
"""Header names (lower case) that mark a line as HTTP, besides `sec-*` and
`access-control-*` (the browser's fetch metadata and CORS preflight)."""

HTTP_REFUSED = "ERR HTTP requests are refused: this server speaks one request per line"
WRONG_TOKEN = "ERR wrong token"


def looks_like_http(line: str) -> bool:
    """Whether `line` (terminator stripped) is an HTTP request line or a known header."""
    if _REQUEST_LINE.fullmatch(line):
        return True
    m = _HEADER.match(line)
    if m is None:
        return False
    name = m.group(1).lower()
    return name in HTTP_HEADERS or name.startswith(("sec-", "access-control-"))


def token_matches(line: str, token: str) -> bool:
    """Whether the line a client sent first is `token` (constant time)."""
    return hmac.compare_digest(line.encode("latin-1", "replace"), token.encode("ascii"))
