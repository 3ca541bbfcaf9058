"""`motionvm test`'s verdicts and reports: a case's outcome judged, pytest-style text, JUnit XML."""

from __future__ import annotations

import contextlib
import difflib
import os
import re
import shlex
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

from motionvm.cli.cases import Case, Expectations
from motionvm.cli.workers import Outcome

PASSED, FAILED, ERROR = "passed", "failed", "error"
_LETTER = {PASSED: ".", FAILED: "F", ERROR: "E"}
_WORD = {PASSED: "PASSED", FAILED: "FAILED", ERROR: "ERROR"}


@dataclass(frozen=True)
class Verdict:
    """A case's result: passed, failed (expectations not met) or error (could not run)."""

    case: Case
    status: str
    details: str = ""
    """What went wrong, for the report: the command, the problems, diffs, stderr."""
    wall_time: float = 0.0
    stdout: str = ""
    stderr: str = ""


def judge(case: Case, outcome: Outcome | None, timeout: float) -> Verdict:
    """The verdict on `case` given what its run did (None: it could not run)."""
    if case.problem is not None or outcome is None:
        return Verdict(case, ERROR, case.problem or "not run")
    command = f"$ motionvm run {shlex.join(case.argv)}  (in {case.folder})"
    t = outcome.wall_time
    if outcome.crashed is not None:
        return Verdict(case, ERROR, f"{command}\nthe worker running it died: {outcome.crashed}", t)
    if outcome.timed_out:
        text = f"{command}\ntimed out after {timeout:g} s of wall-clock time (--case-timeout)"
        return Verdict(case, FAILED, text, t, outcome.stdout, outcome.stderr)
    exp = case.expect
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
    problems += _error_problems(exp, outcome.stderr)
    if "Traceback (most recent call last)" in outcome.stderr:
        problems.append("a Python traceback on stderr")
    if not problems:
        return Verdict(case, PASSED, "", t)
    text = "\n".join([command, *problems])
    return Verdict(case, FAILED, text, t, outcome.stdout, outcome.stderr)


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


def _error_problems(exp: Expectations, stderr: str) -> list[str]:
    problems = []
    lines = stderr.splitlines()
    for file, line, col, text in exp.compile_errors:
        head = re.compile(rf"(?:^|.*[/\\]){re.escape(file)}:{line}:{col}: error: (?P<msg>.*)")
        found = [" ".join(m.group("msg").split()) for m in map(head.fullmatch, lines) if m]
        if not any(text in msg for msg in found):
            there = f" (errors there: {found})" if found else ""
            problems.append(f"missing compile error {file}:{line}:{col}: ...{text}...{there}")
    flat = [" ".join(s.split()) for s in lines]
    for text in exp.runtime_errors:
        if not any(text in s for s in flat):
            problems.append(f"missing runtime error containing {text!r}")
    return problems


class TextReport:
    """pytest's look: a progress line, the failures with diffs, one summary line."""

    def __init__(self, out: TextIO, verbosity: int) -> None:
        self.out = out
        self.verbosity = verbosity
        self._column = 0

    def start(self, n_cases: int, n_deselected: int, where: str) -> None:
        if self.verbosity >= 0:
            more = f" ({n_deselected} deselected)" if n_deselected else ""
            noun = "case" if n_cases == 1 else "cases"
            self.out.write(f"collected {n_cases} {noun}{more}{where}\n\n")

    def progress(self, v: Verdict) -> None:
        if self.verbosity > 0:
            self.out.write(f"{v.case.id} {_WORD[v.status]}\n")
        else:
            if self._column == 80:
                self.out.write("\n")
                self._column = 0
            self.out.write(_LETTER[v.status])
            self._column += 1
        self.out.flush()

    def finish(self, verdicts: Sequence[Verdict], wall_time: float, stopped: bool) -> None:
        if self._column:
            self.out.write("\n")
        bad = [v for v in verdicts if v.status != PASSED]
        if bad:
            self.out.write("\n" + _rule("FAILURES", "=") + "\n")
        for v in bad:
            self.out.write(_rule(v.case.id, "_") + "\n" + v.details.rstrip("\n") + "\n")
            if v.stderr.strip():
                self.out.write("--- stderr ---\n" + v.stderr.rstrip("\n") + "\n")
            self.out.write("\n")
        if stopped:
            self.out.write("stopping after the first failure (-x)\n")
        if bad:
            self.out.write(_rule("short summary", "=") + "\n")
        for v in bad:
            self.out.write(f"{_WORD[v.status]} {v.case.id}\n")
        self.out.write(summary(verdicts, wall_time) + "\n")


def summary(verdicts: Sequence[Verdict], wall_time: float) -> str:
    """`N passed, M failed[, K errors] in S s`."""
    count = {s: sum(v.status == s for v in verdicts) for s in (PASSED, FAILED, ERROR)}
    parts = [f"{count[PASSED]} passed", f"{count[FAILED]} failed"]
    if count[ERROR]:
        parts.append(f"{count[ERROR]} error" + ("s" if count[ERROR] > 1 else ""))
    return f"{', '.join(parts)} in {wall_time:.2f} s"


def _rule(title: str, char: str) -> str:
    side = max(3, (78 - len(title)) // 2)
    return f"{char * side} {title} {char * side}"


def write_junit(path: str, verdicts: Sequence[Verdict], wall_time: float) -> None:
    """A JUnit XML report at `path`, written to a temporary file and renamed into place."""
    count = {s: sum(v.status == s for v in verdicts) for s in (FAILED, ERROR)}
    suites = ET.Element("testsuites")
    suite = ET.SubElement(
        suites,
        "testsuite",
        name="motionvm",
        tests=str(len(verdicts)),
        failures=str(count[FAILED]),
        errors=str(count[ERROR]),
        skipped="0",
        time=f"{wall_time:.3f}",
    )
    for v in verdicts:
        folder, _, name = v.case.id.rpartition("/")
        case = ET.SubElement(
            suite,
            "testcase",
            classname=folder.replace("/", ".") or ".",
            name=name,
            file=v.case.id,
            time=f"{v.wall_time:.3f}",
        )
        if v.status != PASSED:
            tag = "failure" if v.status == FAILED else "error"
            first = v.details.splitlines()[1:2] or v.details.splitlines()[:1] or [v.status]
            node = ET.SubElement(case, tag, message=first[0])
            node.text = _xml_safe(v.details)
            if v.stdout:
                ET.SubElement(case, "system-out").text = _xml_safe(v.stdout)
            if v.stderr:
                ET.SubElement(case, "system-err").text = _xml_safe(v.stderr)
    ET.indent(suites)
    data = ET.tostring(suites, encoding="utf-8", xml_declaration=True)
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or Path("."))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data + b"\n")
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


_XML_BAD = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f]")


def _xml_safe(text: str) -> str:
    """XML 1.0 has no control characters: show them as \\xNN."""
    return _XML_BAD.sub(lambda m: f"\\x{ord(m.group()):02x}", text)
