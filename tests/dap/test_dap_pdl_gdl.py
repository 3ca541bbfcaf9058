"""`motionvm debug` with PDL drive programs and GDL procedures: breakpoints in each,
their threads and frames, forcing an input the program reacts to, and output equal to
`motionvm run`."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.dap.dap_client import DapClient

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

PDL = """\
#long n;
#task/0;
n=0;
loop (3) do
  n=n+1;
  printl("n=%ld", n);
end;
halt;
"""


@pytest.fixture
def dap(tmp_path):
    client = DapClient(tmp_path)
    yield client
    client.close()


def _run(tmp_path, *argv) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "motionvm", "run", *argv], capture_output=True,
                          text=True, cwd=tmp_path, check=False)  # fmt: skip


def test_a_breakpoint_in_a_pdl_drive_program(dap, tmp_path):
    path = tmp_path / "d.pdl"
    path.write_text(PDL)
    dap.launch([str(path)])
    bps = dap.ok("setBreakpoints", {"source": {"path": str(path)}, "breakpoints": [{"line": 6}]})
    assert bps["breakpoints"][0]["verified"]
    dap.ok("configurationDone")
    stop = dap.wait_event("stopped")
    assert stop["reason"] == "breakpoint"
    names = [t["name"] for t in dap.ok("threads")["threads"]]
    assert names == ["drive 0 task 0"]
    frame = dap.ok("stackTrace", {"threadId": stop["threadId"]})["stackFrames"][0]
    assert frame["line"] == 6 and frame["source"]["path"] == str(path)
    assert dap.ok("evaluate", {"expression": "drive0.n", "frameId": frame["id"]})["result"] == "1"
    dap.ok("setBreakpoints", {"source": {"path": str(path)}, "breakpoints": []})
    dap.ok("continue", {"threadId": stop["threadId"]})
    assert dap.wait_event("exited")["exitCode"] == 0
    assert dap.stdout() == _run(tmp_path, "d.pdl").stdout == "n=1\nn=2\nn=3\n"


def test_a_pdl_program_s_globals_by_their_names(dap, tmp_path):
    path = tmp_path / "d.pdl"
    path.write_text(PDL)
    dap.launch([str(path)])
    bp = {"line": 6, "condition": "n == 2"}
    dap.ok("setBreakpoints", {"source": {"path": str(path)}, "breakpoints": [bp]})
    dap.ok("configurationDone")
    stop = dap.wait_event("stopped")
    frame = dap.ok("stackTrace", {"threadId": stop["threadId"]})["stackFrames"][0]
    assert dap.ok("evaluate", {"expression": "n * 10", "frameId": frame["id"]})["result"] == "20"
    scopes = dap.ok("scopes", {"frameId": frame["id"]})["scopes"]
    shown = {
        s["name"]: dap.ok("variables", {"variablesReference": s["variablesReference"]})
        for s in scopes[:2]
    }
    assert shown["Locals"]["variables"] == []  # not the generated code's memory views
    assert [(v["name"], v["value"]) for v in shown["Globals"]["variables"]] == [("n", "2")]


def test_a_breakpoint_in_a_gdl_procedure_and_going_back(dap, tmp_path):
    for name in ("02_gdl_packer.gdl", "02_gdl_packer.toml"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    gdl = tmp_path / "02_gdl_packer.gdl"
    dap.launch([str(gdl)], scenario=str(tmp_path / "02_gdl_packer.toml"))
    dap.ok("setBreakpoints", {"source": {"path": str(gdl)}, "breakpoints": [{"line": 74}]})
    dap.ok("configurationDone")
    stop = dap.wait_event("stopped")
    assert stop["reason"] == "breakpoint"
    frames = dap.ok("stackTrace", {"threadId": stop["threadId"]})["stackFrames"]
    assert (frames[0]["name"], frames[0]["line"]) == ("fan_control", 74)
    assert [t["name"] for t in dap.ok("threads")["threads"]] == ["procedure fan_control"]
    first = dap.ok("evaluate", {"expression": "VALUE OF cell_index"})["result"]
    # an element of an array object (its channel `photocell{3}.STATUS`), in any case
    assert dap.ok("evaluate", {"expression": "status of photocell{ 3 }"})["result"] == "1"
    assert dap.ok("evaluate", {"expression": "STATUS OF photocell{2}"})["result"] == "0"
    dap.ok("continue", {"threadId": stop["threadId"]})
    dap.wait_event("stopped")
    dap.ok("reverseContinue", {"threadId": stop["threadId"]})
    back = dap.wait_event("stopped")
    assert back["reason"] == "breakpoint" and back["description"] == stop["description"]
    assert dap.ok("evaluate", {"expression": "VALUE OF cell_index"})["result"] == first
    dap.ok("setBreakpoints", {"source": {"path": str(gdl)}, "breakpoints": []})
    dap.ok("continue", {"threadId": stop["threadId"]})
    assert dap.wait_event("exited")["exitCode"] == 0
    expected = _run(tmp_path, "02_gdl_packer.gdl", "--scenario", "02_gdl_packer.toml").stdout
    assert dap.stdout() == expected


def test_forcing_an_input_the_program_waits_for(dap, tmp_path):
    path = tmp_path / "w.hmpl"
    path.write_text(
        'void main()\n{\n    Till(HIMC_GPI(3));\n    Print("input 3 at %d ms", system_timeInMs);\n}\n'
    )
    dap.launch([str(path)], stop_on_entry=True)
    dap.ok("configurationDone")
    dap.wait_event("stopped")
    dap.ok("stepCycle", {"count": 20})
    dap.wait_event("stopped")
    scopes = dap.ok("scopes", {"frameId": 0})["scopes"]
    dap.ok("setVariable", {"variablesReference": scopes[-1]["variablesReference"], "name": "gpi3",
                           "value": "ON"})  # fmt: skip
    dap.ok("continue", {"threadId": 1})
    assert dap.wait_event("exited")["exitCode"] == 0
    assert dap.stdout() == "input 3 at 20 ms\n"


def test_globals_of_a_drive_of_the_machine_file_by_their_names(dap):
    counter = str(EXAMPLES / "03_pdl_drives.counter.pdl")
    dap.launch([str(EXAMPLES / "03_pdl_drives.hmpl")],
               machine=str(EXAMPLES / "03_pdl_drives.toml"))  # fmt: skip
    bp = {"line": 7, "condition": "n == 2"}  # printl("drive 2: count %ld", n);
    dap.ok("setBreakpoints", {"source": {"path": counter}, "breakpoints": [bp]})
    dap.ok("configurationDone")
    stop = dap.wait_event("stopped")
    frame = dap.ok("stackTrace", {"threadId": stop["threadId"]})["stackFrames"][0]
    assert frame["source"]["path"] == counter
    assert dap.ok("evaluate", {"expression": "n", "frameId": frame["id"]})["result"] == "2"
    assert dap.ok("evaluate", {"expression": "drive2.n", "frameId": frame["id"]})["result"] == "2"
    scopes = dap.ok("scopes", {"frameId": frame["id"]})["scopes"]
    globals_ = next(s for s in scopes if s["name"] == "Globals")["variablesReference"]
    dap.ok("setVariable", {"variablesReference": globals_, "name": "n", "value": "5"})
    assert dap.ok("evaluate", {"expression": "drive2.n"})["result"] == "5"
    dap.ok("setBreakpoints", {"source": {"path": counter}, "breakpoints": []})
    dap.ok("continue", {"threadId": stop["threadId"]})
    dap.wait_event("exited")
    assert "drive 2: count 6" in dap.stdout()
