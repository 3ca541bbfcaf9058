"""The manual's time-out loops (§2.2.11) across the wrap of `fclk` from 2^31 - 1 to -2^31.

A run of `motionvm run` starts `fclk` at 0, 39 hours of drive time before the wrap, so
these programs (fclk_wrap/) run on one drive whose `fclk` starts just before it
(`DriveConfig.fclk_start`, a parameter no machine file sets). Their expectations are
`// expect:` lines, read by the case model of `motionvm test` (`motionvm.cli.cases`);
the printed lines must be exactly those, and the drive must report no fault.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.cli.cases import expectations_of
from motionvm.lang.pdl.drive_axis import AxisConfig
from motionvm.lang.pdl.drive_rt import Drive, DriveConfig
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source import DiagnosticSink, render_diagnostic

PROGRAMS = Path(__file__).parent / "fclk_wrap"
RUN_S = 10.0
"""Drive time each program runs [s]."""
CONFIGS = {
    "w26_tout_v1_wrap.pdl": DriveConfig(fclk_start=2147483000),
    "w26_tout_v2_found.pdl": DriveConfig(
        fclk_start=2147480000, axis=AxisConfig(home_position=1333)
    ),
    "w26_tout_v3_wrap.pdl": DriveConfig(fclk_start=2147483000),
}


def test_every_program_has_its_configuration() -> None:
    assert sorted(p.name for p in PROGRAMS.glob("*.pdl")) == sorted(CONFIGS)


@pytest.mark.parametrize("name", sorted(CONFIGS))
def test_program_prints_what_it_expects(name: str) -> None:
    path = PROGRAMS / name
    found = expectations_of(path)
    assert found is not None, f"{name} has no expectations"
    exp = found[0]
    assert exp.stdout and all(kind == "text" for kind, _ in exp.stdout)
    sink = DiagnosticSink()
    program = compile_pdl(str(path), sink=sink)
    assert program is not None, "\n".join(render_diagnostic(d) for d in sink.items)
    printed: list[str] = []
    faults: list[str] = []
    drive = Drive(
        program,
        CONFIGS[name],
        on_message=lambda msg: printed.append(msg.text),
        on_fault=faults.append,
    )
    drive.run(RUN_S)
    assert faults == []
    assert printed == [line for _, line in exp.stdout]
