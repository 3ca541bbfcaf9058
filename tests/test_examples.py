"""Runs every example program in examples/ and diffs its stdout against NN_topic.out.

`examples/NN_topic.hmpl` runs as `python -m motionvm run NN_topic.hmpl` in examples/,
with a fresh data folder in MOTIONVM_DATA_DIR; it must exit with code 0 and print
exactly the text of `NN_topic.out`. A multi-task example puts task K in
`NN_topic.taskK.hmpl` (K = 1, 2, ...); such files are passed after the example and are
not examples of their own. A GDL example `NN_topic.gdl` runs with its scenario
`NN_topic.toml` when there is one; an HMPL example runs on the machine file
`NN_topic.toml` when there is one (`--machine`); a GDL application beside it,
`NN_topic.NAME.gdl`, is passed after the tasks (all three languages on one machine),
with its scenario `NN_topic.scenario.toml` when there is one. Set MOTIONVM_TEST_CMD to run another command instead of
`python -m motionvm` (see tests/lang/hmpl/test_hmpl_programs.py).
"""

from __future__ import annotations

import difflib
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"
SUFFIXES = (".hmpl", ".gdl")
TIMEOUT_S = 60


def collect_examples() -> list[Path]:
    return sorted(p for p in EXAMPLES.glob("*") if p.suffix in SUFFIXES and "." not in p.stem)


def task_files(example: Path) -> list[str]:
    """The example's task files NN_topic.task1.hmpl, task2, ... in task order."""
    pattern = re.compile(rf"{re.escape(example.stem)}\.task(\d+){re.escape(example.suffix)}")
    found = {}
    for p in example.parent.iterdir():
        m = pattern.fullmatch(p.name)
        if m:
            found[int(m.group(1))] = p.name
    numbers = sorted(found)
    if numbers != list(range(1, len(numbers) + 1)):
        pytest.fail(f"{example.name}: task files must be numbered 1, 2, ...: {numbers}")
    return [found[n] for n in numbers]


def companions(example: Path) -> list[str]:
    """An HMPL example's GDL application `NN_topic.NAME.gdl` and its scenario."""
    if example.suffix != ".hmpl":
        return []
    out = sorted(p.name for p in example.parent.glob(f"{example.stem}.*.gdl"))
    scenario = example.with_name(f"{example.stem}.scenario.toml")
    if out and scenario.is_file():
        out += ["--scenario", scenario.name]
    return out


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
    extra = task_files(example)
    scenario = example.with_suffix(".toml")
    if example.suffix == ".gdl" and scenario.is_file():
        extra += ["--scenario", scenario.name]  # a GDL example's stimuli: NN_topic.toml
    elif example.suffix == ".hmpl" and scenario.is_file():
        extra += ["--machine", scenario.name]  # an HMPL example's machine: NN_topic.toml
    extra += companions(example)
    cmd = base_command() + ["run", example.name, *extra]
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
