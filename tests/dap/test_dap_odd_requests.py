"""`motionvm debug` over real pipes given odd but legal request sequences: every one gets
a response (an error with a clear message where it cannot be done) and the adapter goes on."""

from __future__ import annotations

from tests.dap.dap_client import DapClient


def _error(dap: DapClient, command: str, arguments: dict | None = None) -> str:
    response = dap.request(command, arguments)
    assert not response["success"], response
    return response["message"]


def _paused_in_twice(dap: DapClient, tmp_path) -> tuple[int, int]:
    """Launched and stopped at `int r = v * 2;`: (thread id, frame id)."""
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [{"line": 6}]})
    dap.ok("configurationDone")
    tid = dap.wait_event("stopped")["threadId"]
    frame = dap.ok("stackTrace", {"threadId": tid})["stackFrames"][0]
    return tid, frame["id"]


def test_malformed_arguments_get_an_error_and_the_adapter_goes_on(dap, tmp_path):
    assert _error(dap, "configurationDone") == "no program was launched"  # before launch
    message = _error(dap, "launch", {"program": "main.hmpl", "cwd": str(tmp_path / "nowhere")})
    assert message == f"launch: cwd '{tmp_path / 'nowhere'}' is not a folder"
    dap.launch([str(tmp_path / "main.hmpl")])
    assert "setBreakpoints" in _error(dap, "setBreakpoints", {"source": "main.hmpl"})
    assert _error(dap, "evaluate", {"expression": "nosuch"}) == "unknown name 'nosuch'"
    dap.ok("configurationDone")
    assert dap.wait_event("exited")["exitCode"] == 0


def test_bad_conditions_and_hit_conditions_are_not_verified(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    bps = dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [
        {"line": 6, "hitCondition": "% 0"},
        {"line": 6, "hitCondition": "abc"},
        {"line": 6, "condition": "v >"},
        {"line": 14, "hitCondition": ">= 2"},
    ]})["breakpoints"]  # fmt: skip
    assert [b["verified"] for b in bps] == [False, False, False, True]
    assert "% needs a number of 1 or more" in bps[0]["message"]
    assert "'abc' is not N" in bps[1]["message"]
    assert bps[2]["message"] == "'v >' is not an expression"
    dap.ok("configurationDone")
    stop = dap.wait_event("stopped")  # the second pass over line 14; no internal error
    assert stop["reason"] == "breakpoint" and stop["hitBreakpointIds"] == [bps[3]["id"]]
    assert not [e for e in dap.events if "internal error" in str(e)]


def test_array_indices_are_checked_as_in_c(dap, tmp_path):
    path = tmp_path / "cells.hmpl"
    path.write_text("int cells[3] = {4, 5, 6};\nvoid main()\n{\n    Sleep(10);\n}\n")
    dap.launch([str(path)])
    dap.ok("setBreakpoints", {"source": {"path": str(path)}, "breakpoints": [{"line": 4}]})
    dap.ok("configurationDone")
    dap.wait_event("stopped")
    for expression, message in [
        ("cells[-1]", "index -1 is out of range for an array of 3"),
        ("cells[3]", "'cells[3]': index 3 is out of range for an array of 3"),
        ("cells[1][0]", "5 is not an array"),
    ]:
        assert _error(dap, "evaluate", {"expression": expression}) == message
    assert dap.ok("evaluate", {"expression": "cells[1 + 1]"})["result"] == "6"


def test_set_variable_keeps_an_integer_local_an_integer(dap, tmp_path):
    tid, fid = _paused_in_twice(dap, tmp_path)
    scopes = dap.ok("scopes", {"frameId": fid})["scopes"]
    ref = scopes[0]["variablesReference"]
    message = _error(dap, "setVariable", {"variablesReference": ref, "name": "v", "value": "2.5"})
    assert message == "'v' is an integer variable: it cannot hold 2.5"
    assert dap.ok("setVariable", {"variablesReference": ref, "name": "v", "value": "3.0"}) == {
        "value": "3"
    }
    dap.ok("setBreakpoints", {"source": {"path": str(tmp_path / "main.hmpl")}, "breakpoints": []})
    dap.ok("continue", {"threadId": tid})
    assert dap.wait_event("exited")["exitCode"] == 0  # no internal error of the task
    assert dap.stdout() == "count=30 level=0\n"


def test_the_end_reached_again_after_going_back_is_a_stop(dap, tmp_path):
    dap.launch([str(tmp_path / "main.hmpl")])
    dap.ok("configurationDone")
    assert dap.wait_event("exited")["exitCode"] == 0
    dap.ok("goToTime", {"seconds": 0.005})
    tid = dap.wait_event("stopped")["threadId"]
    dap.ok("continue", {"threadId": tid})
    stop = dap.wait_event("stopped")
    assert stop["reason"] == "exited" and "cycle 31" in stop["description"]


def test_disconnect_after_terminate_is_answered(dap, tmp_path):
    tid, _fid = _paused_in_twice(dap, tmp_path)
    dap.ok("terminate")
    dap.wait_event("terminated")
    assert _error(dap, "continue", {"threadId": tid}) == "the debug session was terminated"
    dap.ok("disconnect")


def test_a_body_that_is_not_json_is_skipped(dap, tmp_path):
    for body in (b"{not json", b"[1, 2]"):
        dap.proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    dap.proc.stdin.flush()
    dap.launch([str(tmp_path / "main.hmpl")])
    dap.ok("configurationDone")
    assert dap.wait_event("exited")["exitCode"] == 0
    errors = [e["body"]["output"] for e in dap.events if e["event"] == "output"]
    assert errors[:2] == [
        "motionvm debug: a message that is not JSON: Expecting property name enclosed in "
        "double quotes: line 1 column 2 (char 1) (skipped)\n",
        "motionvm debug: a message that is not a JSON object (skipped)\n",
    ]


def test_stack_trace_pages_by_start_frame_and_levels(dap, tmp_path):
    tid, _fid = _paused_in_twice(dap, tmp_path)
    whole = dap.ok("stackTrace", {"threadId": tid})
    assert [f["name"] for f in whole["stackFrames"]] == ["twice", "main"]
    top = dap.ok("stackTrace", {"threadId": tid, "startFrame": 0, "levels": 1})
    rest = dap.ok("stackTrace", {"threadId": tid, "startFrame": 1, "levels": 20})
    assert [f["name"] for f in top["stackFrames"]] == ["twice"]
    assert [f["name"] for f in rest["stackFrames"]] == ["main"]
    assert top["totalFrames"] == rest["totalFrames"] == 2


def test_a_pause_while_paused_does_not_stop_the_next_run(dap, tmp_path):
    dap.launch([str(tmp_path / "main.hmpl")], stop_on_entry=True)
    dap.ok("configurationDone")
    tid = dap.wait_event("stopped")["threadId"]
    dap.ok("pause", {"threadId": tid})
    dap.ok("continue", {"threadId": tid})
    assert dap.wait_event("exited")["exitCode"] == 0
    assert [e["body"]["reason"] for e in dap.events if e["event"] == "stopped"] == ["entry"]


def test_a_second_launch_and_values_of_the_wrong_kind_are_refused(dap, tmp_path):
    dap.launch([str(tmp_path / "main.hmpl")], stop_on_entry=True)
    message = _error(dap, "launch", {"program": str(tmp_path / "main.hmpl")})
    assert message == "launch: a program was launched already (disconnect first)"
    message = _error(dap, "setExceptionBreakpoints", {"filters": "runtime"})
    assert message == "setExceptionBreakpoints: 'filters' must be a list"
    dap.ok("configurationDone")
    tid = dap.wait_event("stopped")["threadId"]
    assert (
        _error(dap, "goToTime", {"seconds": float("inf")})
        == "goToTime: seconds must be >= 0, got inf"
    )
    dap.ok("continue", {"threadId": tid})
    assert dap.wait_event("exited")["exitCode"] == 0
