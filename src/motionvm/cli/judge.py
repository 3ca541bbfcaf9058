"""The verdict on a case of `motionvm test`: what its run did, held against what it expects."""

from __future__ import annotations

import difflib
import re
import shlex
from collections.abc import Sequence
from dataclasses import dataclass

from motionvm.cli.cases import Case, Expectations
from motionvm.cli.workers import Outcome, flood_message

PASSED, FAILED, ERROR, XFAILED = "passed", "failed", "error", "xfailed"

_DIAGNOSTIC = re.compile(
    r"(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): "
    r"(?P<severity>error|warning): (?P<message>.*)"
)
_RUNTIME_ERROR = re.compile(r".+:\d+:\d+: runtime error in .+ at t=\S+ s: .*")
"""A runtime error's report, whichever language: `FILE:LINE:COL: runtime error in WHO at
t=S s: MESSAGE`."""


@dataclass(frozen=True)
class Verdict:
    """A case's result: passed, failed (expectations not met), error (could not run) or
    xfailed (a pending case that failed, as expected)."""

    case: Case
    status: str
    details: str = ""
    """What went wrong, for the report: the command, the problems, diffs, stderr."""
    wall_time: float = 0.0
    stdout: str = ""
    stderr: str = ""


def command_line(case: Case) -> str:
    """The command(s) of the case, as a user would type them, and where."""
    text = f"$ motionvm {case.command} {shlex.join(case.argv)}"
    if case.restart:
        text += f"; motionvm run {shlex.join(case.restart)}"
    return f"{text}  (in {case.folder})"


def judge(case: Case, outcome: Outcome | None, timeout: float) -> Verdict:
    """The verdict on `case` given what its run did (None: it could not run)."""
    verdict = _judge(case, outcome, timeout)
    if case.pending is None or verdict.status == ERROR:
        return verdict
    if verdict.status == FAILED:
        return Verdict(case, XFAILED, f"pending: {case.pending}", verdict.wall_time)
    details = f"{command_line(case)}\npasses, but is pending ({case.pending}): remove 'pending:'"
    return Verdict(case, FAILED, details, verdict.wall_time)


def _judge(case: Case, outcome: Outcome | None, timeout: float) -> Verdict:
    if case.problem is not None or outcome is None:
        return Verdict(case, ERROR, case.problem or "not run")
    command = command_line(case)
    t = outcome.wall_time
    if outcome.crashed is not None:
        return Verdict(case, ERROR, f"{command}\nthe worker running it died: {outcome.crashed}", t)
    if outcome.flooded:
        text = f"{command}\n{flood_message()}"
        return Verdict(case, FAILED, text, t, _tail(outcome.stdout), _tail(outcome.stderr))
    if outcome.timed_out:
        text = f"{command}\ntimed out after {timeout:g} s of wall-clock time (--case-timeout)"
        return Verdict(case, FAILED, text, t, outcome.stdout, outcome.stderr)
    problems = problems_of(case.expect, outcome)
    if not problems:
        return Verdict(case, PASSED, "", t)
    text = "\n".join([command, *problems])
    return Verdict(case, FAILED, text, t, outcome.stdout, outcome.stderr)


_SHOWN = 4096
"""Characters of a flooding case's output the report keeps (its end)."""


def _tail(text: str) -> str:
    return text if len(text) <= _SHOWN else "...\n" + text[-_SHOWN:]


def problems_of(exp: Expectations, outcome: Outcome) -> list[str]:
    """What of `exp` the finished run `outcome` did not do ([]: all of it)."""
    problems = []
    if outcome.returncode != exp.exit_code:
        problems.append(f"exit code {outcome.returncode}, expected {exp.exit_code}")
    if exp.compile_errors:
        if outcome.stdout:
            problems.append("a program with compile errors printed to stdout")
    elif exp.stdout_file is not None:
        if outcome.stdout != exp.stdout_text:
            diff = difflib.unified_diff(
                exp.stdout_text.splitlines(keepends=True),
                outcome.stdout.splitlines(keepends=True),
                exp.stdout_file,
                "actual stdout",
            )
            problems.append("stdout differs:\n" + _ended("".join(diff)).rstrip("\n"))
    else:
        diff = _lines_diff(exp.stdout, outcome.stdout.splitlines())
        if diff:
            problems.append(diff)
    lines = outcome.stderr.splitlines()
    problems += _diagnostic_problems(exp, lines)
    problems += _runtime_problems(exp.runtime_errors, lines)
    if "Traceback (most recent call last)" in outcome.stderr:
        problems.append("a Python traceback on stderr")
    return problems


def _ended(diff: str) -> str:
    """A unified diff whose lines all end in a newline (a last line without one is marked)."""
    return "".join(
        line if line.endswith("\n") else line + "\n\\ No newline at end of file\n"
        for line in diff.splitlines(keepends=True)
    )


def _lines_diff(expected: Sequence[tuple[str, str]], actual: list[str]) -> str:
    """'' when the lines match the `expect:` directives, else a unified diff."""
    ok = len(expected) == len(actual) and all(
        (re.fullmatch(v, a) is not None) if k == "regex" else v == a
        for (k, v), a in zip(expected, actual)
    )
    if ok:
        return ""
    shown = []
    for i, (k, v) in enumerate(expected):
        if k == "regex" and i < len(actual) and re.fullmatch(v, actual[i]):
            shown.append(actual[i])  # a matching regex line is no difference
        else:
            shown.append(f"/{v}/" if k == "regex" else v)
    diff = difflib.unified_diff(shown, actual, "expected stdout", "actual stdout", lineterm="")
    return "stdout differs:\n" + "\n".join(diff)


def _diagnostic_problems(exp: Expectations, lines: list[str]) -> list[str]:
    """Missing expected diagnostics; with `exact_diagnostics` also unlisted ones."""
    reported = []
    for m in map(_DIAGNOSTIC.fullmatch, lines):
        if m is not None:
            at = (m.group("file"), int(m.group("line")), int(m.group("col")))
            reported.append((m.group("severity"), *at, " ".join(m.group("message").split())))
    listed = [("error", *e) for e in exp.compile_errors] + [("warning", *w) for w in exp.warnings]
    problems = []
    unclaimed = list(reported)
    for severity, file, line, col, text in listed:
        there = [r for r in reported if r[0] == severity and r[2:4] == (line, col)]
        there = [r for r in there if _same_file(r[1], file)]
        if exp.exact_diagnostics:
            hit = next((r for r in unclaimed if r in there and r[4] == text), None)
        else:
            hit = next((r for r in there if text in r[4]), None)
        if hit is None:
            also = f" ({severity}s there: {[r[4] for r in there]})" if there else ""
            shown = text if exp.exact_diagnostics else f"...{text}..."
            problems.append(f"missing compile {severity} {file}:{line}:{col}: {shown}{also}")
        elif hit in unclaimed:
            unclaimed.remove(hit)
    if exp.exact_diagnostics:
        for severity, file, line, col, text in unclaimed:
            problems.append(f"unexpected compile {severity} {file}:{line}:{col}: {text}")
    return problems


def _same_file(reported: str, file: str) -> bool:
    """Whether a diagnostic's path names `file` (a path relative to the case's folder)."""
    path = reported.replace("\\", "/")
    return path == file or path.endswith("/" + file)


def _runtime_problems(expected: Sequence[str], lines: list[str]) -> list[str]:
    """The runtime errors reported, held against the expected ones: each expected text is
    in a report, at or after the report of the text before it (several texts may pin one
    report: its place, its message), and every report is expected."""
    reported = [" ".join(s.split()) for s in lines if _RUNTIME_ERROR.fullmatch(s)]
    problems = []
    matched: set[int] = set()
    k = 0
    for text in expected:
        j = next((j for j in range(k, len(reported)) if text in reported[j]), None)
        if j is None:
            after = f" (at or after runtime error {k + 1})" if k else ""
            problems.append(f"missing runtime error containing {text!r}{after}")
            continue
        matched.add(j)
        k = j
    if not problems:
        for j, line in enumerate(reported):
            if j not in matched:
                problems.append(f"unexpected runtime error: {line}")
    return problems
