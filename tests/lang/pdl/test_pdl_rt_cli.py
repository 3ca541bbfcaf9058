"""`motionvm run|check x.pdl` (one PDL program on a drive of its own): output and exit codes."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

from motionvm.cli import main
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source import DiagnosticSink

RUN = Path(__file__).parents[2] / "programs" / "pdl" / "run"
MANUAL = Path(__file__).parents[2] / "programs" / "pdl" / "manual"


def cli(*argv) -> tuple[int, str, str]:
    """`motionvm ARGV...` in this process: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def run(tmp_path: Path, text: str, start=None, until=5.0, *extra: str) -> tuple[int, str, str]:
    path = tmp_path / "prog.pdl"
    path.write_text(text)
    labels = [start] if isinstance(start, str) else list(start or [])
    argv = ["run", str(path), *extra]
    for label in labels:
        argv += ["--start", label]
    if until is not None:
        argv += ["--until", str(until)]
    return cli(*argv)


def test_run_prints_one_line_per_message(tmp_path: Path) -> None:
    code, out, err = run(
        tmp_path, '#long a;\n#task/0;\na=41;\na++;\nprintl(" a=%ld ", a);\nhalt;\n'
    )
    assert (code, out, err) == (0, " a=42 \n", "")


def test_run_starts_host_labels_in_order(tmp_path: Path) -> None:
    text = '_x:\nprintl("x");\nret;\n_y:\nprintl("y");\nret;\n'
    assert run(tmp_path, text, ["_y", "_x"])[:2] == (0, "y\nx\n")
    assert run(tmp_path, text, "_x")[:2] == (0, "x\n")
    code, out, _err = run(tmp_path, text, "top")
    assert (code, out) == (0, "x\n")


def test_run_reports_a_fault_and_exits_1(tmp_path: Path) -> None:
    code, out, err = run(
        tmp_path, '#long a, z;\n#task/0;\na=a/z;\nhalt;\n#task/1;\nsleep 1;\nprintl("on");\nhalt;\n'
    )
    assert code == 1
    assert out == "on\n"
    assert err == (
        f"{tmp_path / 'prog.pdl'}:3:1: runtime error in task 0 at t=0.000000 s: division by zero\n"
    )


def test_run_stops_at_until(tmp_path: Path) -> None:
    code, out, _ = run(tmp_path, '#task/0;\nl: sleep 100; printl("t"); goto l;\n', until=0.35)
    assert (code, out) == (0, "t\nt\nt\n")


def test_compile_errors_are_sorted_and_exit_2(tmp_path: Path) -> None:
    code, out, err = run(tmp_path, "#long a;\nb=1;\na=c;\n")
    assert code == 2 and out == ""
    heads = [line for line in err.splitlines() if ": error: " in line]
    assert [h.split(":")[1] for h in heads] == ["2", "3"]


def test_bad_command_lines_exit_3(tmp_path: Path) -> None:
    assert run(tmp_path, "_a:\nret;\n", "_nope")[0] == 3
    assert run(tmp_path, "a:\nret;\n", "a")[0] == 3
    assert cli("run", tmp_path / "missing.pdl")[0] == 3
    assert cli("run")[0] == 3
    assert cli("check", tmp_path / "x.txt")[0] == 3


def test_no_task_gives_a_note(tmp_path: Path) -> None:
    code, out, err = run(tmp_path, "#long a;\na=1;\n")
    assert code == 0 and out == "" and "no task runs" in err


def test_check_accepts_every_manual_example() -> None:
    paths = [str(p) for p in sorted(MANUAL.rglob("*.pdl"))]
    code, _out, err = cli("check", *paths)
    assert code == 0, err


def test_generated_python_keeps_the_users_lines() -> None:
    path = RUN / "w07_procedures.pdl"
    program = compile_pdl(str(path), sink=DiagnosticSink())
    assert program is not None
    assert program.code.co_filename == str(path)
    src = program.python_source()
    assert "def _p_add3(T, b, a0, a1, a2, a3):" in src and "def _main(T, pc):" in src


def test_stamp_prefixes_time_and_task(tmp_path: Path) -> None:
    text = '#task/1;\nsleep 500;\nprintl("hi");\nhalt;\n'
    code, out, _err = run(tmp_path, text, None, 2.0, "--stamp")
    assert (code, out) == (0, "[t=0.500000][task 1] hi\n")
