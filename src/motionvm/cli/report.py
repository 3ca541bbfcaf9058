"""`motionvm test`'s reports of the verdicts (cli/judge.py): pytest-style text, JUnit XML."""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO

from motionvm.cli.judge import ERROR, FAILED, PASSED, XFAILED, Verdict

_LETTER = {PASSED: ".", FAILED: "F", ERROR: "E", XFAILED: "x"}
_WORD = {PASSED: "PASSED", FAILED: "FAILED", ERROR: "ERROR", XFAILED: "XFAIL"}


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

    def finish(
        self,
        verdicts: Sequence[Verdict],
        wall_time: float,
        stopped: bool,
        durations: int | None = None,
        cached: int = 0,
    ) -> None:
        """The failures, `durations` slowest cases (0: all; None: none) and the summary."""
        if self._column:
            self.out.write("\n")
        bad = [v for v in verdicts if v.status in (FAILED, ERROR)]
        if bad:
            self.out.write("\n" + _rule("FAILURES", "=") + "\n")
        for v in bad:
            self.out.write(_rule(v.case.id, "_") + "\n" + v.details.rstrip("\n") + "\n")
            if v.stderr.strip():
                self.out.write("--- stderr ---\n" + v.stderr.rstrip("\n") + "\n")
            self.out.write("\n")
        if durations is not None:
            self._durations(verdicts, durations)
        if stopped:
            self.out.write("stopping after the first failure (-x)\n")
        if bad:
            self.out.write(_rule("short summary", "=") + "\n")
        for v in bad:
            self.out.write(f"{_WORD[v.status]} {v.case.id}\n")
        more = f" ({cached} from cache)" if cached else ""
        self.out.write(summary(verdicts, wall_time) + more + "\n")

    def _durations(self, verdicts: Sequence[Verdict], n: int) -> None:
        slow = sorted(verdicts, key=lambda v: (-v.wall_time, v.case.id))
        title = "slowest durations" if n == 0 else f"slowest {n} durations"
        self.out.write(_rule(title, "=") + "\n")
        for v in slow[:n] if n else slow:
            self.out.write(f"{v.wall_time:.2f}s {v.case.id}\n")
        self.out.write("\n")


def summary(verdicts: Sequence[Verdict], wall_time: float) -> str:
    """`N passed, M failed[, K errors][, X xfailed] in S s`."""
    count = {s: sum(v.status == s for v in verdicts) for s in _WORD}
    parts = [f"{count[PASSED]} passed", f"{count[FAILED]} failed"]
    if count[ERROR]:
        parts.append(f"{count[ERROR]} error" + ("s" if count[ERROR] > 1 else ""))
    if count[XFAILED]:
        parts.append(f"{count[XFAILED]} xfailed")
    return f"{', '.join(parts)} in {wall_time:.2f} s"


def _rule(title: str, char: str) -> str:
    side = max(3, (78 - len(title)) // 2)
    return f"{char * side} {title} {char * side}"


def write_junit(path: str, verdicts: Sequence[Verdict], wall_time: float) -> None:
    """A JUnit XML report at `path`, written to a temporary file and renamed into place."""
    count = {s: sum(v.status == s for v in verdicts) for s in _WORD}
    suites = ET.Element("testsuites")
    suite = ET.SubElement(
        suites,
        "testsuite",
        name="motionvm",
        tests=str(len(verdicts)),
        failures=str(count[FAILED]),
        errors=str(count[ERROR]),
        skipped=str(count[XFAILED]),
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
        if v.status == XFAILED:
            ET.SubElement(case, "skipped", message=v.details)
        elif v.status != PASSED:
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
