"""A closed-form advance leaves an axis exactly as stepping it does: every field of the
axis, its generator, drive, motor and sensors (their cached switch bands aside), bit for
bit, in every phase of a move: on the T-curve, past its end while region I ends, while
the axis settles into position and where it comes into position.

Two axes built alike get the same commands; one is advanced by `coast` as far as
`coast_cycles` allows (or a random part of that, with or without going past the cycle
in which region I ends), the other stepped as many cycles; after each advance their
states are compared. The machines vary what the closed forms depend on: motor delay,
counts per mm, cycle time, in-position radius and debounce time, smoothing, position
offset, limits that make short moves triangular.
"""

from __future__ import annotations

import enum
import os
import types
from collections import deque

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.drives.objects import DI_HOME_SWITCH
from motionvm.motion.axis import Axis
from motionvm.motion.axis_coast import coast, coast_cycles
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError

settings.register_profile("coast-ci", max_examples=40, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("coast-thorough", max_examples=600, derandomize=True,
                          deadline=None, suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("coast-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

_CACHES = frozenset({
    "quiet_low", "quiet_high", "quiet_inputs", "_switch_low", "_switch_high",
    "_switch_external", "_switch_inputs", "_index_low", "_index_high", "_index_n",
})  # fmt: skip
"""The sensors' cached bands: which positions computed them differs, never what they
answer (the drive skips the sensors inside them)."""


def state(obj, seen: set | None = None):
    """Every value reachable from `obj` through the package's objects, floats by their
    bits."""
    if isinstance(obj, float):
        return obj.hex()
    if obj is None or isinstance(obj, (bool, int, str, enum.Enum)):
        return obj
    if isinstance(obj, (list, tuple, deque)):
        return tuple(state(x, seen) for x in obj)
    if isinstance(obj, dict):
        return tuple(sorted((str(k), state(v, seen)) for k, v in obj.items()))
    if isinstance(obj, (types.MethodType, types.FunctionType, types.BuiltinFunctionType)):
        return "function"
    if not type(obj).__module__.startswith("motionvm"):
        return type(obj).__name__
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return "seen"
    seen.add(id(obj))
    names = set(getattr(obj, "__dict__", ()))
    for cls in type(obj).__mro__:
        names.update(n for n in getattr(cls, "__slots__", ()) if n != "__weakref__")
    return type(obj).__name__, tuple(
        (n, state(getattr(obj, n), seen)) for n in sorted(names - _CACHES) if hasattr(obj, n)
    )


def _axis(config: dict, dt: float, offset: float) -> Axis:
    a = Axis(0, create(config), dt)
    a.enable()
    for _ in range(40):
        a.step()
    assert a.enabled and a.in_pos
    if offset:
        a.set_pos(a.ref_pos + offset)
        for _ in range(10):
            a.step()
    return a


machine = st.fixed_dictionaries({
    "delay": st.sampled_from([0, 1, 1, 2, 4]),
    "counts_per_unit": st.sampled_from([10000.0, 1000.0, 364.0888, 3.0]),
    "inpos_radius": st.sampled_from([1e-9, 1e-4, 0.01, 0.01, 2.0]),
    "inpos_debounce_ms": st.sampled_from([0.0, 1.0, 1.0, 2.0, 7.0]),
    "smooth_time_ms": st.sampled_from([0.0, 0.0, 0.0, 3.0]),
    "max_vel": st.sampled_from([1000.0, 37.0]),
    "max_acc": st.sampled_from([10000.0, 123.0]),
    "max_pos_err": st.sampled_from([10.0, 0.8]),
})  # fmt: skip
targets = st.lists(
    st.one_of(st.floats(-60.0, 60.0), st.sampled_from([0.0, 1e-6, 0.00012, 5.0, 100.0])),
    min_size=1, max_size=3,
)  # fmt: skip
wanted = st.lists(st.sampled_from([1, 2, 3, 5, 17, 5000]), max_size=5).map(
    lambda asks: [*asks, 5000]
)
"""How many cycles each advance asks for, in turn (at last as many as it may)."""


@PROFILE
@given(machine, st.sampled_from([0.001, 0.0005]), st.sampled_from([0.0, 12.345]), targets,
       wanted, st.lists(st.booleans(), min_size=1, max_size=4))  # fmt: skip
def test_a_coasting_axis_ends_as_a_stepped_one(spec, dt, offset, moves, asks, pasts):
    config = {k: v for k, v in spec.items() if k != "delay"}
    config["drive"] = {"mechanics": {"model": "ideal", "delay_cycles": spec["delay"]}}
    coasted, stepped = _axis(config, dt, offset), _axis(config, dt, offset)
    assert state(coasted) == state(stepped)
    for target in moves:
        for a in (coasted, stepped):
            try:
                a.move_abs(target)
            except AxisCommandError:  # after a position error: in error stop
                pass
        cycles = i = 0
        while not coasted.resting and cycles < 6000:
            ask = asks[i % len(asks)]
            memo = {} if i % 2 else None  # what the horizon found, reused (the kernel's way)
            k = coast_cycles(coasted, ask, pasts[i % len(pasts)], memo)
            assert 0 <= k <= ask
            if k:
                coast(coasted, k, memo)
                for _ in range(k):
                    stepped.step()
            else:
                coasted.step()
                stepped.step()
            assert state(coasted) == state(stepped), (target, i, k)
            cycles += max(k, 1)
            i += 1


def test_an_advance_runs_through_the_end_of_a_move_to_the_in_position_cycle():
    # 100 mm at 1000 mm/s, 10000 mm/s^2 (0.2 s), 1 cycle of motor delay, 1 ms debounce:
    # region I ends 1 cycle after the T-curve, the axis is in position 1 cycle later
    config = {"drive": {"mechanics": {"model": "ideal", "delay_cycles": 1}}}
    a = _axis(config, 0.001, 0.0)
    a.move_abs(100.0)
    a.step()
    to_end = coast_cycles(a, 1 << 30)
    through = coast_cycles(a, 1 << 30, past_moving=True)
    assert through == to_end + 1
    coast(a, through)
    assert a.in_pos and not a.moving and a.move_time_ms == 200.0


def _coast_to_rest(coasted: Axis, stepped: Axis) -> None:
    """Advance `coasted` as far as it may at a time and step `stepped` alike, until the
    coasted one rests; their states must agree after each advance."""
    for _ in range(6000):
        if coasted.resting:
            return
        k = coast_cycles(coasted, 5000, True)
        if k:
            coast(coasted, k)
        else:
            coasted.step()
        for _ in range(max(k, 1)):
            stepped.step()
        assert state(coasted) == state(stepped)
    raise AssertionError("the axis never came to rest")


def test_a_home_switch_moved_inside_a_switch_band_is_seen_coasting_and_stepping():
    # the axis rests at 100 mm, inside the band (5, 1050) mm between the home switch's
    # high end and the positive limit; the home switch moves to [150, 160] mm, within
    # that band, and the axis moves onto it: both must see it (no stale band)
    config = {"drive": {"mechanics": {"model": "ideal", "delay_cycles": 1}}}
    coasted, stepped = _axis(config, 0.001, 0.0), _axis(config, 0.001, 0.0)
    for target, home in ((100.0, False), (155.0, True), (100.0, False)):
        if target == 155.0:
            for a in (coasted, stepped):
                a.drive.sensors.home_low = 150.0 * a.cpu
                a.drive.sensors.home_high = 160.0 * a.cpu
        for a in (coasted, stepped):
            a.move_abs(target)
        _coast_to_rest(coasted, stepped)
        for a in (coasted, stepped):
            assert a.in_pos and bool(a.drive.digital_inputs & DI_HOME_SWITCH) == home
