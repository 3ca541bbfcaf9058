"""PDL programs on the drives of a machine file (`pdl = ...` in [[axis]]; lang/pdl/machine_drives.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.sim.machine import MachineFileError, load_machine

MOVER = """\
#long p;
#task/0;
X_trg=20000;
till(~x_run);
p=x_ref_pos;
printl("mover at %ld", p);
halt;
"""

COUNTER = """\
#long n;
_count:
loop(3) do
  sleep 10;
  n++;
  printl("count %ld", n);
end;
ret;
"""

HMPL = """\
void main() {
    Print("refused 0x%x", MoveAbs(1, 1.0));
    Sleep(25);
    Print("last error 0x%x", GetAxisLastErr(1));
}
"""

MACHINE = """\
axes = 3

[[axis]]

[[axis]]
max_vel = 100.0
max_acc = 10000.0
pdl = "mover.pdl"

[[axis]]
pdl = "counter.pdl"
pdl_start = ["_count"]
"""


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


@pytest.fixture
def machine(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(tmp_path, "mover.pdl", MOVER)
    write(tmp_path, "counter.pdl", COUNTER)
    write(tmp_path, "main.hmpl", HMPL)
    return write(tmp_path, "m.toml", MACHINE)


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["run", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_two_drives_and_an_hmpl_task_exact_stdout(machine: Path, capsys) -> None:
    hmpl = str(machine.parent / "main.hmpl")
    code, out, err = run(capsys, "--machine", str(machine), hmpl, "--stamp")
    assert (code, err) == (0, "")
    # 2 mm at 100 mm/s with 10000 mm/s^2: 10 ms ramp up, 10 ms cruise, 10 ms down;
    # drive 2 keeps the timing of `motionvm run counter.pdl --start _count`.
    assert out == (
        "[t=0.000000][task 0] refused 0x830100f0\n"
        "[t=0.010133][drive 2 task 0] count 1\n"
        "[t=0.020333][drive 2 task 0] count 2\n"
        "[t=0.025000][task 0] last error 0x830100f0\n"
        "[t=0.030133][drive 1 task 0] mover at 20000\n"
        "[t=0.030533][drive 2 task 0] count 3\n"
    )


def test_runs_are_deterministic(machine: Path, capsys) -> None:
    hmpl = str(machine.parent / "main.hmpl")
    first = run(capsys, "--machine", str(machine), hmpl, "--stamp")
    second = run(capsys, "--machine", str(machine), hmpl, "--stamp")
    assert first == second and first[0] == 0


def test_the_drives_alone_without_an_hmpl_file(machine: Path, capsys) -> None:
    code, out, err = run(capsys, "--machine", str(machine))
    assert (code, err) == (0, "")
    assert out == "count 1\ncount 2\nmover at 20000\ncount 3\n"


def test_until_stops_a_drive_that_never_ends(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(tmp_path, "tick.pdl", '#task/1;\nl: sleep 100; printl("t"); goto l;\n')
    m = write(tmp_path, "m.toml", 'axes = 1\n[[axis]]\npdl = "tick.pdl"\n')
    code, out, _ = run(capsys, "--machine", str(m), "--until", "0.35", "--stamp")
    assert code == 0
    assert out == (
        "[t=0.100000][drive 0 task 1] t\n"
        "[t=0.200133][drive 0 task 1] t\n"
        "[t=0.300267][drive 0 task 1] t\n"
    )


def test_a_sleeping_drive_keeps_the_run_going(tmp_path: Path, capsys, monkeypatch) -> None:
    """The HMPL task and the drive sleep long and the controller jumps over the sleeps;
    the drive's phases keep their timing (the stamps are those of
    `motionvm run slow.pdl --stamp`)."""
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(
        tmp_path,
        "slow.pdl",
        '#task/0;\nsleep 500;\nprintl("a");\nsleep 700;\nprintl("b");\nhalt;\n',
    )
    write(tmp_path, "main.hmpl", 'void main() { Sleep(1000); Print("hmpl"); }\n')
    m = write(tmp_path, "m.toml", '[controller]\ncycle_time_ms = 2.0\n[[axis]]\npdl = "slow.pdl"\n')
    code, out, _ = run(capsys, "--machine", str(m), str(tmp_path / "main.hmpl"), "--stamp")
    assert code == 0
    assert out == (
        "[t=0.500000][drive 0 task 0] a\n[t=1.000000][task 0] hmpl\n[t=1.200067][drive 0 task 0] b\n"
    )


def test_a_drive_fault_names_the_drive_and_exits_1(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    prog = write(tmp_path, "bad.pdl", "#long a, z;\n#task/0;\na=a/z;\nhalt;\n")
    m = write(tmp_path, "m.toml", 'axes = 2\n[[axis]]\n[[axis]]\npdl = "bad.pdl"\n')
    code, out, err = run(capsys, "--machine", str(m))
    assert (code, out) == (1, "")
    assert err == f"{prog}:3:1: runtime error in drive 1 task 0 at t=0.000000 s: division by zero\n"


def test_compile_errors_in_a_drive_program_exit_2(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    prog = write(tmp_path, "bad.pdl", "#long a;\n#task/0;\na=b;\n")
    write(tmp_path, "main.hmpl", 'void main() { Print("never"); }\n')
    m = write(tmp_path, "m.toml", '[[axis]]\npdl = "bad.pdl"\n')
    code, out, err = run(capsys, "--machine", str(m), str(tmp_path / "main.hmpl"))
    assert (code, out) == (2, "")
    first = err.splitlines()[0]
    assert first.startswith(f"{prog}:3:") and ": error: " in first
    assert "Traceback" not in err


@pytest.mark.parametrize(
    ("axis_lines", "line", "needle"),
    [
        ("pdl = 3", 3, "pdl = 3: must be the name of a .pdl file"),
        ('pdl = "nothere.pdl"', 3, "pdl = 'nothere.pdl': no such file"),
        ('pdl = "prog.txt"', 3, "must be the name of a .pdl file"),
        ('pdl_start = ["_go"]', 3, "pdl_start needs a PDL program"),
        ('pdl = "ok.pdl"\npdl_start = "_go"', 4, "pdl_start = '_go': must be a list of labels"),
        ('pdl = "ok.pdl"\npdl_start = ["go"]', 4, "can only start labels beginning with '_'"),
    ],
)
def test_bad_pdl_keys(tmp_path: Path, axis_lines: str, line: int, needle: str) -> None:
    write(tmp_path, "ok.pdl", "_go:\nret;\n")
    m = write(tmp_path, "m.toml", f"axes = 1\n[[axis]]\n{axis_lines}\n")
    with pytest.raises(MachineFileError) as info:
        load_machine(m)
    msg = str(info.value)
    assert msg.startswith(f"{m}:{line}:1: error: [[axis]] 0: "), msg
    assert needle in msg


def test_a_machine_file_error_exits_3(tmp_path: Path, capsys) -> None:
    m = write(tmp_path, "m.toml", '[[axis]]\npdl = "missing.pdl"\n')
    code, out, err = run(capsys, "--machine", str(m))
    assert (code, out) == (3, "")
    assert err.startswith(f"{m}:2:1: error: [[axis]] 0: pdl = 'missing.pdl': no such file")


def test_an_unknown_start_label_exits_3(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    write(tmp_path, "ok.pdl", "_go:\nret;\n")
    m = write(tmp_path, "m.toml", '[[axis]]\npdl = "ok.pdl"\npdl_start = ["_go", "_gone"]\n')
    code, out, err = run(capsys, "--machine", str(m))
    assert (code, out) == (3, "")
    assert err == f"{m}:3:1: error: [[axis]] 0: pdl_start: ok.pdl has no label '_gone'\n"


def test_machine_keeps_the_pdl_specs(machine: Path) -> None:
    cfg = load_machine(machine)
    assert [(s.axis, s.path.name, s.starts) for s in cfg.pdl_drives] == [
        (1, "mover.pdl", ()),
        (2, "counter.pdl", ("_count",)),
    ]
    assert len(cfg.axes) == 3  # the pdl keys do not reach the axis configuration


def test_a_machine_without_programs_and_no_files_is_a_usage_error(tmp_path: Path, capsys) -> None:
    m = write(tmp_path, "m.toml", "axes = 1\n")
    code, _out, err = run(capsys, "--machine", str(m))
    assert code == 3 and "no input files" in err
