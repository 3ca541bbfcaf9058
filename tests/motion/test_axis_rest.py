"""Resting axes: the motion kernel does not step them, and what could change them wakes them.

A resting axis costs the kernel one flag test per cycle. Its step would give the same
values, so resting must change no result: a kernel run is compared, cycle by cycle, with
the same axes stepped every cycle regardless of rest, under a random script of commands
and of writes to the drives from outside the cycle (object dictionary writes and
forcing, injected faults, the sensors' external inputs and switches, the touch probe
function). A missed wake-up would let the kernel's copy fall behind.
"""

from __future__ import annotations

import random

import pytest

from motionvm.drives import objects as od
from motionvm.drives.dictionary import SdoAbort
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.kernel import MotionKernel

DT = 0.001
CONFIG = {"hw_left": -50.0, "hw_right": 50.0, "home_pos": 0.0, "home_width": 2.0}


def kernel(n: int = 2) -> MotionKernel:
    k = MotionKernel([create(dict(CONFIG)) for _ in range(n)], DT)
    for a in k.axes:
        a.enable()
    return k


def run_until_rest(k: MotionKernel, limit: int = 2_000) -> None:
    for _ in range(limit):
        k.step()
        if all(a.resting for a in k.axes):
            return
    raise AssertionError("the axes did not come to rest")


def state(k: MotionKernel) -> tuple:
    return tuple(
        (a.pos_fb.hex(), a.ref_pos.hex(), a.enabled, a.moving, a.in_pos, a.error_stop,
         a.last_error, a.drive.statusword, a.drive.position_actual, a.drive.digital_inputs,
         a.drive.error_code, a.drive.tp_status)
        for a in k.axes
    )  # fmt: skip


def test_the_kernel_does_not_step_a_resting_axis():
    k = kernel()
    run_until_rest(k)
    cycles = [a._cycle for a in k.axes]
    for _ in range(50):
        k.step()
    assert [a._cycle for a in k.axes] == cycles


@pytest.mark.parametrize(
    "write",
    [
        lambda a: a.drive.objects.write(0x607A, 0, a.drive.target_position + 1000),
        lambda a: a.drive.objects.force(0x607A, 0, 1000),
        lambda a: a.drive.inject_fault(0x7500),
        lambda a: setattr(a.drive.sensors, "external", od.DI_POSITIVE_LIMIT),
        lambda a: setattr(a.drive, "tp_function", 0x0001),
        lambda a: setattr(a.drive.sensors, "home_low", 500_000.0),
    ],
    ids=["sdo", "force", "fault", "external", "tp_function", "switch"],
)
def test_a_write_to_the_drive_wakes_its_axis_and_the_next_cycle_sees_it(write):
    k = kernel()
    run_until_rest(k)
    a, other = k.axes
    write(a)
    assert not a.resting and other.resting
    before = a._cycle
    k.step()
    assert a._cycle == before + 1


def _event(rnd: random.Random, a) -> None:
    kind = rnd.choice(["move", "move", "sdo", "force", "release", "fault", "reset",
                       "external", "clear", "probe", "switch"])  # fmt: skip
    d = a.drive
    try:
        if kind == "move":
            a.move_abs(rnd.uniform(-60.0, 60.0))
        elif kind == "sdo":
            d.objects.write(0x607A, 0, d.target_position + rnd.randrange(-5000, 5000))
        elif kind == "force":
            d.objects.force(0x607A, 0, d.target_position + rnd.randrange(-5000, 5000))
        elif kind == "release":
            d.objects.release(0x607A, 0)
        elif kind == "fault":
            d.inject_fault(0x7500)
        elif kind == "reset":
            a.reset()
            a.enable()
        elif kind == "external":
            d.sensors.external = rnd.choice([od.DI_POSITIVE_LIMIT, od.DI_NEGATIVE_LIMIT])
        elif kind == "clear":
            d.sensors.external = 0
        elif kind == "switch":  # the home switch moves onto or off the axis [counts]
            low = rnd.choice([-10_000.0, a.drive.position_actual - 5.0, 400_000.0])
            d.sensors.home_low, d.sensors.home_high = low, low + 20_000.0
        else:
            d.tp_function = rnd.choice([0, 0x0001, 0x0003])
    except (AxisCommandError, SdoAbort):
        pass


@pytest.mark.parametrize("seed", range(6))
def test_resting_changes_no_result_under_outside_writes(seed):
    """The kernel (resting axes skipped) against the same axes stepped every cycle."""
    resting, stepped = kernel(), kernel()
    rnd_a, rnd_b = random.Random(seed), random.Random(seed)
    rested = 0
    for cycle in range(3_000):
        if cycle % 97 == 0:
            for k, rnd in ((resting, rnd_a), (stepped, rnd_b)):
                for a in k.axes:
                    if rnd.random() < 0.6:
                        _event(rnd, a)
        resting.step()
        for a in stepped.axes:
            a.step()
        rested += sum(a.resting for a in resting.axes)
        assert state(resting) == state(stepped), cycle
    assert rested > 500  # the kernel did skip resting axes
