"""Filters and compensation in a whole run: the scope channels of 14.1 and the status
bits of 5.1.1.5, and time skipping that gives the same output as stepping."""

from __future__ import annotations

import contextlib
import io

import pytest

from motionvm.api import Simulation
from motionvm.cli import main

COMP_AND_SHAPER = """
void main() {
    double data[3] = {0.2, -0.1, 0.3};
    SetUserTable(10, 3, data);
    SetupComp(0, 10, 0, 50, 3, 1);
    EnableComp(0);
    SetAxisInShape(1, 12.5, 0.05, SHAPER_ROBUST);
    EnableAxisInShape(1);
    SetAxisVsf(2, 30, 1.0);
    EnableAxisVsf(2);
    Enable(0); Enable(1); Enable(2);
    Till(IsEnabled(0) && IsEnabled(1) && IsEnabled(2));
    Sleep(500);
    MoveAbs(1, 80); MoveAbs(2, 5);
    Till(IsInPos(1) && IsInPos(0) && IsInPos(2));
    Print("comp %.4f out %.4f", GetCompPos(0), GetPosOut(0));
    Sleep(2000);
    MoveRel(1, -55);
    Till(IsInPos(1) && IsInPos(0));
    Print("comp %.4f fb %.4f fb+comp %.4f", GetCompPos(0), GetPosFb(0), GetPosFbComp(0));
}
"""


def cli(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def test_the_scope_shows_reference_plus_compensation_as_position_output():
    with Simulation.from_source(COMP_AND_SHAPER) as sim:
        rec = sim.scope(
            ["axis0.ref_pos", "axis0.comp_pos_set", "axis0.pos_out", "axis0.pos_comp",
             "axis1.ref_pos", "axis1.motion_status", "axis2.motion_status"]
        )  # fmt: skip
        assert sim.run(timeout=10).reason == "finished"
        data = rec.as_dict()
    comp = data["axis0.comp_pos_set"]
    assert comp[0] == 0.0  # not sent before the axis is enabled
    assert max(comp) == pytest.approx(0.2, abs=1e-12)  # x = 0: the first point
    assert any(c == pytest.approx(0.14, abs=1e-12) for c in comp)  # x = 80: 0.3*.6 - 0.1*.4
    assert comp[-1] == pytest.approx(0.05, abs=1e-12)  # x = 25: the mean of 0.2 and -0.1
    for ref, c, out, pos_comp in zip(
        data["axis0.ref_pos"], comp, data["axis0.pos_out"], data["axis0.pos_comp"]
    ):
        assert out == pytest.approx(ref + c, abs=1e-12) and pos_comp == out
    assert all(int(s) & (1 << 6) for s in data["axis1.motion_status"])  # Input Shape
    assert not any(int(s) & (1 << 7) for s in data["axis1.motion_status"])
    assert all(int(s) & (1 << 7) for s in data["axis2.motion_status"])  # VSF
    assert data["axis1.ref_pos"][-1] == 25.0


def test_skipping_idle_cycles_gives_the_same_output_as_stepping(tmp_path, monkeypatch):
    prog = tmp_path / "filters.hmpl"
    prog.write_text(COMP_AND_SHAPER, encoding="utf-8")
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    jumped = cli("run", prog, "--stamp")
    stepped = cli("run", prog, "--stamp", "--no-skip")
    assert jumped == stepped and jumped[0] == 0
    assert jumped[1].splitlines()[0].endswith("comp 0.1400 out 0.1400")
    assert jumped[1].splitlines()[1].endswith("comp 0.0500 fb 0.0000 fb+comp 0.0500")
