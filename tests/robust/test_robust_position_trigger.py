"""Position trigger commands in any order with any values, from a careless program: each
returns 0 or the manual's error code, and an armed train takes memory independent of
its length (an equal-interval train was a list of every position: start -1e9, end 1e9,
interval 1 um filled the machine's memory)."""

from __future__ import annotations

import math
import os
import tracemalloc

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.io.trigger_commands import TriggerCommands
from motionvm.motion.commands import MotionCommands
from motionvm.sim.controller import Controller

settings.register_profile(
    "pt-robust-ci", max_examples=40, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "pt-robust-thorough", max_examples=500, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "pt-robust-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "pt-robust-ci"
)


def homed_rig() -> tuple[Controller, MotionCommands, TriggerCommands]:
    ctl = Controller()
    m = MotionCommands(ctl.motion)
    m.Enable(0)
    for _ in range(100):  # bounded: the drive enables within a few cycles
        if m.IsEnabled(0):
            break
        ctl.step()
    m.SetHomedStatus(0, 1)
    return ctl, m, TriggerCommands(ctl.motion, ctl.triggers)


def test_a_train_of_two_million_positions_is_armed_without_listing_them():
    ctl, m, pt = homed_rig()
    assert pt.SetPT_StartPos(0, -1000.0) == pt.SetPT_EndPos(0, 1000.0) == 0
    assert pt.SetPT_Interval(0, 0.001) == 0
    assert m.SetVel(0, 10.0) == 0  # below 0.001 mm x 16 kHz
    tracemalloc.start()
    try:
        assert pt.EnablePT(0) == 0
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000, peak
    assert m.MoveAbs(0, 0.0105) == 0
    for _ in range(2000):  # bounded: 2 s
        if m.IsInPos(0):
            break
        ctl.step()
    assert [round(p, 9) for _, p in ctl.triggers[0].pulses] == [
        round(k * 0.001, 9) for k in range(11)
    ]


INVALID_PARAMETER = 0x8300012C
"""eERR_AXIS_CMD_INVALID_PARAMETER of axis 0."""

VALUES = st.sampled_from(
    [0.0, -1.0, 1.0, 5.0, 25.0, 1e-4, 1e-6, 1e9, -1e9, 1e308, -1e308, math.inf, -math.inf,
     math.nan]
)  # fmt: skip
INDEXES = st.sampled_from([0, 1, -1, 2, 10, 255, 256, 4096, 2**31 - 1, -(2**31)])
AXES = st.sampled_from([0, 0, 0, 1, -1, 7])
COMMAND = st.one_of(
    st.tuples(st.sampled_from(["EnablePT", "DisablePT", "IsPTEnabled"]), AXES),
    st.tuples(st.sampled_from(["SetPT_StartPos", "SetPT_EndPos", "SetPT_Interval"]), AXES, VALUES),
    st.tuples(
        st.just("SetPT_PulseWidth"), AXES, st.sampled_from([0, 20, 1000, 80_000, 80_001, -20])
    ),
    st.tuples(st.just("SetPT_PosArray"), AXES, INDEXES, VALUES),
    st.tuples(st.sampled_from(["SetPT_StartIndex", "SetPT_EndIndex"]), AXES, INDEXES),
    st.tuples(st.just("SetPT_StateArray"), AXES, INDEXES, INDEXES),
    st.tuples(st.just("MoveAbs"), st.sampled_from([0.0, 10.0, 30.0, -20.0, 1e-3])),
    st.tuples(st.sampled_from(["Stop", "Disable", "Enable"])),
)


@PROFILE
@given(commands=st.lists(st.tuples(COMMAND, st.sampled_from([0, 1, 20, 300])), max_size=20))
def test_any_sequence_of_pt_commands_returns_codes_and_fires_at_finite_positions(commands):
    ctl, m, pt = homed_rig()
    for command, cycles in commands:
        name, *args = command
        if name in ("MoveAbs", "Stop", "Disable", "Enable"):
            getattr(m, name)(0, *args)
        else:
            assert isinstance(getattr(pt, name)(*args), int)
        for _ in range(cycles):
            ctl.step()
    assert all(math.isfinite(p) for _, p in ctl.triggers[0].pulses)


def test_a_train_longer_than_any_count_is_an_invalid_parameter():
    _ctl, _m, pt = homed_rig()
    assert pt.SetPT_StartPos(0, -1e308) == pt.SetPT_EndPos(0, 1e308) == 0
    assert pt.SetPT_Interval(0, 1e-300) == 0
    assert pt.EnablePT(0) & 0xFFFFFFFF == INVALID_PARAMETER
    assert pt.IsPTEnabled(0) == 0
