"""GDL axis models: the stand-in and the profile-generator adapter honour one contract."""

from __future__ import annotations

from itertools import pairwise

import pytest

from motionvm.lang.gdl.axis import Axis, ProfileAxis, TrapezoidAxis

DT = 0.001
P_TOL = 1e-6


def _run(axis: Axis, cycles: int) -> list[tuple[float, float]]:
    out = []
    for _ in range(cycles):
        axis.step(DT)
        out.append((axis.position, axis.velocity))
    return out


@pytest.mark.parametrize("make", [TrapezoidAxis, ProfileAxis])
def test_gdl_axis_move_reaches_target_within_limits(make: type) -> None:
    axis = make()
    axis.move_to(500.0, 2000.0, 20000.0)
    assert axis.busy and axis.transient
    trace = _run(axis, 1000)
    assert not axis.busy and not axis.transient
    assert abs(axis.position - 500.0) < P_TOL and axis.velocity == 0.0
    assert max(abs(v) for _, v in trace) <= 2000.0 + 1e-6
    # Velocity and acceleration as backward differences of the position, cycle by cycle.
    positions = [0.0] + [p for p, _ in trace] + [trace[-1][0]]
    speeds = [(b - a) / DT for a, b in pairwise(positions)]
    assert max(abs(v) for v in speeds) <= 2000.0 * (1 + 1e-6)
    assert max(abs(b - a) / DT for a, b in pairwise(speeds)) <= 20000.0 * (1 + 1e-6)


@pytest.mark.parametrize("make", [TrapezoidAxis, ProfileAxis])
def test_gdl_axis_jog_is_steady_then_stops(make: type) -> None:
    axis = make()
    axis.run_at(800.0, 10000.0)
    _run(axis, 200)
    assert axis.busy and not axis.transient
    assert abs(axis.velocity - 800.0) < 1e-6
    axis.stop(10000.0)
    assert axis.transient
    _run(axis, 200)
    assert not axis.busy and axis.velocity == 0.0


@pytest.mark.parametrize("make", [TrapezoidAxis, ProfileAxis])
def test_gdl_axis_halt_cuts_at_once(make: type) -> None:
    axis = make()
    axis.run_at(-500.0, 50000.0)
    _run(axis, 50)
    where = axis.position
    axis.halt()
    assert not axis.busy and axis.velocity == 0.0
    _run(axis, 10)
    assert axis.position == where
