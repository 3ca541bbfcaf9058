"""`motionvm ... | head -1`: a reader that closes stdout early ends the run quietly.

The command exits 0 with nothing on stderr, whether the pipe closes while a program
still prints (a flood) or before anything was written (the output still sat in
Python's buffer at exit), for every language and for the commands that only print.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import motionvm

SRC = Path(motionvm.__file__).resolve().parents[1]
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

FLOODS = {
    "flood.pdl": '#task/0;\nl: printl("x");\ngoto l;\n',
    "flood.hmpl": 'void main() {\n    while (1) {\n        Print("x");\n    }\n}\n',
}


def _env(buffered: bool) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(SRC)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    )
    env.pop("PYTHONUNBUFFERED", None)
    if not buffered:
        env["PYTHONUNBUFFERED"] = "1"
    return env


def _start(argv, cwd: Path, buffered: bool) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "motionvm", *map(str, argv)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=_env(buffered),
    )


def _finish(proc: subprocess.Popen) -> tuple[int, str]:
    try:
        err = proc.stderr.read().decode("utf-8", "replace")
        proc.wait(timeout=120)
    finally:
        proc.kill()
        proc.stderr.close()
    return proc.returncode, err


def _assert_quiet(code: int, err: str) -> None:
    assert "internal error" not in err, err
    assert "Traceback" not in err, err
    assert "BrokenPipeError" not in err, err
    assert code == 0, err


@pytest.mark.parametrize("buffered", [True, False], ids=["buffered", "unbuffered"])
@pytest.mark.parametrize("name", sorted(FLOODS))
def test_a_flood_ends_quietly_when_the_reader_stops_after_one_line(tmp_path, name, buffered):
    (tmp_path / name).write_text(FLOODS[name])
    proc = _start(["run", name], tmp_path, buffered)
    assert proc.stdout.readline() == b"x\n"
    proc.stdout.close()
    _assert_quiet(*_finish(proc))


SHORT_RUNS = {
    "pdl": ["run", "one.pdl"],
    "hmpl": ["run", "one.hmpl"],
    "gdl": ["run", "02_gdl_packer.gdl", "--scenario", "02_gdl_packer.toml"],
    "builtins": ["builtins"],
}


@pytest.mark.parametrize("what", sorted(SHORT_RUNS))
def test_output_still_buffered_when_the_reader_is_gone_is_dropped_quietly(tmp_path, what):
    (tmp_path / "one.pdl").write_text('#task/0;\nprintl("x");\n')
    (tmp_path / "one.hmpl").write_text('void main() {\n    Print("x");\n}\n')
    for name in ("02_gdl_packer.gdl", "02_gdl_packer.toml"):
        (tmp_path / name).write_bytes((EXAMPLES / name).read_bytes())
    proc = _start(SHORT_RUNS[what], tmp_path, buffered=True)
    proc.stdout.close()  # before the command wrote anything
    _assert_quiet(*_finish(proc))
