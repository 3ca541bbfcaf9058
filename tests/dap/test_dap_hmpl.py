"""`motionvm debug` over real pipes with an HMPL program: breakpoints, stepping, one
controller cycle, inspection, evaluation, setting values, and going back in time."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.dap.dap_client import DapClient

PROGRAM = """\
int count = 0;
int level = 0;

int twice(int v)
{
    int r = v * 2;
    return r;
}

void main()
{
    int i;
    for (i = 0; i < 3; i++) {
        count = twice(count + 1);
        Sleep(10);
    }
    Print("count=%d level=%d", count, level);
}
"""


def _stop(dap: DapClient) -> dict:
    return dap.wait_event("stopped")


def _top(dap: DapClient, thread_id: int) -> dict:
    return dap.ok("stackTrace", {"threadId": thread_id})["stackFrames"][0]


def test_capabilities_and_entry(dap, tmp_path):
    caps = dap.launch([str(tmp_path / "main.hmpl")], stop_on_entry=True)
    for cap in ("supportsConfigurationDoneRequest", "supportsConditionalBreakpoints",
                "supportsHitConditionalBreakpoints", "supportsLogPoints", "supportsStepBack",
                "supportsSetVariable", "supportsEvaluateForHovers", "supportsDataBreakpoints",
                "supportsExceptionInfoRequest"):  # fmt: skip
        assert caps[cap] is True, cap
    assert {f["filter"] for f in caps["exceptionBreakpointFilters"]} == {"runtime", "axis"}
    dap.ok("configurationDone")
    assert _stop(dap)["reason"] == "entry"
    dap.ok("continue", {"threadId": 1})
    assert dap.wait_event("exited")["exitCode"] == 0
    dap.wait_event("terminated")
    assert dap.stdout() == "count=14 level=0\n"


def test_breakpoint_moves_to_a_statement_and_stops_there(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    bps = dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [{"line": 3}]})
    assert bps["breakpoints"][0]["verified"] and bps["breakpoints"][0]["line"] == 6
    dap.ok("configurationDone")
    stop = _stop(dap)
    assert stop["reason"] == "breakpoint" and stop["hitBreakpointIds"] == [
        bps["breakpoints"][0]["id"]
    ]
    threads = dap.ok("threads")["threads"]
    assert [t["name"] for t in threads] == ["task 0"]
    frames = dap.ok("stackTrace", {"threadId": stop["threadId"]})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [("twice", 6), ("main", 14)]
    scopes = dap.ok("scopes", {"frameId": frames[0]["id"]})["scopes"]
    assert [s["name"] for s in scopes] == ["Locals", "Globals", "Machine"]
    local = dap.ok("variables", {"variablesReference": scopes[0]["variablesReference"]})
    assert {v["name"]: v["value"] for v in local["variables"]}["v"] == "1"
    glob = dap.ok("variables", {"variablesReference": scopes[1]["variablesReference"]})
    assert {v["name"]: v["value"] for v in glob["variables"]}["count"] == "0"
    machine = dap.ok("variables", {"variablesReference": scopes[2]["variablesReference"]})
    assert [v["name"] for v in machine["variables"]] == ["axes", "io", "system"]
    value = dap.ok("evaluate", {"expression": "v * 10 + count", "frameId": frames[0]["id"]})
    assert value["result"] == "10"
    hover = dap.ok(
        "evaluate", {"expression": "axis0.pos_fb", "frameId": frames[0]["id"], "context": "hover"}
    )
    assert float(hover["result"]) == 0.0


def test_steps_over_in_and_out(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [{"line": 14}]})
    dap.ok("configurationDone")
    tid = _stop(dap)["threadId"]
    dap.ok("stepIn", {"threadId": tid})
    assert _stop(dap)["reason"] == "step"
    assert (_top(dap, tid)["name"], _top(dap, tid)["line"]) == ("twice", 6)
    dap.ok("stepOut", {"threadId": tid})
    _stop(dap)
    assert _top(dap, tid)["name"] == "main"
    dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": []})
    dap.ok("next", {"threadId": tid})
    _stop(dap)
    assert _top(dap, tid)["line"] == 13  # the for loop's step, after Sleep(10)


def test_conditions_hit_counts_and_logpoints(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [
        {"line": 15, "logMessage": "count is {count}"},
        {"line": 14, "condition": "count >= 2 && i == 1"},
        {"line": 6, "hitCondition": "3"},
    ]})  # fmt: skip
    dap.ok("configurationDone")
    stop = _stop(dap)
    frame = _top(dap, stop["threadId"])
    assert frame["line"] == 14
    assert dap.ok("evaluate", {"expression": "count", "frameId": frame["id"]})["result"] == "2"
    dap.ok("continue", {"threadId": stop["threadId"]})
    stop = _stop(dap)
    frame = _top(dap, stop["threadId"])
    assert (frame["name"], frame["line"]) == ("twice", 6)
    assert dap.ok("evaluate", {"expression": "v", "frameId": frame["id"]})["result"] == "7"
    assert "count is 2\ncount is 6\n" in dap.stdout()


def test_step_cycle_and_going_back_in_time(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path], stop_on_entry=True)
    dap.ok("configurationDone")
    _stop(dap)
    dap.ok("stepCycle", {"count": 1})
    stop = _stop(dap)
    assert "cycle 1" in stop["description"]
    assert dap.ok("evaluate", {"expression": "count"})["result"] == "2"
    dap.ok("goToTime", {"seconds": 0.025})
    stop = _stop(dap)
    assert stop["reason"] == "goto" and "cycle 25" in stop["description"]
    assert dap.ok("evaluate", {"expression": "count"})["result"] == "14"
    dap.ok("goToTime", {"seconds": 0.005})
    _stop(dap)
    assert dap.ok("evaluate", {"expression": "count"})["result"] == "2"
    changed = dap.ok("lastChange", {"expression": "count"})
    assert (
        changed["changed"] and changed["after"] == "2" and changed["time"] == pytest.approx(0.001)
    )
    dap.ok("setBreakpoints", {"source": {"path": path}, "breakpoints": [{"line": 14}]})
    dap.ok("reverseContinue", {"threadId": 1})
    stop = _stop(dap)
    assert stop["reason"] == "breakpoint"
    assert dap.ok("evaluate", {"expression": "count"})["result"] == "0"
    dap.ok("stepBack", {"threadId": stop["threadId"]})
    stop = _stop(dap)
    assert _top(dap, stop["threadId"])["line"] == 13


def test_set_variable_is_an_input_of_the_run_and_replays(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path], stop_on_entry=True)
    dap.ok("configurationDone")
    _stop(dap)
    dap.ok("stepCycle", {"count": 5})
    stop = _stop(dap)
    scopes = dap.ok("scopes", {"frameId": 0})["scopes"]
    machine = scopes[-1]["variablesReference"]
    dap.ok("setVariable", {"variablesReference": machine, "name": "level", "value": "7"})
    assert dap.ok("evaluate", {"expression": "level"})["result"] == "7"
    dap.ok("goToTime", {"seconds": 0.002})
    _stop(dap)
    assert dap.ok("evaluate", {"expression": "level"})["result"] == "0"
    dap.ok("goToTime", {"seconds": 0.010})
    _stop(dap)
    assert dap.ok("evaluate", {"expression": "level"})["result"] == "7"
    dap.ok("continue", {"threadId": stop["threadId"]})
    assert dap.wait_event("exited")["exitCode"] == 0
    assert dap.stdout().endswith("count=14 level=7\n")


def test_the_output_and_exit_code_are_those_of_motionvm_run(dap, tmp_path):
    (tmp_path / "bad.hmpl").write_text(
        'void main()\n{\n    int a[2];\n    int i = 5;\n    Print("before");\n    a[i] = 1;\n}\n'
    )
    path = str(tmp_path / "bad.hmpl")
    run = subprocess.run([sys.executable, "-m", "motionvm", "run", path], capture_output=True,
                         text=True, cwd=tmp_path, check=False)  # fmt: skip
    dap.launch([path])
    dap.ok("setExceptionBreakpoints", {"filters": ["runtime"]})
    dap.ok("configurationDone")
    stop = _stop(dap)
    assert stop["reason"] == "exception"
    info = dap.ok("exceptionInfo", {"threadId": stop["threadId"]})
    assert info["exceptionId"] == "runtime" and "runtime error in task 0" in info["description"]
    dap.ok("continue", {"threadId": stop["threadId"]})
    assert dap.wait_event("exited")["exitCode"] == run.returncode == 1
    assert dap.stdout() == run.stdout


def test_data_breakpoint_stops_after_the_cycle_of_the_change(dap, tmp_path):
    path = str(tmp_path / "main.hmpl")
    dap.launch([path])
    info = dap.ok("dataBreakpointInfo", {"name": "count"})
    dap.ok("setDataBreakpoints", {"breakpoints": [{"dataId": info["dataId"]}]})
    dap.ok("configurationDone")
    stop = _stop(dap)
    assert stop["reason"] == "data breakpoint" and "count changed from 0 to 2" in stop["text"]
    dap.ok("continue", {"threadId": stop["threadId"]})
    stop = _stop(dap)
    assert "from 2 to 6" in stop["text"] and "cycle 11" in stop["description"]


def test_a_compile_error_ends_the_launch_with_exit_2(dap, tmp_path):
    (tmp_path / "bad.hmpl").write_text("void main() { x = 1; }\n")
    dap.ok("initialize", {"adapterID": "motionvm"})
    response = dap.request("launch", {"program": [str(tmp_path / "bad.hmpl")]})
    assert not response["success"]
    assert dap.wait_event("exited")["exitCode"] == 2
    errors = [e["body"]["output"] for e in dap.events if e["event"] == "output"]
    assert any("bad.hmpl:1:15: error:" in line for line in errors), errors


def test_no_debug_runs_as_motionvm_run(dap, tmp_path):
    dap.launch([str(tmp_path / "main.hmpl")], noDebug=True)
    dap.ok("configurationDone")
    assert dap.wait_event("exited")["exitCode"] == 0
    assert dap.stdout() == "count=14 level=0\n"
