"""PDL run time: every program under tests/programs/pdl/run/ prints what its comments expect.

Each program states its expectations in comments (see tests/programs/pdl/README.md):

    // expect: TEXT                   the next printl line (trailing blanks ignored)
    // expect runtime error: TEXT     the next fault report ends with TEXT
    // start: _label | top            a host start after reset (in order)
    // until: SECONDS                 simulated run time (default 10 s)
    // config: key=value              a DriveConfig field (budget, fclk_start, ...)
    // axis: key=value                an AxisConfig field (home_position, ...)
    // input: NAME=0|1                an input state at reset
    // write: NAME=VALUE              a host (KMI) write after reset, before the starts

Messages and faults are compared as one ordered list, so a test also pins down which
task prints first.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from motionvm.lang.pdl.drive_axis import AxisConfig
from motionvm.lang.pdl.drive_rt import Drive, DriveConfig
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source import DiagnosticSink, render_diagnostic

RUN = Path(__file__).parents[2] / "programs" / "pdl" / "run"
PROGRAMS = sorted(RUN.rglob("*.pdl"))
DIRECTIVE = re.compile(
    r"^\s*// (expect|expect runtime error|start|until|config|axis|input|write): ?(.*)$"
)


def _number(text: str) -> float | int | None:
    if text == "None":
        return None
    return float(text) if "." in text or "e" in text else int(text, 0)


def run_program(path: Path) -> tuple[list[str], list[str]]:
    """(what the program printed and faulted, what its comments expect)."""
    expected: list[str] = []
    starts: list[str] = []
    until = 10.0
    config = DriveConfig(axis=AxisConfig())
    inputs: dict[str, int] = {}
    writes: list[tuple[str, float | int | None]] = []
    for line in path.read_text().splitlines():
        m = DIRECTIVE.match(line)
        if not m:
            continue
        key, value = m[1], m[2].rstrip()
        if key == "expect":
            expected.append(value)
        elif key == "expect runtime error":
            expected.append("ERROR ..." + value)
        elif key == "start":
            starts.append(value)
        elif key == "until":
            until = float(value)
        elif key in ("config", "axis"):
            name, v = value.split("=")
            setattr(config if key == "config" else config.axis, name.strip(), _number(v.strip()))
        elif key == "write":
            name, v = value.split("=")
            writes.append((name.strip(), _number(v.strip())))
        elif key == "input":
            name, v = value.split("=")
            inputs[name.strip()] = int(v)
    sink = DiagnosticSink()
    program = compile_pdl(str(path), sink=sink)
    assert program is not None, "\n".join(render_diagnostic(d) for d in sink.items)
    got: list[str] = []
    drive = Drive(
        program,
        config,
        on_message=lambda msg: got.append(msg.text.rstrip()),
        on_fault=lambda text: got.append(text),
    )
    for name, v in inputs.items():
        drive.set_input(name, v)
    for name, v in writes:
        drive.write(name, v)  # type: ignore[arg-type]
    for label in starts:
        if label == "top":
            drive.start_top(next(t.id for t in drive.tasks if t.gen is None))
        else:
            drive.start(label)
    drive.run(until)
    return got, expected


def _matches(got: str, want: str) -> bool:
    if want.startswith("ERROR ..."):
        return " runtime error in task " in got and got.endswith(want[len("ERROR ...") :])
    return got == want


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_program_prints_what_it_expects(path: Path) -> None:
    got, expected = run_program(path)
    assert expected, "no expectations in the file"
    assert len(got) == len(expected) and all(map(_matches, got, expected)), (
        "\n".join(f"got:  {g}" for g in got) + "\n" + "\n".join(f"want: {w}" for w in expected)
    )
