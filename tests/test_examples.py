"""Runs every example program in examples/ and diffs its stdout against NN_topic.out.

`examples/NN_topic.hmpl` runs as `python -m motionvm run NN_topic.hmpl` in examples/,
with a fresh data folder in MOTIONVM_DATA_DIR; it must exit with code 0 and print
exactly the text of `NN_topic.out`. A multi-task example puts task K in
`NN_topic.taskK.hmpl` (K = 1, 2, ...); such files are passed after the example and are
not examples of their own. A GDL example `NN_topic.gdl` runs with its scenario
`NN_topic.toml` when there is one; an HMPL example runs on the machine file
`NN_topic.toml` when there is one (`--machine`) and its scenario
`NN_topic.scenario.toml` when there is one; a GDL application beside it,
`NN_topic.NAME.gdl`, is passed after the tasks (all three languages on one machine); an
`args:` comment adds the options the documentation runs it with (`// args: --stamp`). These are the conventions of
`motionvm test` (`motionvm.cli.cases.run_arguments`), shared here. Set MOTIONVM_TEST_CMD
to run another command instead of `python -m motionvm` (shell-style), e.g. an installed
`motionvm`.
"""

from __future__ import annotations

import difflib
import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from motionvm.cli.cases import CaseError, expectations_of, is_case_file, run_arguments

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"
TIMEOUT_S = 60


def collect_examples() -> list[Path]:
    return sorted(p for p in EXAMPLES.iterdir() if is_case_file(p))


def base_command() -> list[str]:
    override = os.environ.get("MOTIONVM_TEST_CMD")
    if override:
        return shlex.split(override)
    return [sys.executable, "-m", "motionvm"]


@pytest.mark.parametrize("example", collect_examples(), ids=lambda p: p.name)
def test_example(example: Path, tmp_path: Path) -> None:
    expected_path = example.with_suffix(".out")
    assert expected_path.is_file(), f"{example.name} has no {expected_path.name}"
    expected = expected_path.read_text(encoding="utf-8")

    env = dict(os.environ)
    env["MOTIONVM_DATA_DIR"] = str(tmp_path)
    src = str(REPO / "src")
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    try:
        argv = run_arguments(example)  # task files, machine or scenario, companions
        case = expectations_of(example)
    except CaseError as exc:
        pytest.fail(str(exc), pytrace=False)
    options = case[1] if case is not None else []  # `args: --stamp`, as the docs run it
    cmd = base_command() + ["run", *argv, *options]
    try:
        proc = subprocess.run(
            cmd,
            check=False,
            cwd=EXAMPLES,
            env=env,
            capture_output=True,
            text=True,
            encoding="utf-8",
            errors="replace",
            timeout=TIMEOUT_S,
        )
    except subprocess.TimeoutExpired:
        proc = None
    if proc is None:
        pytest.fail(f"timed out after {TIMEOUT_S} s: {shlex.join(cmd)}", pytrace=False)

    problems = []
    if proc.returncode != 0:
        problems.append(f"exit code {proc.returncode}, expected 0")
    if proc.stdout != expected:
        diff = difflib.unified_diff(
            expected.splitlines(keepends=True),
            proc.stdout.splitlines(keepends=True),
            expected_path.name,
            "actual stdout",
        )
        problems.append("stdout differs:\n" + "".join(diff))
    if problems:
        pytest.fail(
            f"$ {shlex.join(cmd)}  (in {EXAMPLES})\n"
            + "\n".join(problems)
            + f"\n--- stderr ---\n{proc.stderr.rstrip()}",
            pytrace=False,
        )
