"""Runs every golden HMPL program under tests/programs/hmpl/ and checks its inline expectations.

Each `tests/programs/hmpl/**/NAME.hmpl` whose stem has no dot is one test case (id: the
path relative to tests/programs/hmpl). Files whose stem has a dot (`NAME.task1.hmpl`,
`NAME.restart.hmpl`, `ticker.task1.hmpl`) are helpers of other programs and never run on
their own; headers for `#include` use other extensions (`lang/include/*.h`).

The program is run as `python -m motionvm run ARGS NAME.hmpl [TASK FILES]` in a
subprocess, with the program's folder as working directory, a fresh empty data folder
in the environment variable MOTIONVM_DATA_DIR, and a 60 s wall-clock timeout.

Directives are `//` comments, anywhere on a line (so `Print("x"); // expect: x` works):

`// expect: TEXT`
    The next line the program prints on stdout is exactly TEXT (everything after
    `expect: `, trailing spaces included). The stdout lines must equal the expect
    lines, in order, with nothing extra.
`// expect regex: PATTERN`
    Like `expect:`, but the stdout line must fully match the Python regex PATTERN
    (for values the manual leaves to the implementation, e.g. a firmware version).
`// expect runtime error: TEXT`
    The run exits with code 1 and some stderr line of the form
    `FILE:LINE:COL: runtime error in task N at t=S.mmm s: MESSAGE` contains TEXT. Write
    `:LINE:COL: runtime error in task N at t=S.mmm s:` to pin the place, task and time
    as well.
`// error: [FILE:]LINE:COL: TEXT`
    A compile error: exit code 2, nothing on stdout, and stderr has a headline
    `...FILE:LINE:COL: error: MESSAGE` whose MESSAGE contains TEXT. FILE defaults to
    the program itself; name a task file to expect an error in it. Several `error:`
    lines may be given; all must be reported (extra errors are not a failure).
`// args: ARG...`
    Extra command-line arguments, placed before the files (shell-style quoting),
    e.g. `// args: --until 3.5`.
`// task N: FILE`
    FILE (relative to the program's folder) is task N; the program itself is task 0.
    Task files are passed in task order after the program; when the task numbers
    are not 1, 2, ... without gaps they are passed as `--task N=FILE` instead.
`// pending: REASON`
    The program needs a capability of a later issue (e.g. axis functions): the case is a
    strict expected failure, so it turns into an error the day the capability lands.
`// restart: FILE`
    After the run, start the controller again (same data folder, same `args:`) with
    FILE as its only task: a power cycle of the controller. The stdout of the two runs
    is compared as one; each run must end with the expected exit code.

Without an error directive the run must exit with code 0 (also when `--until` ends it).
A Python traceback on stderr always fails the test. A directive-like comment that does
not parse (e.g. `// expect:` misspelt as `// expected:`) is reported as an error.

Set MOTIONVM_TEST_CMD (shell-style) to run another command instead of
`python -m motionvm`, e.g. an installed `motionvm` or a stub when testing this runner.
"""

from __future__ import annotations

import difflib
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
PROGRAMS = REPO / "tests" / "programs" / "hmpl"
TIMEOUT_S = 60

_DIRECTIVE = re.compile(
    r"//\s*(?P<kind>expect regex|expect runtime error|expect|error|args|task\s+(?P<task>\d+)"
    r"|restart|pending):(?: (?P<text>.*)|$)"
)
_LOOKS_LIKE_DIRECTIVE = re.compile(
    r"//\s*(expect|error\s*:|args\s*:|task\s+\d+\s*:|restart\s*:|pending\s*:)"
)
_ERROR_AT = re.compile(r"(?:(?P<file>[^:\s]+):)?(?P<line>\d+):(?P<col>\d+): (?P<text>.+)")
_RUNTIME_LINE = re.compile(r".+:\d+:\d+: runtime error in task \d+ at t=\d+\.\d{3} s: .*")


@dataclass
class Expectations:
    """What one golden program's directives ask for."""

    stdout: list[tuple[str, str]] = field(default_factory=list)  # ('text'|'regex', value)
    runtime_errors: list[str] = field(default_factory=list)
    compile_errors: list[tuple[str | None, int, int, str]] = field(default_factory=list)
    args: list[str] = field(default_factory=list)
    tasks: dict[int, str] = field(default_factory=dict)
    restart: str | None = None
    pending: str | None = None  # needs a capability of a later issue: a strict xfail

    @property
    def exit_code(self) -> int:
        if self.compile_errors:
            return 2
        if self.runtime_errors:
            return 1
        return 0


def parse_expectations(path: Path) -> Expectations:
    """Read the directives of one program; a malformed directive is a test error."""
    exp = Expectations()
    text = path.read_text(encoding="utf-8")
    for lineno, line in enumerate(text.splitlines(), 1):
        where = f"{path.name}:{lineno}"
        m = _DIRECTIVE.search(line)
        if m is None:
            if _LOOKS_LIKE_DIRECTIVE.search(line):
                raise ValueError(f"{where}: malformed directive: {line.strip()!r}")
            continue
        kind, value = m.group("kind"), m.group("text") or ""
        if kind == "expect":
            exp.stdout.append(("text", value))
        elif kind == "expect regex":
            re.compile(value)
            exp.stdout.append(("regex", value))
        elif kind == "expect runtime error":
            if not value.strip():
                raise ValueError(f"{where}: empty runtime error expectation")
            exp.runtime_errors.append(value.strip())
        elif kind == "error":
            e = _ERROR_AT.fullmatch(value.strip())
            if e is None:
                raise ValueError(f"{where}: want '// error: [FILE:]LINE:COL: TEXT', got {value!r}")
            exp.compile_errors.append(
                (e.group("file"), int(e.group("line")), int(e.group("col")), e.group("text"))
            )
        elif kind == "args":
            exp.args.extend(shlex.split(value))
        elif kind.startswith("task"):
            n = int(m.group("task"))
            if n == 0 or n in exp.tasks or not value.strip():
                raise ValueError(f"{where}: bad or repeated task directive")
            exp.tasks[n] = value.strip()
        elif kind == "restart":
            exp.restart = value.strip()
        elif kind == "pending":
            exp.pending = value.strip() or "pending"
    if exp.compile_errors and (exp.stdout or exp.runtime_errors):
        raise ValueError(f"{path.name}: a compile-error program cannot expect output")
    return exp


def collect_programs() -> list[Path]:
    """Every runnable program: *.hmpl whose stem has no dot (helpers have one)."""
    return sorted(p for p in PROGRAMS.rglob("*.hmpl") if "." not in p.stem)


def base_command() -> list[str]:
    override = os.environ.get("MOTIONVM_TEST_CMD")
    if override:
        return shlex.split(override)
    return [sys.executable, "-m", "motionvm"]


def task_arguments(exp: Expectations) -> list[str]:
    numbers = sorted(exp.tasks)
    if numbers == list(range(1, len(numbers) + 1)):
        return [exp.tasks[n] for n in numbers]
    return [arg for n in numbers for arg in ("--task", f"{n}={exp.tasks[n]}")]


@dataclass
class RunResult:
    command: list[str]
    returncode: int
    stdout: str
    stderr: str


def run_motionvm(files: list[str], exp: Expectations, cwd: Path, data_dir: Path) -> RunResult:
    env = dict(os.environ)
    env["MOTIONVM_DATA_DIR"] = str(data_dir)
    src = str(REPO / "src")
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    cmd = base_command() + ["run", *exp.args, *files]
    try:
        proc = subprocess.run(
            cmd,
            check=False,
            cwd=cwd,
            env=env,
            capture_output=True,
            text=True,
            encoding="utf-8",
            errors="replace",
            timeout=TIMEOUT_S,
        )
    except subprocess.TimeoutExpired as e:
        timed_out = (_text(e.stdout), _text(e.stderr))
    else:
        return RunResult(cmd, proc.returncode, proc.stdout, proc.stderr)
    pytest.fail(
        f"timed out after {TIMEOUT_S} s: {shlex.join(cmd)}\n"
        f"--- stdout so far ---\n{timed_out[0]}\n--- stderr so far ---\n{timed_out[1]}",
        pytrace=False,
    )


def _text(data: bytes | str | None) -> str:
    if isinstance(data, bytes):
        return data.decode("utf-8", "replace")
    return data or ""


def stdout_problems(expected: list[tuple[str, str]], actual: list[str]) -> str:
    """'' when the lines match, else a unified diff (regex lines shown as /PATTERN/)."""
    ok = len(expected) == len(actual) and all(
        (re.fullmatch(v, a) is not None) if k == "regex" else v == a
        for (k, v), a in zip(expected, actual)
    )
    if ok:
        return ""
    shown = []
    for i, (k, v) in enumerate(expected):
        if k == "regex" and i < len(actual) and re.fullmatch(v, actual[i]):
            shown.append(actual[i])  # a matching regex line is not part of the diff
        else:
            shown.append(f"/{v}/" if k == "regex" else v)
    diff = difflib.unified_diff(
        [repr(s) for s in shown],
        [repr(s) for s in actual],
        "expected stdout",
        "actual stdout",
        lineterm="",
    )
    return "stdout differs (- expected, + actual; lines quoted):\n" + "\n".join(diff)


def error_problems(exp: Expectations, program: str, stderr: str) -> list[str]:
    problems = []
    lines = stderr.splitlines()
    for file, line, col, text in exp.compile_errors:
        name = file or program
        head = re.compile(rf"(?:^|.*[/\\]){re.escape(name)}:{line}:{col}: error: (?P<msg>.*)")
        found = [m.group("msg") for m in map(head.fullmatch, lines) if m]
        if not any(text in msg for msg in found):
            got = f" (errors there: {found})" if found else ""
            problems.append(f"missing compile error {name}:{line}:{col}: ...{text}...{got}")
    runtime_lines = [s for s in lines if _RUNTIME_LINE.fullmatch(s)]
    for text in exp.runtime_errors:
        if not any(text in s for s in runtime_lines):
            problems.append(f"missing runtime error containing {text!r}")
    if "Traceback (most recent call last)" in stderr:
        problems.append("a Python traceback on stderr")
    return problems


def check_program(path: Path, data_dir: Path) -> None:
    exp = parse_expectations(path)
    cwd = path.parent
    runs = [run_motionvm([path.name, *task_arguments(exp)], exp, cwd, data_dir)]
    if exp.restart and runs[0].returncode == exp.exit_code:
        runs.append(run_motionvm([exp.restart], exp, cwd, data_dir))

    problems = []
    for r in runs:
        if r.returncode != exp.exit_code:
            problems.append(f"exit code {r.returncode}, expected {exp.exit_code}")
    stderr = "".join(r.stderr for r in runs)
    stdout_lines = [line for r in runs for line in r.stdout.splitlines()]
    if exp.compile_errors:
        if stdout_lines:
            problems.append("a program with compile errors printed to stdout")
    else:
        diff = stdout_problems(exp.stdout, stdout_lines)
        if diff:
            problems.append(diff)
    problems += error_problems(exp, path.name, stderr)
    if problems:
        commands = "\n".join("$ " + shlex.join(r.command) for r in runs)
        pytest.fail(
            f"{path.relative_to(PROGRAMS)} (in {cwd}):\n{commands}\n"
            + "\n".join(problems)
            + f"\n--- stderr ---\n{stderr.rstrip()}",
            pytrace=False,
        )


@pytest.mark.parametrize(
    "program",
    collect_programs(),
    ids=lambda p: p.relative_to(PROGRAMS).as_posix(),
)
def test_hmpl_program(program: Path, tmp_path: Path, request: pytest.FixtureRequest) -> None:
    pending = parse_expectations(program).pending
    if pending:
        request.node.add_marker(pytest.mark.xfail(reason=pending, strict=True))
    data_dir = tmp_path / "data"
    data_dir.mkdir()
    check_program(program, data_dir)
