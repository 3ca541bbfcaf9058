"""Skipping and stepping give byte-identical outputs: every golden program and example.

Each program runs in-process as `motionvm run --stamp ARGV` three ways: with time
skipping (the default), with `--no-skip` and with MOTIONVM_NO_SKIP=1. Exit code, stdout
(with the simulated time of every message) and stderr must be equal byte for byte. Each
program also runs with a scope recording every cycle (axis positions and velocities,
the HMPL time), skipping and stepping: the scope files must be equal too.
"""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.cli.cases import collect

REPO = Path(__file__).resolve().parents[2]
CASES = collect([str(REPO / "tests" / "programs"), str(REPO / "examples")])
RUNS = [c for c in CASES if c.problem is None and c.command == "run"]
"""The cases that run (`check:` cases only compile)."""


def _run(folder: str, argv: list[str], env: dict[str, str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    saved = {k: os.environ.get(k) for k in env}
    cwd = os.getcwd()
    os.environ.update(env)
    try:
        os.chdir(folder)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
    finally:
        os.chdir(cwd)
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return code, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("case", RUNS, ids=lambda c: c.id)
def test_skipping_and_stepping_print_the_same(case, tmp_path):
    argv = ["run", "--stamp", "--timeout", "120", *case.argv]
    env = {"MOTIONVM_DATA_DIR": str(tmp_path / "a"), "MOTIONVM_NO_SKIP": "0"}
    jumped = _run(case.folder, argv, env)
    env["MOTIONVM_DATA_DIR"] = str(tmp_path / "b")
    stepped = _run(case.folder, [*argv[:1], "--no-skip", *argv[1:]], env)
    env["MOTIONVM_DATA_DIR"] = str(tmp_path / "c")
    env["MOTIONVM_NO_SKIP"] = "1"
    by_env = _run(case.folder, argv, env)
    assert jumped == stepped == by_env


def _channels(case) -> str:
    hmpl_only = all(not a.endswith((".pdl", ".gdl")) for a in case.argv)
    return "axis0.pos_fb,axis0.ref_vel,axis1.pos_fb" + (",system_timeInMs" if hmpl_only else "")


@pytest.mark.parametrize("case", RUNS, ids=lambda c: c.id)
def test_skipping_and_stepping_record_the_same_scope(case, tmp_path):
    files = []
    for skip in (True, False):
        scope = tmp_path / f"scope_{skip}.csv"
        argv = ["run", "--timeout", "120", "--scope", _channels(case), "--scope-out",
                str(scope), *case.argv]  # fmt: skip
        if not skip:
            argv.insert(1, "--no-skip")
        env = {"MOTIONVM_DATA_DIR": str(tmp_path / str(skip)), "MOTIONVM_NO_SKIP": "0"}
        code, out, err = _run(case.folder, argv, env)
        files.append((code, out, err, scope.read_bytes() if scope.exists() else None))
    assert files[0] == files[1]


@pytest.mark.parametrize(
    ("argv", "channels"),
    [
        (["--machine", "03_pdl_drives.toml", "03_pdl_drives.hmpl"],
         "drive1.fclk,drive1.X_trg,drive1.x_ref_pos,drive2.fclk,axis1.pos_fb,system_timeInMs"),
        (["02_gdl_packer.gdl", "--scenario", "02_gdl_packer.toml"],
         "start_button.STATUS,photocell{1}.STATUS,axis0.pos_fb,axis0.ref_vel"),
    ],
)  # fmt: skip
def test_drive_and_gdl_channels_are_sampled_the_same(argv, channels, tmp_path):
    files = []
    for skip in (True, False):
        scope = tmp_path / f"scope_{skip}.csv"
        run = ["run", *([] if skip else ["--no-skip"]), "--scope", channels, "--scope-out",
               str(scope), *argv]  # fmt: skip
        env = {"MOTIONVM_DATA_DIR": str(tmp_path / str(skip)), "MOTIONVM_NO_SKIP": "0"}
        code, out, err = _run(str(REPO / "examples"), run, env)
        assert code == 0, err
        files.append((out, err, scope.read_bytes()))
    assert files[0] == files[1]
