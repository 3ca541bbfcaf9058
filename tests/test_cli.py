"""The command line contract: subcommands, exit codes, diagnostics, options."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "motionvm", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
    )


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


def test_run_prints_messages_and_exits_0(tmp_path):
    write(tmp_path, "a.hmpl", 'void main() { Print("hello %d", 42); }\n')
    r = run(["run", "a.hmpl"], tmp_path)
    assert (r.returncode, r.stdout, r.stderr) == (0, "hello 42\n", "")


def test_stamp_prefixes_time_and_task(tmp_path):
    write(tmp_path, "a.hmpl", 'void main() { Sleep(5); Print("x"); }\n')
    r = run(["run", "--stamp", "a.hmpl"], tmp_path)
    assert r.stdout == "[t=0.005000][task 0] x\n"


def test_compile_error_format_and_exit_2(tmp_path):
    write(tmp_path, "a.hmpl", 'void main() {\n    int x = 1\n    Print("%d", x);\n}\n')
    r = run(["run", "a.hmpl"], tmp_path)
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.splitlines()
    assert lines[0] == "a.hmpl:2:14: error: expected ';' after declaration"
    assert lines[1] == "    int x = 1"
    assert lines[2] == " " * 13 + "^"


def test_check_reports_up_to_20_errors_per_file(tmp_path):
    body = "".join(f"    undefined_{i} = 1;\n" for i in range(30))
    write(tmp_path, "a.hmpl", "void main() {\n" + body + "}\n")
    r = run(["check", "a.hmpl"], tmp_path)
    assert r.returncode == 2
    assert sum(": error: " in line for line in r.stderr.splitlines()) == 20
    assert "Traceback" not in r.stderr


def test_runtime_error_exit_1_other_tasks_go_on(tmp_path):
    write(
        tmp_path,
        "t0.hmpl",
        'void main() {\n    StartTask(1);\n    int z = 0;\n    Sleep(3);\n    Print("%d", 5 % z);\n}\n',
    )
    write(tmp_path, "t1.hmpl", 'void main() { Sleep(10); Print("task 1 still runs"); }\n')
    r = run(["run", "t0.hmpl", "t1.hmpl"], tmp_path)
    assert r.returncode == 1
    assert r.stderr.strip() == (
        "t0.hmpl:5:5: runtime error in task 0 at t=0.003 s: integer modulo by zero"
    )
    assert r.stdout == "task 1 still runs\n"


def test_task_option_places_files(tmp_path):
    write(tmp_path, "main.hmpl", "void main() { StartTask(5); }\n")
    write(tmp_path, "five.hmpl", 'void main() { Print("task %d", _TASKID_); }\n')
    r = run(["run", "--task", "5=five.hmpl", "main.hmpl"], tmp_path)
    assert (r.returncode, r.stdout) == (0, "task 5\n")


def test_only_task_0_and_autorun_start(tmp_path):
    write(tmp_path, "t0.hmpl", 'void main() { Print("t0"); }\n')
    write(tmp_path, "t1.hmpl", 'void main() { Print("t1 must not run"); }\n')
    write(tmp_path, "t2.hmpl", '_AUTORUN_ void main() { Print("t2 autorun"); }\n')
    r = run(["run", "t0.hmpl", "t1.hmpl", "t2.hmpl"], tmp_path)
    assert r.stdout.splitlines() == ["t0", "t2 autorun"]


def test_until_stops_an_endless_program(tmp_path):
    write(
        tmp_path,
        "a.hmpl",
        'void main() { for (;;) { Sleep(100); Print("%d", system_timeInMs); } }\n',
    )
    r = run(["run", "--until", "0.35", "a.hmpl"], tmp_path)
    assert (r.returncode, r.stdout.split()) == (0, ["100", "200", "300"])


def test_bad_command_lines_exit_3(tmp_path):
    assert run(["run", "missing.hmpl"], tmp_path).returncode == 3
    assert run(["run", "--task", "x=y.hmpl"], tmp_path).returncode == 3
    write(tmp_path, "a.txt", "")
    assert run(["run", "a.txt"], tmp_path).returncode == 3
    assert run(["frobnicate"], tmp_path).returncode == 3


def test_bad_machine_file_names_key_and_line(tmp_path):
    write(tmp_path, "a.hmpl", "void main() { }\n")
    write(tmp_path, "m.toml", "[controller]\ncycle_time_ms = 1.0\ntask_slice = -5\n")
    r = run(["run", "--machine", "m.toml", "a.hmpl"], tmp_path)
    assert r.returncode == 3
    assert r.stderr.startswith("m.toml:3:1: error: ") and "task_slice" in r.stderr


def test_compile_emit_python(tmp_path):
    write(tmp_path, "a.hmpl", "int g = 1;\nvoid main() { g = g + 1; }\n")
    r = run(["compile", "--emit-python", "a.hmpl"], tmp_path)
    assert r.returncode == 0
    assert "def g_main():" in r.stdout and "global g_g" in r.stdout


def test_builtins_json_lists_every_builtin(tmp_path):
    r = run(["builtins", "--json"], tmp_path)
    rows = json.loads(r.stdout)
    assert len(rows) == 324
    assert set(rows[0]) >= {"name", "prototype", "implemented"}
    by_name = {row["name"]: row for row in rows}
    assert by_name["Print"]["implemented"] and by_name["StringCopy"]["implemented"]


def test_dump_stages(tmp_path):
    write(tmp_path, "a.hmpl", "void main() { }\n")
    for stage, needle in (("tokens", "keyword\tvoid"), ("ast", "FuncDef"), ("py", "def g_main")):
        r = run(["dump", "--stage", stage, "a.hmpl"], tmp_path)
        assert r.returncode == 0 and needle in r.stdout, (stage, r.stdout[:200])


WARNS = 'void main() {\n    int n = 1;\n    if (n = 2) Print("%d", n);\n}\n'


def test_check_prints_warnings_and_exits_0(tmp_path):
    write(tmp_path, "a.hmpl", WARNS)
    r = run(["check", "a.hmpl"], tmp_path)
    assert r.returncode == 0
    assert r.stderr.splitlines() == [
        "a.hmpl:3:11: warning: suggest parentheses around assignment used as truth value",
        '    if (n = 2) Print("%d", n);',
        " " * 10 + "^",
    ]


def test_werror_makes_warnings_fail_check_run_and_compile_with_exit_2(tmp_path):
    write(tmp_path, "a.hmpl", WARNS)
    for cmd in ("check", "run", "compile"):
        r = run([cmd, "--Werror", "a.hmpl"], tmp_path)
        assert (r.returncode, r.stdout) == (2, ""), (cmd, r.stderr)
        assert r.stderr.startswith("a.hmpl:3:11: warning: suggest parentheses"), cmd
        assert (
            r.stderr.splitlines()[-1] == "motionvm: all warnings being treated as errors (--Werror)"
        )


def test_werror_passes_a_program_without_warnings(tmp_path):
    write(tmp_path, "a.hmpl", 'void main() { Print("%d", 42); }\n')
    assert run(["check", "--Werror", "a.hmpl"], tmp_path).returncode == 0
    r = run(["run", "--Werror", "a.hmpl"], tmp_path)
    assert (r.returncode, r.stdout, r.stderr) == (0, "42\n", "")


def test_a_run_with_warnings_runs_and_reports_them(tmp_path):
    write(tmp_path, "a.hmpl", 'void main() {\n    int idle;\n    Print("%d", 1.5);\n}\n')
    r = run(["run", "a.hmpl"], tmp_path)
    assert (r.returncode, r.stdout) == (0, "1\n")
    heads = [line for line in r.stderr.splitlines() if ": warning: " in line]
    assert heads == [
        "a.hmpl:2:9: warning: unused variable 'idle'",
        "a.hmpl:3:17: warning: format '%d' expects an argument of type 'int', but argument 2 "
        "has type 'double'",
    ]


def test_werror_in_process_through_main(tmp_path, capsys, monkeypatch):
    from motionvm.cli import main

    write(tmp_path, "a.hmpl", "void main() {\n    int idle;\n}\n")
    monkeypatch.chdir(tmp_path)
    assert main(["check", "a.hmpl"]) == 0
    assert "unused variable 'idle'" in capsys.readouterr().err
    assert main(["check", "--Werror", "a.hmpl"]) == 2
