"""Both ASCII servers refuse HTTP: a web page in a browser on the same machine can send
a request to any loopback port (`fetch("http://127.0.0.1:3999", {mode: "no-cors",
method: "POST", body})`), so a line that is an HTTP request line or header closes the
connection and nothing after it runs. Real HTTP requests over loopback sockets."""

from __future__ import annotations

import http.client

import pytest
from comm_helpers import WAIT, LineClient, served

from motionvm.comm.gate import HTTP_REFUSED, looks_like_http
from motionvm.comm.lineserver import MAX_LINE
from motionvm.comm.modbus_map import gpio_index

PROGRAM = """
void Agent(char *cmd, char *res) {
    HIMC_GPO(2) = 1;
    StringCopy(res, cmd);
}
void main() { START_ASCII_AGENT(Agent); }
"""

BODY = b"HIMC_GPO(1, 1)\r\nsystem_ltest0 = 7\r\nSaveUserTable()\r\n"
"""What a hostile page posts: set an output, write a global, save the user table."""

BROWSER_REQUEST = (
    b"POST / HTTP/1.1\r\n"
    b"Host: 127.0.0.1:3999\r\n"
    b"Origin: https://evil.example\r\n"
    b"Content-Type: text/plain;charset=UTF-8\r\n"
    b"Sec-Fetch-Mode: no-cors\r\n"
    b"Content-Length: " + str(len(BODY)).encode() + b"\r\n\r\n" + BODY
)


@pytest.fixture(scope="module")
def server():
    with served(PROGRAM) as (sim, srv):
        yield sim, srv


def _untouched(sim, data_dir) -> None:
    gpo = sim.controller.io.gpio.outputs
    assert gpo[gpio_index(1)] == 0 and gpo[gpio_index(2)] == 0
    assert sim.read("system_ltest0") == 0
    assert not any(data_dir.iterdir())  # SaveUserTable wrote nothing


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_an_http_post_runs_nothing_and_is_closed(server, name, data_dir):
    sim, srv = server
    c = LineClient(srv.ports[name])
    c.send(BROWSER_REQUEST)
    assert c.rest() == HTTP_REFUSED.encode() + b"\r\n"
    c.close()
    _untouched(sim, data_dir)


@pytest.mark.parametrize("name", ["native-ascii", "user-ascii"])
def test_http_client_gets_no_http_answer_and_nothing_runs(server, name, data_dir):
    sim, srv = server
    conn = http.client.HTTPConnection("127.0.0.1", srv.ports[name], timeout=WAIT)
    conn.request("POST", "/", body=BODY, headers={"Content-Type": "text/plain"})
    with pytest.raises(http.client.HTTPException):  # BadStatusLine or RemoteDisconnected
        conn.getresponse()
    conn.close()
    _untouched(sim, data_dir)


def test_a_header_after_a_request_line_too_long_still_closes(server, data_dir):
    """A long URL makes the request line too long to read; its headers close it."""
    sim, srv = server
    c = LineClient(srv.ports["native-ascii"])
    c.send(b"GET /" + b"a" * MAX_LINE + b" HTTP/1.1\r\nHost: x\r\n\r\n" + BODY)
    assert c.rest() == b"ERR line too long\r\n" + HTTP_REFUSED.encode() + b"\r\n"
    c.close()
    _untouched(sim, data_dir)


def test_lines_with_a_colon_that_are_not_http_are_served(server):
    sim, srv = server
    native = LineClient(srv.ports["native-ascii"])
    assert native.ask("speed: 5").startswith("ERR ")  # not a request, but no HTTP either
    assert native.ask("system_ltest5") == "0"  # still connected
    native.close()
    user = LineClient(srv.ports["user-ascii"])
    assert user.ask("MOVE 0: 5 GET") == "MOVE 0: 5 GET"
    user.close()
    sim.controller.io.gpio.outputs[gpio_index(2)] = 0


@pytest.mark.parametrize(
    "line",
    [
        "GET / HTTP/1.1",
        "POST /api?x=1 HTTP/1.0",
        "OPTIONS * HTTP/1.1",
        "PRI * HTTP/2.0",
        "Host: 127.0.0.1:3999",
        "origin: null",
        "User-Agent: Mozilla/5.0",
        "Sec-Fetch-Site: cross-site",
        "Access-Control-Request-Method: POST",
        "Content-Length: 12",
    ],
)
def test_http_lines_are_recognised(line):
    assert looks_like_http(line)


@pytest.mark.parametrize(
    "line",
    ["GetPosFb(0)", "system_ltest0 = 1", "GET pos", "speed: 5", "MOVEABS 0 0.05", "HTTP/1.1"],
)
def test_request_lines_are_not_http(line):
    assert not looks_like_http(line)
