"""The axis cycle's fast path (`AxisCycle.step`'s plain cycle) against the general one.

Two machines get the same seeded commands: the default axes, which take the plain
cycle whenever it applies, and axes whose drives check a following-error window no
error reaches (0x7FFFFFFF counts), which keeps every cycle on the general path
(`_step_general`: the profile generator and the drive step themselves) with the same
results. After every cycle every axis and its drive must read the same, value for
value; a spy on `_step_general` shows which path each machine took (pure Python only:
the compiled build calls it in C).
"""

from __future__ import annotations

import random

import pytest

from motionvm import compiled_build
from motionvm.drives.objects import wrap_i32
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.kernel import MotionKernel

DT = 0.001
NO_ERROR_REACHES = 0x7FFFFFFF
"""A following-error window [counts] no int32 error exceeds but -2**31: checked, never hit."""


def observed(a: Axis) -> tuple:
    d = a.drive
    m = d.mechanics
    return (a.ref_pos, a.ref_vel, a.ref_acc, a.pos_fb, a.pos_fb_raw, a.moving, a.in_pos,
            a.enabled, a.fault_status, a.last_error, a.error_stop, a.move_time_ms,
            a.settling_time_ms, a.resting, d.state, d.statusword, d.controlword,
            d.target_position, d.position_actual, d.position_demand, d.following_error,
            d.velocity_actual, d.torque_actual, d.digital_inputs, m.position, m.velocity,
            m.torque, a.pg.output, a.pg.mode)  # fmt: skip


def machines(configs: list[dict]) -> tuple[MotionKernel, MotionKernel]:
    """(plain, general): the axes of `configs`, and the same with the window checked."""
    general = []
    for c in configs:
        drive = dict(c.get("drive", {}))
        drive["following_error_window"] = NO_ERROR_REACHES
        general.append({**c, "drive": drive})
    return (MotionKernel([create(c) for c in configs], DT),
            MotionKernel([create(c) for c in general], DT))  # fmt: skip


def command(a: Axis, rng: random.Random) -> None:
    """A random command for axis `a` (refused ones are part of the test too)."""
    kind = rng.random()
    try:
        if kind < 0.5:
            a.move_abs(rng.uniform(-900.0, 900.0))
        elif kind < 0.65:
            a.move_vel(rng.choice((-1.0, 1.0)) * rng.uniform(50.0, 900.0))
        elif kind < 0.75:
            a.stop()
        elif kind < 0.82:
            a.move_rel(rng.uniform(-50.0, 50.0))
        elif kind < 0.88:
            a.reset()
            a.enable()
        elif kind < 0.92:
            a.set_smooth_time(rng.choice((0.0, 5.0, 20.0)))
        else:
            a.enable()
    except AxisCommandError:
        pass


def test_plain_and_general_paths_give_the_same_cycles(monkeypatch):
    calls: dict[tuple[bool, int], int] = {}  # (general machine, axis id): cycles
    general_ids: set[int] = set()
    step_general = Axis._step_general

    def spy(self, drive):
        key = (id(self) in general_ids, self.axis_id)
        calls[key] = calls.get(key, 0) + 1
        return step_general(self, drive)

    monkeypatch.setattr(Axis, "_step_general", spy)
    configs = [
        {},  # the default axis
        {"sw_left": -2000.0, "sw_right": 2000.0},  # jogs end on the limit switches
        {"sw_left": -300.0, "sw_right": 300.0},  # jogs end on the software limits
        {
            "counts_per_unit": 3_000_000.0,
            "sw_left": -900.0,
            "sw_right": 900.0,
            "index_spacing": 0.5,
        },  # int32 targets and counts wrap  # fmt: skip
        {"drive": {"mechanics": {"model": "servo", "bandwidth": 15.0}}, "max_pos_err": 5.0},
        {"drive": {"mechanics": {"model": "ideal", "delay_cycles": 3}}},
        {"smooth_time_ms": 10.0, "max_vel": 400.0, "max_acc": 3000.0},
    ]
    plain, general = machines(configs)
    general_ids.update(id(a) for a in general.axes)
    rng_p, rng_g = random.Random(31), random.Random(31)
    for k in (plain, general):
        for a in k.axes:
            a.enable()
    n_cycles = 6000
    for cycle in range(n_cycles):
        for k, rng in ((plain, rng_p), (general, rng_g)):
            for a in k.axes:
                if rng.random() < 0.002 or (a.in_pos and rng.random() < 0.05):
                    command(a, rng)
            k.begin_cycle()
            k.step()
        for a, b in zip(plain.axes, general.axes, strict=True):
            assert observed(a) == observed(b), f"axis {a.axis_id} differs at cycle {cycle}"
    if compiled_build.STATUS == "compiled":
        pytest.skip("the compiled build calls _step_general in C: no spy sees it")
    for a in general.axes:  # every cycle it stepped (a resting axis does not step)
        assert calls[True, a.axis_id] > n_cycles // 2
    for a in plain.axes:  # the cycles of the enable sequence only, unless disabled since
        assert calls[False, a.axis_id] <= 10 or not a.enabled
    assert sum(not a.enabled for a in plain.axes) <= 1  # (the position error fault)


def test_a_default_axis_takes_the_plain_path(monkeypatch):
    """Moving and at rest, a default axis steps without `_step_general` once enabled."""
    calls = []
    step_general = Axis._step_general
    monkeypatch.setattr(
        Axis, "_step_general", lambda self, d: calls.append(1) or step_general(self, d)
    )
    k = MotionKernel([create({})], DT)
    a = k.axes[0]
    a.enable()
    while not a.enabled:
        k.step()
    k.step()  # the drive's first common cycle sets it up for the next ones
    calls.clear()
    a.move_abs(100.0)
    for _ in range(200):
        k.step()
    assert a.moving
    if compiled_build.STATUS == "compiled":
        pytest.skip("the compiled build calls _step_general in C: no spy sees it")
    assert calls == []


def test_the_cycle_rounds_and_wraps_as_python():
    """The counts of every cycle are Python's round (half to even) and int32 wrap of the
    positions (the compiled build computes them in C: rint, long long arithmetic): at
    exact ties, and on a jog whose targets and counts wrap the int32 range."""
    ties = [{"counts_per_unit": 4.0, "start_position": s} for s in (0.625, 0.875, -0.625)]
    wraps = {"counts_per_unit": 3_000_000.0, "sw_left": -900.0, "sw_right": 900.0}
    k = MotionKernel([create(c) for c in ties + [wraps]], DT)

    def check(targets: bool = True) -> None:
        for a in k.axes:
            d = a.drive
            assert d.position_actual == wrap_i32(round(d.mechanics.position))
            if targets:  # (the cycle that enables an axis sets its reference after them)
                counts = round((a.ref_pos + a.slave_offset) * a.cpu)
                assert d.target_position == wrap_i32(counts)

    for a in k.axes:
        a.enable()
    assert [a.drive.position_actual for a in k.axes[:3]] == [2, 4, -2]  # 2.5, 3.5, -2.5
    for _ in range(20):  # the enable sequence
        k.step()
        check(targets=False)
    assert all(a.enabled for a in k.axes)
    for a, offset in zip(k.axes[:3], (0.125, 0.375, -0.125), strict=True):
        a.pos_offset = offset  # targets on half counts: (p + offset) * 4 = n + 0.5
        a.wake()
    k.step()
    check()
    assert [a.drive.target_position for a in k.axes[:3]] == [2, 6, -2]  # 2.5, 5.5, -2.5
    jog = k.axes[3]
    jog.move_vel(900.0)  # 2.7e9 counts/s: the int32 target wraps within a second
    wrapped = False
    for _ in range(1500):
        k.step()
        check()
        wrapped = wrapped or jog.drive.target_position < 0 < jog.ref_pos
    assert wrapped
