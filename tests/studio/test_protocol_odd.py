"""The studio's protocol given odd requests on the wire: values out of range, a seek far
beyond the recording of a run that never ends, breakpoints in an edited, unsaved file.
Every request gets an answer; nothing blocks the studio."""

from __future__ import annotations

import threading
import time

import pytest

from tests.studio.studio_client import TIMEOUT_S, StudioServer

FOREVER = """int n = 0;
void main()
{


    while (1) {
        n = n + 1;
        Sleep(1);
    }
}
"""


@pytest.fixture
def server(tmp_path):
    path = tmp_path / "forever.hmpl"
    path.write_text(FOREVER)
    with StudioServer([str(path)], tmp_path / "data") as s:
        s.path = str(path)
        yield s


def test_values_out_of_range_are_answered_with_errors(server):
    with server.client() as client:
        for method, params in [
            ("run.seek", {"time": 1e308}),
            ("run.seek", {"time": "inf"}),
            ("history.at", {"time": "inf"}),
        ]:
            error = client.request(method, params)["error"]
            assert error == {"code": -32602, "message": f"{method}: time {params['time']} s "
                                                        "is beyond any run"}  # fmt: skip
        error = client.request("file.edit", {"path": server.path, "text": None})["error"]
        assert error == {"code": -32602, "message": "file.edit: 'text' must be a string"}
        assert client.call("file.open", {"path": server.path})["text"] == FOREVER
        assert client.call("studio.hello")["state"]["loaded"]


def test_pause_stops_a_seek_far_beyond_the_recording(server):
    answers: list[dict] = []
    with server.client() as seeker, server.client() as pauser:
        thread = threading.Thread(
            target=lambda: answers.append(seeker.request("run.seek", {"cycle": 10**9}))
        )
        thread.start()
        time.sleep(0.5)
        deadline = time.monotonic() + TIMEOUT_S
        while thread.is_alive() and time.monotonic() < deadline:
            pauser.call("run.pause")
            thread.join(0.2)
        assert not thread.is_alive(), "the seek went on after a pause"
        state = answers[0]["result"]
        assert 0 < state["cycle"] < 10**9 and not state["running"]
        assert pauser.call("run.step_cycle", {"count": 1})["cycle"] == state["cycle"] + 1


def test_breakpoints_are_placed_on_the_unsaved_text_that_runs(server):
    with server.client() as client:
        edited = FOREVER.replace("{\n\n\n", "{\n    n = 10;\n    n = 11;\n")
        client.call("file.edit", {"path": server.path, "text": edited})
        client.call("run.reset")
        (bp,) = client.call("breakpoints.set", {"path": server.path, "lines": [4]})
        assert bp == {"line": 4, "verified": True, "message": ""}
        client.call("run.start")
        stop = client.wait_for("stopped")
        assert (stop["reason"], stop["line"]) == ("breakpoint", 4)
        assert client.call("debug.evaluate", {"expression": "n"}) == "0"
