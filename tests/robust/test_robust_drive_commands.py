"""Drive objects, controller variables, filters and compensation driven by a careless
program: random sequences of their commands with ids, indexes, lengths and values out
of every range, between moves. Each returns a code; positions stay finite; a length
that lies allocates nothing (WriteSDO with obj_length 2**31 - 1 allocated 2 GB)."""

from __future__ import annotations

import inspect
import math
import os
import tracemalloc

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.motion.commands import MotionCommands
from motionvm.motion.config_vars import manual_ids
from motionvm.sim.controller import Controller

settings.register_profile(
    "drive-cmd-robust-ci", max_examples=40, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "drive-cmd-robust-thorough", max_examples=500, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "drive-cmd-robust-thorough"
    if os.environ.get("HYPOTHESIS_PROFILE") == "thorough"
    else "drive-cmd-robust-ci"
)

ABORT_LENGTH = 0x06070010
COMMANDS = [
    "SetCompAlgType", "EnableComp", "DisableComp", "GetCompPos", "GetPosFbComp", "IsCompActive",
    "EnableAxisVsf", "DisableAxisVsf", "SetAxisVsf", "EnableAxisInShape", "DisableAxisInShape",
    "SetAxisInShape", "ReadSDO", "WriteSDO", "ReadPDO", "WritePDO", "ForceWritePDO",
    "ReleasePDO", "GetConfigVar", "SetConfigVar", "MoveAbs", "MoveRel", "MoveVel", "Stop",
    "Enable", "Disable", "SetHomedStatus", "SetVel", "SetAcc", "SetDec", "SetOpMode",
]  # fmt: skip
HCV_IDS = sorted(c << 24 | v for c, rows in manual_ids().items() for v, _ in rows)
FLOATS = st.sampled_from([0.0, -1.0, 1.0, 5.0, 1e-4, 1e-9, 1e9, -1e9, 1e12, 1e308, -1e308,
                          math.inf, -math.inf, math.nan, 0.5, 100.0])  # fmt: skip
INTS = st.sampled_from([0, 1, -1, 2, 3, 8, 9, 10, 255, 256, 65535, 2**31 - 1, -(2**31), 0x6040,
                        0x6060, 0x607A, 0x60FE, 0x6064, 0x60FF, 0x6071, 0x1A00, 0x1600, 0x1018])  # fmt: skip
IDS = st.sampled_from([0, 0, 0, 1, -1, 7, 64])


def _argument(name: str, param: inspect.Parameter):
    if param.name in ("axis_id", "slv_id", "group_id"):
        return IDS
    if param.name == "hcv_id":
        return st.one_of(st.sampled_from(HCV_IDS), INTS)
    return FLOATS if "float" in str(param.annotation) else INTS


def _call(name: str):
    params = inspect.signature(getattr(MotionCommands, name)).parameters.values()
    args = [_argument(name, p) for p in params if p.name != "self"]
    return st.tuples(st.just(name), *args)


CALL = st.one_of([_call(n) for n in COMMANDS])


def rig() -> tuple[Controller, MotionCommands]:
    ctl = Controller()
    m = MotionCommands(ctl.motion)
    m.Enable(0)
    m.Enable(1)
    for _ in range(30):
        ctl.step()
    return ctl, m


@PROFILE
@given(calls=st.lists(st.tuples(CALL, st.sampled_from([0, 1, 10, 200])), max_size=25))
def test_any_sequence_returns_codes_and_keeps_positions_finite(calls):
    ctl, m = rig()
    for (name, *args), cycles in calls:
        getattr(m, name)(*args)
        for _ in range(cycles):
            ctl.step()
        for axis in ctl.axes:
            assert math.isfinite(axis.pos_fb) and math.isfinite(axis.ref_pos), (name, args)


def test_a_write_sdo_length_that_lies_allocates_nothing():
    _ctl, m = rig()
    tracemalloc.start()
    try:
        assert m.WriteSDO(0, 0x6040, 0, 2**31 - 1, 6) == -1
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 100_000, peak
    assert m.GetSystemLastErr() & 0xFFFFFFFF == ABORT_LENGTH
