"""Everything a user's file causes is one `FILE:LINE:COL: severity: message` line (what an
editor's gcc problem matcher picks up): runtime faults of every language, every problem
of a machine file or a scenario at once; command-line mistakes stay `motionvm: error:`."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

from motionvm.api import SessionError, Simulation
from motionvm.cli import main

GCC_LINE = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+):(?P<col>\d+): (?P<severity>error|warning): ")
HMPL_FAULT = re.compile(r"^[^:]+:\d+:\d+: runtime error in task \d+ at t=\d+\.\d{3} s: ")
PDL_FAULT = re.compile(r"^[^:]+:\d+:\d+: runtime error in drive \d+ task \d+ at t=\d+\.\d{6} s: ")
PDL_STANDALONE_FAULT = re.compile(r"^[^:]+:\d+:\d+: runtime error in task \d+ at t=\d+\.\d{6} s: ")
GDL_FAULT = re.compile(r"^[^:]+:\d+:\d+: runtime error in procedure \w+ at t=\d+\.\d{3} s: ")

GDL_APP = """MODULE m;
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT go [ BOARD$NAME = io, CHANNEL = 1 ];
  INTEGER$VARIABLE v [ ARRAY$SIZE = 3 ];
  INTEGER$VARIABLE i [ INITIAL$VALUE = 7 ];
  PROCEDURE bump;
  DECLARE { STATUS OF go };
  BEGIN
    VALUE OF v{VALUE OF i} = 1;
  END$PROCEDURE;
END$MODULE;
"""


def cli(cwd: Path, *argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(cwd), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


def test_an_hmpl_fault_names_place_task_and_time(tmp_path, monkeypatch):
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(
        tmp_path, "t.hmpl", "void main() {\n    int z = 0;\n    Sleep(1234);\n    z = 7 / z;\n}\n"
    )
    code, _out, err = cli(tmp_path, "run", "t.hmpl")
    assert code == 1
    (line,) = err.splitlines()
    assert HMPL_FAULT.match(line), line
    assert line == "t.hmpl:4:5: runtime error in task 0 at t=1.234 s: integer division by zero"


def test_a_pdl_drive_fault_names_place_drive_task_and_phase_time(tmp_path, monkeypatch):
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(tmp_path, "bad.pdl", "#long a, z;\n#task/0;\nsleep 2;\n   a=a/z;\nhalt;\n")
    write(tmp_path, "m.toml", 'axes = 2\n[[axis]]\n[[axis]]\npdl = "bad.pdl"\n')
    code, _out, err = cli(tmp_path, "run", "--machine", "m.toml")
    assert code == 1
    (line,) = err.splitlines()
    assert PDL_FAULT.match(line), line
    assert line.endswith(
        "bad.pdl:4:4: runtime error in drive 1 task 0 at t=0.002000 s: division by zero"
    )
    # the same program alone on the default machine's drive
    code, _out, err = cli(tmp_path, "run", "bad.pdl")
    assert code == 1
    (line,) = err.splitlines()
    assert PDL_STANDALONE_FAULT.match(line), line
    assert line.startswith("bad.pdl:4:4: runtime error in task 0 at t=0.002")


def test_a_gdl_fault_names_place_procedure_and_time(tmp_path):
    write(tmp_path, "app.gdl", GDL_APP)
    write(tmp_path, "s.toml", '[[event]]\nat = 0.25\nset = "STATUS OF go"\nvalue = "ON"\n')
    code, _out, err = cli(tmp_path, "run", "app.gdl", "--scenario", "s.toml")
    assert code == 1
    (line,) = err.splitlines()
    assert GDL_FAULT.match(line), line
    assert line == (
        "app.gdl:9:5: runtime error in procedure bump at t=0.250 s: "
        "index 7 of v is outside 1..3 (ARRAY$SIZE)"
    )


def test_every_problem_of_a_machine_file_in_one_run(tmp_path):
    write(tmp_path, "a.hmpl", "void main() { }\n")
    write(
        tmp_path,
        "m.toml",
        "[controller]\ntask_slice = 0\n\n[[axis]]\nmax_vel = -1\n"
        '  drive = { mechanics = { model = "warp" } }\n',
    )
    code, out, err = cli(tmp_path, "run", "--machine", "m.toml", "a.hmpl")
    assert (code, out) == (3, "")
    lines = err.splitlines()
    assert all(GCC_LINE.match(line) for line in lines), err
    assert [line.split(" error: ")[0] for line in lines] == [
        "m.toml:2:1:",
        "m.toml:5:1:",
        "m.toml:6:27:",
    ]
    assert "task_slice = 0" in lines[0]
    assert "[[axis]] 0: max_vel = -1" in lines[1]
    assert "[[axis]] 0: mechanics: model = 'warp'" in lines[2]


def test_the_api_gets_every_machine_file_problem(tmp_path):
    prog = write(tmp_path, "a.hmpl", "void main() { }\n")
    m = write(
        tmp_path,
        "m.toml",
        "axes = 2\n[[axis]]\nspeed = 3\n[[axis]]\nsw_left = 5.0\nsw_right = 4.0\n",
    )
    with pytest.raises(SessionError) as info:
        Simulation.from_files([prog], machine=str(m))
    assert info.value.located
    assert [msg.split(": error: ")[0] for msg in info.value.messages] == [f"{m}:3:1", f"{m}:6:1"]


def test_an_unreadable_machine_file_is_a_command_line_error(tmp_path):
    write(tmp_path, "a.hmpl", "void main() { }\n")
    code, _out, err = cli(tmp_path, "run", "--machine", "gone.toml", "a.hmpl")
    assert code == 3
    assert err.startswith("motionvm: error: cannot read machine file gone.toml: ")


def test_every_bad_event_of_a_scenario_in_one_run(tmp_path):
    write(tmp_path, "app.gdl", GDL_APP)
    write(
        tmp_path,
        "s.toml",
        '[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = "ON"\n\n'
        '[[event]]\nat = 0.2\nset = "STATUS OF gone"\nvalue = "ON"\n\n'
        '[[event]]\nat = -1\nset = "STATUS OF go"\nvalue = "OFF"\n',
    )
    code, out, err = cli(tmp_path, "run", "app.gdl", "--scenario", "s.toml")
    assert (code, out) == (3, "")
    lines = err.splitlines()
    assert all(GCC_LINE.match(line) for line in lines), err
    assert lines == [
        "s.toml:8:1: error: event 2: unknown object 'gone' (did you mean 'go'?)",
        "s.toml:12:1: error: event 3: 'at' must be a number of seconds >= 0, not -1",
    ]


def test_a_force_text_stays_a_command_line_error(tmp_path):
    write(tmp_path, "app.gdl", GDL_APP)
    code, _out, err = cli(tmp_path, "run", "app.gdl", "--force", "STATUS OF gone = ON")
    assert code == 3
    assert (
        err
        == "motionvm: error: --force 'STATUS OF gone = ON': unknown object 'gone' (did you mean 'go'?)\n"
    )


def test_a_machine_file_that_is_not_utf8_is_located(tmp_path):
    write(tmp_path, "a.hmpl", "void main() { }\n")
    (tmp_path / "m.toml").write_bytes(b"axes = 1\n# caf\xe9\n")
    code, _out, err = cli(tmp_path, "run", "--machine", "m.toml", "a.hmpl")
    assert code == 3
    assert err == "m.toml:2:6: error: invalid TOML: the file is not UTF-8 text\n"


def test_an_injection_that_never_applied_is_a_located_warning(tmp_path):
    write(tmp_path, "app.gdl", GDL_APP)
    write(
        tmp_path,
        "s.toml",
        '\n[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = "ON"\nduring = "bump"\nline = 99\n',
    )
    code, _out, err = cli(tmp_path, "run", "app.gdl", "--scenario", "s.toml")
    assert code == 0
    assert err == "s.toml:2:1: warning: scenario event 1 (during bump, line 99) was never applied\n"
