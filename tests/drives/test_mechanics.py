"""Tests of the drive mechanics models: ideal delay line and the servo loop."""

from __future__ import annotations

import math
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.drives.mechanics import IdealMechanics, ServoMechanics, create

DT = 0.001

settings.register_profile(
    "mechanics-ci", max_examples=60, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "mechanics-thorough", max_examples=1000, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile("mechanics-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def test_ideal_follows_after_exact_delay():
    m = create({"model": "ideal", "delay_cycles": 3})
    demands = [float(k * k) for k in range(1, 20)]
    actual = []
    for r in demands:
        m.step_position(r, DT)
        actual.append(m.position)
    assert actual[:3] == [0.0, 0.0, 0.0]
    assert actual[3:] == demands[:-3]


def test_ideal_without_delay_and_velocity_mode():
    m = create({"model": "ideal"})
    m.step_position(10.0, DT)
    assert (m.position, m.velocity) == (10.0, 10.0 / DT)
    for _ in range(10):
        m.step_velocity(1000.0, DT)
    assert m.position == pytest.approx(20.0) and m.velocity == pytest.approx(1000.0)


def test_ideal_torque_accelerates_the_inertia():
    m = IdealMechanics(inertia=1e-3, counts_per_rev=1000)
    for _ in range(100):
        m.step_torque(0.01, DT)  # 10 rad/s^2 = 10000/(2 pi) counts/s^2
    alpha = 0.01 / 1e-3 * 1000 / (2 * math.pi)
    # the velocity is the backward difference: the mean over the last cycle
    assert m.velocity == pytest.approx(alpha * (0.1 - DT / 2), rel=1e-9)
    assert m.position == pytest.approx(alpha * 0.1**2 / 2, rel=1e-9)


def servo(**kw):
    return ServoMechanics.create({"model": "servo", **kw})


def run_ramp(m, v, cycles):
    errors = []
    for k in range(1, cycles + 1):
        r = v * k * DT
        m.step_position(r, DT)
        errors.append(r - m.position)
    return errors


@pytest.mark.parametrize("bandwidth, damping", [(20.0, 0.7), (50.0, 1.0), (100.0, 0.5)])
def test_servo_ramp_following_error_is_2_zeta_v_over_wn(bandwidth, damping):
    m = servo(bandwidth=bandwidth, damping=damping)
    errors = run_ramp(m, 100_000.0, 2000)
    wn = 2 * math.pi * bandwidth
    assert errors[-1] == pytest.approx(2 * damping * 100_000.0 / wn, rel=1e-6)
    assert m.velocity == pytest.approx(100_000.0, rel=1e-6)


def test_servo_velocity_feedforward_removes_the_cruise_error():
    m = servo(bandwidth=50.0, damping=0.7, velocity_feedforward=1.0)
    errors = run_ramp(m, 100_000.0, 1000)
    assert abs(errors[-1]) < 1e-6
    assert max(abs(e) for e in errors) < 2 * 0.7 * 100_000.0 / (2 * math.pi * 50)


@pytest.mark.parametrize("damping", [0.5, 0.7, 1.0, 2.0])
def test_servo_step_settles_within_time_from_bandwidth(damping):
    bandwidth = 40.0
    wn = 2 * math.pi * bandwidth
    # 2 % settling: 4/(zeta wn) underdamped; 5.8/wn critically damped; the slow pole
    # governs when overdamped
    if damping < 1:
        t_settle = 4.0 / (damping * wn) * 1.25
    else:
        t_settle = 6.0 / (wn * (damping - math.sqrt(damping**2 - 1)))
    m = servo(bandwidth=bandwidth, damping=damping)
    trace = []
    for _ in range(int(1.0 / DT)):
        m.step_position(1000.0, DT)
        trace.append(m.position)
    late = trace[int(t_settle / DT) :]
    assert all(abs(1000.0 - x) <= 20.0 for x in late)
    overshoot = max(trace) - 1000.0
    if damping < 1:
        expected = 1000.0 * math.exp(-math.pi * damping / math.sqrt(1 - damping**2))
        assert overshoot == pytest.approx(expected, rel=0.1)
    else:
        assert overshoot <= 1e-6


def test_servo_is_stable_far_above_the_euler_limit():
    # wn*dt = 6.3: explicit Euler would explode; the exact discretization settles
    m = servo(bandwidth=1000.0, damping=0.7)
    for _ in range(100):
        m.step_position(500.0, DT)
    assert m.position == pytest.approx(500.0, abs=1e-6)


def _servo_rhs(t, x, v, r_0, r_1):
    """Continuous closed loop of the servo below: (x', v') [counts/s, counts/s^2]."""
    kv = 2 * 0.6 * 2 * math.pi * 30.0
    kp = 2 * math.pi * 30.0 / (2 * 0.6)
    load = 0.01 / (2e-4 * 2 * math.pi / (1 << 17))  # load torque as [counts/s^2]
    r = r_0 + (r_1 - r_0) * t / DT
    return v, kv * (kp * (r - x) - v) - (2e-4 / 2e-4) * v + load


def test_servo_cycle_equals_fine_integration():
    m = servo(bandwidth=30.0, damping=0.6, friction=2e-4, load_torque=0.01, inertia=2e-4)
    x, v, sub = 0.0, 0.0, 2000
    h = DT / sub
    for k in range(1, 51):
        r_0, r_1 = 300.0 * (k - 1) ** 2, 300.0 * k**2
        m.step_position(r_1, DT)
        for i in range(sub):  # midpoint (RK2) integration of the same continuous model
            t = i * h
            dx1, dv1 = _servo_rhs(t, x, v, r_0, r_1)
            dx2, dv2 = _servo_rhs(t + h / 2, x + dx1 * h / 2, v + dv1 * h / 2, r_0, r_1)
            x, v = x + dx2 * h, v + dv2 * h
        assert m.position == pytest.approx(x, rel=1e-6, abs=1e-3)
        assert m.velocity == pytest.approx(v, rel=1e-6, abs=1e-2)


def test_servo_torque_limit_bounds_the_acceleration():
    m = servo(bandwidth=100.0, damping=0.7, inertia=1e-4, max_torque=0.05, counts_per_rev=10_000)
    alpha_max = 0.05 / 1e-4 * 10_000 / (2 * math.pi)  # [counts/s^2]
    v_prev = 0.0
    for _ in range(200):
        m.step_position(1e6, DT)
        assert abs(m.torque) <= 0.05 + 1e-12
        assert abs(m.velocity - v_prev) <= alpha_max * DT * (1 + 1e-9)
        v_prev = m.velocity


def test_servo_velocity_and_torque_modes():
    m = servo(bandwidth=50.0, damping=0.7, friction=1e-4, inertia=1e-4, counts_per_rev=1000)
    for _ in range(500):
        m.step_velocity(2000.0, DT)
    assert m.velocity == pytest.approx(2000.0, rel=0.05)  # friction leaves a small droop
    for _ in range(3000):
        m.step_free(DT)
    assert abs(m.velocity) < 2000.0 * math.exp(-1.0 * 3.0) * 1.01  # decays with b/J = 1/s
    for _ in range(100):
        m.step_torque(0.0, DT)
    assert m.torque == 0.0


@pytest.mark.parametrize(
    "config, message",
    [
        ({"model": "stepper"}, "model = 'stepper' is unknown"),
        ({"model": "ideal", "delay_cycles": -1}, "delay_cycles = -1 is not an integer >= 0"),
        ({"model": "ideal", "delay_cycles": 1.5}, "delay_cycles = 1.5 is not an integer"),
        ({"model": "servo", "bandwidth": 0}, "bandwidth = 0.0 is not a finite number > 0"),
        ({"model": "servo", "damping": "high"}, "damping = 'high' is not a finite number"),
        ({"model": "servo", "bandwith": 50}, "unknown key 'bandwith' = 50"),
        ({"model": "servo", "velocity_feedforward": 2}, "velocity_feedforward = 2.0 is not"),
        ({"model": "servo", "inertia": math.inf}, "inertia = inf is not a finite number"),
    ],
)
def test_bad_config_names_key_and_value(config, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        create(config)


@PROFILE
@given(
    hs.integers(0, 3),
    hs.lists(
        hs.tuples(hs.sampled_from(["position", "velocity", "torque", "free", "set"]),
                  hs.floats(-1e7, 1e7), hs.sampled_from([0.001, 0.0005, 0.00025, 0.002])),
        max_size=30,
    ),
)  # fmt: skip
def test_the_ideal_torque_read_is_the_cycles_change_of_velocity_bit_for_bit(delay, ops):
    """The ideal motor's torque, computed when read, is the inertia times the velocity
    change of the last cycle: bit for bit that formula under random histories of every
    mode and cycle time; 0 after the motor is placed or freed."""
    m = IdealMechanics(delay_cycles=delay, inertia=3e-4, counts_per_rev=10_000)
    for op, value, dt in ops:
        v_0 = m.velocity
        if op == "position":
            m.step_position(value, dt)
        elif op == "velocity":
            m.step_velocity(value, dt)
        elif op == "torque":
            m.step_torque(value * 1e-6, dt)
        elif op == "free":
            m.step_free(dt)
        else:
            m.set_position(value)
        if op in ("free", "set"):
            assert m.torque == 0.0 and m.velocity == 0.0
        else:
            eager = m.inertia * (m.velocity - v_0) / dt * (2.0 * math.pi) / m.counts_per_rev
            assert m.torque.hex() == eager.hex()
