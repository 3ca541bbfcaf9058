"""The studio's protocol on the wire: a real server on 127.0.0.1 and a real WebSocket
client run, pause, step, stop at a breakpoint, force an input, scrub and go back, edit a
file; the token and Origin rules of HTTP and WebSocket."""

from __future__ import annotations

import urllib.error
import urllib.request

import pytest
from websockets.exceptions import InvalidStatus

from tests.studio.studio_client import EXAMPLES, TIMEOUT_S, StudioServer, connect_ws

PROGRAM = str(EXAMPLES / "05_pick_and_place.hmpl")
MACHINE = str(EXAMPLES / "05_pick_and_place.toml")
WAITING_LINE = 66  # Print("waiting for start")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with StudioServer([PROGRAM], tmp_path_factory.mktemp("data"), machine=MACHINE) as s:
        yield s


@pytest.fixture
def client(server):
    with server.client() as c:
        c.call("breakpoints.set", {"path": PROGRAM, "lines": []})
        c.call("run.speed", {"factor": None})
        c.call("run.reset")
        c.notes.clear()
        yield c


def test_hello_describes_the_files_the_machine_and_the_default_scope(client):
    hello = client.call("studio.hello")
    assert [f["name"] for f in hello["files"]] == ["05_pick_and_place.hmpl"]
    assert hello["files"][0]["language"] == "hmpl"
    machine = hello["machine"]
    assert [a["name"] for a in machine["axes"]] == ["axis0", "axis1", "axis2"]
    assert "gpi3" in machine["inputs"] and "gpo1" in machine["outputs"]
    assert hello["scope"][:3] == ["axis0.pos_fb", "axis1.pos_fb", "axis2.pos_fb"]
    assert len(hello["scope"]) == 8
    assert hello["units"]["axis0.vel_fb"] == "mm/s"
    assert hello["state"] | {"running": False, "time": 0.0, "cycle": 0} == hello["state"]


def test_run_to_a_time_streams_lines_scope_and_panels_then_steps_a_cycle(client):
    client.call("run.to_time", {"seconds": 1.9})
    stopped = client.wait_for("stopped")
    assert stopped["reason"] == "goto" and stopped["cycle"] == 1900
    assert "homed at t=1835 ms: X 0, Z 0; X at 0.000 mm, Z at 0.000 mm" in client.console_text()
    scope = [n["params"] for n in client.notes if n["method"] == "scope"]
    assert scope and scope[-1]["t"][-1] <= 1.9
    xs = [v for s in scope for v in s["values"]["axis0.pos_fb"]]
    assert xs[0] == pytest.approx(137.0) and xs[-1] == pytest.approx(0.0, abs=1e-6)
    client.call("run.step_cycle", {"count": 1})
    assert client.wait_for("stopped")["cycle"] == 1901
    assert client.call("studio.hello")["state"]["time"] == pytest.approx(1.901)


def test_pause_stops_a_paced_run(client):
    client.call("run.speed", {"factor": 1.0})
    client.call("run.start")
    client.wait_for("state", lambda p: p["time"] > 0.1)
    client.call("run.pause")
    stopped = client.wait_for("stopped")
    assert stopped["reason"] == "pause" and 0.1 < stopped["time"] < 1.835
    assert client.call("studio.hello")["state"]["running"] is False


def test_a_run_waiting_for_an_input_nothing_sets_stops_as_waiting_forever(client):
    client.call("run.start")
    stopped = client.wait_for("stopped")
    assert stopped["reason"] == "waits forever" and stopped["time"] > 1.835
    assert "waiting for start" in client.console_text()
    assert client.call("studio.hello")["state"]["waits_forever"] is True
    client.call("io.force", {"name": "gpi3", "value": 1})  # now it can go on
    client.call("run.to_time", {"seconds": stopped["time"] + 0.2})
    assert client.wait_for("stopped")["reason"] == "goto"
    assert client.call("studio.hello")["state"]["waits_forever"] is False


def test_a_breakpoint_stops_the_run_and_shows_the_stack_and_variables(client):
    bps = client.call("breakpoints.set", {"path": PROGRAM, "lines": [WAITING_LINE]})
    assert bps == [{"line": WAITING_LINE, "verified": True, "message": ""}]
    client.call("run.start")
    stopped = client.wait_for("stopped")
    assert (stopped["reason"], stopped["line"], stopped["file"]) == (
        "breakpoint", WAITING_LINE, PROGRAM)  # fmt: skip
    threads = client.call("debug.threads")
    frames = client.call("debug.stack", {"thread": threads[0]["id"]})
    assert (frames[0]["name"], frames[0]["line"]) == ("main", WAITING_LINE)
    variables = client.call("debug.variables", {"frame": frames[0]["id"]})
    assert {"name": "parts", "value": "0"} in variables["locals"]
    assert (
        client.call("debug.evaluate", {"expression": "parts + 2", "frame": frames[0]["id"]}) == "2"
    )


def test_forcing_an_input_makes_the_program_go_on(client):
    client.call("run.to_time", {"seconds": 1.95})
    client.wait_for("stopped")
    client.call("io.force", {"name": "gpi3", "value": "ON"})
    client.call("run.to_time", {"seconds": 2.2})
    client.wait_for("stopped")
    assert "start at t=1950 ms" in client.console_text()
    panels = [n["params"] for n in client.notes if n["method"] == "panels"][-1]
    assert panels["io"]["inputs"]["gpi3"] == 1


def test_the_recorded_run_can_be_scrubbed_and_the_debugger_moved_back(server, client):
    client.call("run.to_time", {"seconds": 1.0})
    client.wait_for("stopped")
    at = client.call("history.at", {"time": 0.5, "span": 0.5})
    x = at["axes"][0]
    # (the recording's resolution follows the run's speed in wall time: a row every
    # `stride` cycles, more of them the faster the machine runs)
    row = server.studio.run.history.stride * 0.001
    assert 0.5 - row - 1e-9 <= at["time"] <= 0.5 and x["state"] == "homing"
    assert 100.0 < x["pos_fb"] < 137.0
    assert at["scope"]["t"][0] == pytest.approx(0.0) and at["scope"]["t"][-1] == at["time"]
    later = client.call("history.at", {"time": 1.0})["axes"][0]["pos_fb"]
    assert later < x["pos_fb"]  # homing runs toward the switch at 0..5 mm
    state = client.call("run.seek", {"time": 0.5})
    assert state["cycle"] == 500 and state["recorded"] > 0.9  # the future stays recorded
    assert client.wait_for("stopped")["reason"] == "goto"
    live = [n["params"] for n in client.notes if n["method"] == "panels"][-1]
    assert live["axes"][0]["pos_fb"] == pytest.approx(x["pos_fb"], abs=0.05)


def test_a_scope_channel_can_be_chosen_from_the_run(client):
    names = {c["name"]: c["unit"] for c in client.call("scope.channels")}
    assert names["axis0.ref_vel"] == "mm/s" and names["gpi3"] == "bool"
    chosen = client.call("scope.select", {"channels": ["axis0.ref_vel", "gpi3"]})
    assert chosen["scope"] == ["axis0.ref_vel", "gpi3"]
    answer = client.request("scope.select", {"channels": ["axis0.nope"]})
    assert "unknown scope channel 'axis0.nope'" in answer["error"]["message"]
    assert len(client.call("scope.select", {"channels": None})["scope"]) == 8  # the defaults


def test_an_edit_gets_the_language_s_diagnostics(client):
    text = client.call("file.open", {"path": PROGRAM})["text"]
    broken = text.replace("int parts = 0;", "int parts = ;")
    found = client.call("file.edit", {"path": PROGRAM, "text": broken})["diagnostics"]
    assert found and found[0]["severity"] == "error"
    assert found[0]["line"] == text.splitlines().index("    int parts = 0;") + 1
    assert client.call("file.edit", {"path": PROGRAM, "text": text})["diagnostics"] == []


def test_bad_requests_get_errors_not_a_closed_socket(client):
    assert client.request("no.such")["error"]["code"] == -32601
    assert "seconds" in client.request("run.to_time", {})["error"]["message"]
    bad = client.request("run.to_time", {"seconds": -1})["error"]
    assert bad["code"] == -32000 and "-1" in bad["message"]
    assert client.request("io.force", {"name": "nothing9", "value": 1})["error"]["code"] == -32000
    client.ws.send("not json")
    assert client.call("studio.hello")["files"]


def _get(url: str) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url, timeout=TIMEOUT_S) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as exc:
        return exc.code, ""


def test_every_http_request_needs_the_token(server):
    base = f"http://127.0.0.1:{server.port}"
    status, page = _get(f"{base}/?token={server.token}")
    assert status == 200 and f"static/app.js?token={server.token}" in page
    assert _get(f"{base}/")[0] == 403
    assert _get(f"{base}/?token=wrong")[0] == 403
    assert _get(f"{base}/static/app.js")[0] == 403
    assert _get(f"{base}/static/app.js?token={server.token}")[0] == 200


def test_a_websocket_needs_the_token_and_the_studio_s_own_origin(server):
    with pytest.raises(InvalidStatus) as exc:
        connect_ws(server.ws_url("wrong"))
    assert exc.value.response.status_code == 403
    with pytest.raises(InvalidStatus) as exc:
        connect_ws(server.ws_url(), origin="http://evil.example")
    assert exc.value.response.status_code == 403
    own = f"http://127.0.0.1:{server.port}"
    ws = connect_ws(server.ws_url(), origin=own)
    try:
        ws.send('{"jsonrpc": "2.0", "id": 1, "method": "studio.hello"}')
        assert '"result"' in ws.recv(timeout=TIMEOUT_S)
    finally:
        ws.close()
