"""Property: a wire delivers every change of its output exactly 1 + ceil(delay / cycle)
cycles later, in order, for any cycle time, delay and pattern of changes; stepping and
jumping the clock give the same input history."""

from __future__ import annotations

import math
import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.io.config import IOConfig, WireSpec, parse_endpoint
from motionvm.sim.controller import Controller
from motionvm.sim.machine import MachineConfig, default_axes

settings.register_profile("io-ci", max_examples=40, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("io-thorough", max_examples=400, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("io-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def controller(cycle_time: float, delay_ms: float) -> Controller:
    wire = WireSpec(parse_endpoint("gpo3"), parse_endpoint("gpi4"), delay_ms)
    machine = MachineConfig(cycle_time=cycle_time, axes=default_axes(1), io=IOConfig(wires=(wire,)))
    return Controller(cycle_time, machine=machine)


def history(ctl: Controller, changes: dict[int, int], n: int, jump: bool) -> list[int]:
    """The input read at the start of each cycle 0..n-1 (after the I/O latch), with the
    output written in the cycles of `changes`; `jump`: skip the cycles where nothing
    is due, as the controller's time skipping does (the input holds meanwhile)."""
    gpio = ctl.io.gpio
    out = []
    while ctl.cycle < n:
        if jump and ctl.cycle not in changes:
            wake = ctl.io.next_event()
            nxt = min([c for c in changes if c > ctl.cycle] + [n])
            target = nxt if wake is None else min(wake, nxt)
            if target > ctl.cycle:
                out += [gpio.input(4)] * (target - ctl.cycle)
                ctl.clock.cycle = target
                continue
        ctl.io.begin_cycle()
        out.append(gpio.input(4))
        if ctl.cycle in changes:
            gpio.set_output(3, changes[ctl.cycle])
        ctl.io.end_cycle()
        ctl.clock.cycle += 1
    return out


@PROFILE
@given(
    st.sampled_from([0.00025, 0.0005, 0.001, 0.002]),
    st.floats(0.0, 30.0),
    st.dictionaries(st.integers(0, 150), st.integers(0, 1), max_size=12),
)
def test_delivered_exactly_and_in_order(cycle_time, delay_ms, changes):
    n = 220
    d = math.ceil(delay_ms / (cycle_time * 1000.0) - 1e-9)
    expected, level = [], 0
    for k in range(n):  # the input at cycle k shows the output after cycle k - 1 - d
        src = k - 1 - d
        if src in changes:
            level = changes[src]
        expected.append(level)
    assert history(controller(cycle_time, delay_ms), changes, n, jump=False) == expected
    assert history(controller(cycle_time, delay_ms), changes, n, jump=True) == expected
