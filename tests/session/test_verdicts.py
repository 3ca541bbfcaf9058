"""Run verdicts for CI: `--until` notes what still ran, `--timeout` fails naming where each
task waits, a summary line for a person at a terminal (through the real command)."""

from __future__ import annotations

import os
import pty
import re
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
STUCK = 'void main() {\n    StartTask(1);\n    Till(HIMC_GPI(1));\n    Print("never");\n}\n'
LOOP = "void main() {\n    while (1) {\n        Sleep(100);\n    }\n}\n"


def motionvm(*argv, cwd: Path, stderr=subprocess.PIPE) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "motionvm", *map(str, argv)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=stderr,
        text=True,
        timeout=120,
    )


def programs(tmp: Path) -> list[str]:
    (tmp / "t0.hmpl").write_text(STUCK, encoding="utf-8")
    (tmp / "t1.hmpl").write_text(LOOP, encoding="utf-8")
    return ["t0.hmpl", "t1.hmpl"]


def test_until_is_exit_0_with_a_note_of_where_each_task_waits(tmp_path):
    r = motionvm("run", *programs(tmp_path), "--until", "5", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout == ""
    assert r.stderr.splitlines() == [
        "t0.hmpl:3:5: note: task 0 (in Till) still ran when the run ended at t=5 s",
        "t1.hmpl:3:9: note: task 1 (sleeping until t=5.001 s) still ran when the run ended at t=5 s",
    ]


def test_timeout_fails_naming_where_each_task_waits(tmp_path):
    r = motionvm("run", *programs(tmp_path), "--timeout", "2", cwd=tmp_path)
    assert r.returncode == 124
    assert r.stderr.splitlines() == [
        "t0.hmpl:3:5: error: task 0 (in Till) had not finished after --timeout 2 s",
        "t1.hmpl:3:9: error: task 1 (sleeping until t=2.001 s) had not finished after --timeout 2 s",
        "motionvm: error: the run did not finish within --timeout 2 s of simulated time",
    ]


def test_a_run_that_finishes_in_time_passes_without_a_word(tmp_path):
    (tmp_path / "a.hmpl").write_text('void main() { Sleep(50); Print("ok"); }\n', "utf-8")
    r = motionvm("run", "a.hmpl", "--timeout", "1", cwd=tmp_path)
    assert (r.returncode, r.stdout, r.stderr) == (0, "ok\n", "")


def test_an_earlier_until_wins_over_the_timeout(tmp_path):
    r = motionvm("run", *programs(tmp_path), "--timeout", "2", "--until", "1", cwd=tmp_path)
    assert r.returncode == 0 and ": note: task 0 (in Till) still ran" in r.stderr


def test_pdl_drive_tasks_and_moving_axes_are_named(tmp_path):
    argv = ["run", "--machine", "03_pdl_drives.toml", "03_pdl_drives.hmpl", "--until", "0.03"]
    r = motionvm(*argv, cwd=EXAMPLES)
    assert r.returncode == 0
    notes = r.stderr.splitlines()
    assert "03_pdl_drives.mover.pdl:6:1: note: drive 1 task 0 (in till) still ran" in notes[1]
    assert any(n.startswith("motionvm: note: axis 0 (moving) still ran") for n in notes)


def test_gdl_scenario_events_left_are_named(tmp_path):
    argv = ["run", "02_gdl_packer.gdl", "--scenario", "02_gdl_packer.toml", "--timeout", "0.35"]
    r = motionvm(*argv, cwd=EXAMPLES)
    assert r.returncode == 124
    assert "the GDL scenario (4 events not applied yet, the next at t=0.500)" in r.stderr


def test_a_terminal_gets_a_summary_line(tmp_path):
    (tmp_path / "a.hmpl").write_text("void main() { Sleep(2000); }\n", "utf-8")
    primary, secondary = pty.openpty()
    try:
        r = motionvm("run", "a.hmpl", cwd=tmp_path, stderr=secondary)
        os.close(secondary)
        secondary = -1
        chunks = []
        while True:
            try:
                data = os.read(primary, 4096)
            except OSError:
                break
            if not data:
                break
            chunks.append(data)
    finally:
        os.close(primary)
        if secondary >= 0:
            os.close(secondary)
    line = b"".join(chunks).decode()
    assert r.returncode == 0
    wall = r"\d+\.\d\d s|\d+\.\d{1,2} ms"  # with the precision it has
    speed = r" \(\d+x real time\)"  # left out of a run too short to measure it
    assert re.fullmatch(
        rf"motionvm: 2\.001 s simulated in (?:{wall})(?:{speed})?, 0 faults\s*", line
    )


def test_no_summary_when_stderr_is_not_a_terminal(tmp_path):
    (tmp_path / "a.hmpl").write_text("void main() { Sleep(20); }\n", "utf-8")
    assert motionvm("run", "a.hmpl", cwd=tmp_path).stderr == ""
