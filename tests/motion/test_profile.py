"""Example-based tests of the T-curve planner and the profile generator."""

from __future__ import annotations

import itertools
import math

import pytest

from motionvm.motion.profile import IDLE, POSITION, VELOCITY, ProfileGenerator
from motionvm.motion.tcurve import plan_position, plan_velocity, rest_to_rest_time
from motionvm.motion.tolerances import P_TOL, limit_slack, limit_violation

DT = 0.001


def run_until_done(gen: ProfileGenerator, max_cycles: int = 200_000) -> list[tuple]:
    samples = []
    while not gen.is_done:
        samples.append(gen.step())
        assert len(samples) < max_cycles, "the move does not end"
    return samples


def run(gen: ProfileGenerator, cycles: int) -> list[tuple]:
    return [gen.step() for _ in range(cycles)]


# ---- closed-form T-curve ------------------------------------------------------------


def test_rest_to_rest_time_trapezoid_and_triangle():
    # trapezoid: 0.1 s up, 0.2 s down, cruise (100 - 5 - 10) / 100 s
    assert rest_to_rest_time(100.0, 100.0, 1000.0, 500.0) == pytest.approx(0.3 + 0.85)
    # triangle: v_peak = sqrt(2*a*d*D/(a+d)) = sqrt(2*1000*1000*0.001/2000) = 1 mm/s
    assert rest_to_rest_time(-0.001, 100.0, 1000.0, 1000.0) == pytest.approx(0.002)
    assert rest_to_rest_time(0.0, 1.0, 1.0, 1.0) == 0.0


def test_plan_position_lands_exactly_and_matches_closed_form_time():
    plan = plan_position(1.25, 0.0, 101.3, 100.0, 1000.0, 500.0)
    assert plan.duration == pytest.approx(rest_to_rest_time(100.05, 100.0, 1000.0, 500.0))
    assert plan.evaluate(plan.duration) == (101.3, 0.0, 0.0)
    assert plan.evaluate(0.0)[:2] == (1.25, 0.0)


def test_plan_position_brakes_and_reverses_when_moving_away():
    plan = plan_position(0.0, -50.0, 10.0, 100.0, 1000.0, 500.0)
    # first segment: brake at +d_max until v = 0
    t_0, t_1, _, v_0, a = plan.segs[0]
    assert (t_0, v_0, a) == (0.0, -50.0, 500.0)
    assert t_1 == pytest.approx(0.1)
    assert plan.evaluate(plan.duration)[0] == 10.0


def test_plan_position_overshoot_brakes_then_returns():
    # stopping from 100 mm/s at 500 mm/s^2 takes 10 mm; the target is 1 mm ahead
    plan = plan_position(0.0, 100.0, 1.0, 100.0, 1000.0, 500.0)
    p_stop, v_stop, _ = plan.evaluate(0.2)
    assert v_stop == pytest.approx(0.0, abs=1e-9)
    assert p_stop == pytest.approx(10.0)
    assert plan.p_f == 1.0


def test_plan_position_above_v_max_brakes_to_v_max():
    plan = plan_position(0.0, 200.0, 1000.0, 100.0, 1000.0, 500.0)
    _, t_1, _, _, a = plan.segs[0]
    assert a == -500.0 and t_1 == pytest.approx(0.2)
    assert plan.segs[1][3] == 100.0


def test_plan_velocity_reverses_with_decel_then_accel():
    plan = plan_velocity(0.0, 20.0, -30.0, 1000.0, 200.0)
    assert [s[4] for s in plan.segs] == [-200.0, -1000.0, 0.0]
    assert plan.segs[-1][3] == -30.0 and plan.duration == math.inf


# ---- profile generator --------------------------------------------------------------


@pytest.mark.parametrize("t_smooth", [0.0, 0.001, 0.02, 0.05])
@pytest.mark.parametrize("distance", [100.0, -37.3, 0.5, 1e-7])
def test_move_reaches_target_exactly_in_closed_form_time(t_smooth, distance):
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, t_smooth, position=3.0)
    gen.move_to(3.0 + distance)
    assert gen.mode == POSITION and not gen.is_done
    samples = run_until_done(gen)
    assert samples[-1][0] == 3.0 + distance
    expected = rest_to_rest_time(distance, 100.0, 1000.0, 500.0) + gen.t_smooth
    assert abs(len(samples) * DT - expected) <= DT + 1e-12
    assert gen.planned_move_time() == pytest.approx(expected)
    j_max = (1000.0 + 500.0) / gen.t_smooth if gen.t_smooth else None
    assert limit_violation(samples, DT, 100.0, 1000.0, j_max) is None
    # after the end: at rest, idle, nothing changes any more
    tail = run(gen, 3)
    assert tail[-1] == (3.0 + distance, 0.0, 0.0)
    assert gen.mode == IDLE


def test_jerk_is_acc_over_ts_when_phases_are_apart():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.05)
    gen.move_to(200.0)  # 0.1 s ramps, 1.9 s cruise
    samples = run_until_done(gen)
    jerks = [(b[2] - a[2]) / DT for a, b in itertools.pairwise(samples)]
    assert max(abs(j) for j in jerks) == pytest.approx(1000.0 / 0.05, rel=1e-6)
    assert max(abs(s[2]) for s in samples) == pytest.approx(1000.0, rel=1e-6)
    # total acceleration time Ta + Ts: the velocity reaches v_max after 0.1 + 0.05 s
    first_full = next(k for k, s in enumerate(samples) if s[1] >= 100.0 - 1e-9)
    assert abs((first_full + 1) * DT - 0.15) <= DT


def test_triangular_move_has_general_jerk_bound():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.05)
    gen.move_to(1.0)  # v_peak 31.6 mm/s: a triangle shorter than Ts
    samples = run_until_done(gen)
    assert max(s[1] for s in samples) < 100.0
    assert limit_violation(samples, DT, 100.0, 1000.0, 2000.0 / 0.05) is None
    assert samples[-1][0] == 1.0


def test_output_equals_moving_average_of_directly_evaluated_tcurve():
    gen = ProfileGenerator(DT, 80.0, 900.0, 700.0, 0.01, position=-5.0)
    gen.move_to(12.0)
    plan = plan_position(-5.0, 0.0, 12.0, 80.0, 900.0, 700.0)
    samples = run_until_done(gen)
    n = 10
    for k, (p, _, _) in enumerate(samples, start=1):
        window = [plan.evaluate(j * DT)[0] if j > 0 else -5.0 for j in range(k - n + 1, k + 1)]
        assert p == pytest.approx(sum(window) / n, abs=P_TOL)


def test_unsmoothed_steps_equal_direct_evaluation_bitwise():
    gen = ProfileGenerator(DT, 80.0, 900.0, 700.0, 0.0)
    gen.move_to(-33.0)
    plan = plan_position(0.0, 0.0, -33.0, 80.0, 900.0, 700.0)
    for k, (p, _, _) in enumerate(run_until_done(gen), start=1):
        assert p == plan.evaluate(k * DT)[0]


def test_zero_length_move_is_done_at_once():
    gen = ProfileGenerator(DT, 10.0, 100.0, 100.0, 0.02, position=7.5)
    gen.move_to(7.5)
    assert gen.is_done and gen.planned_move_time() == 0.0
    assert gen.step() == (7.5, 0.0, 0.0)


def test_mirrored_command_gives_mirrored_output():
    a = ProfileGenerator(DT, 50.0, 700.0, 300.0, 0.03)
    b = ProfileGenerator(DT, 50.0, 700.0, 300.0, 0.03)
    a.move_to(42.0)
    b.move_to(-42.0)
    for _ in range(200):
        pa, pb = a.step(), b.step()
        assert pa == tuple(-x for x in pb)
    a.move_to(-10.0)
    b.move_to(10.0)
    for pa, pb in zip(run_until_done(a), run_until_done(b)):
        assert pa == tuple(-x for x in pb)


def test_retarget_behind_decelerates_reverses_and_lands():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, 0.02)
    gen.move_to(100.0)
    samples = run(gen, 300)  # at cruise speed
    gen.move_to(5.0)
    samples += run_until_done(gen)
    assert samples[-1][0] == 5.0
    assert max(s[0] for s in samples) > 5.0 + 10.0  # it had to brake past the new target
    assert limit_violation(samples, DT, 100.0, 1000.0, 2 * 1000.0 / 0.02) is None


def test_lower_limits_on_the_fly_apply_to_the_move_in_progress():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.0)
    gen.move_to(100.0)
    before = run(gen, 300)
    gen.set_limits(v_max=20.0, a_max=200.0, d_max=100.0)
    after = run_until_done(gen)
    assert after[-1][0] == 100.0
    assert limit_violation(before + after, DT, 100.0, 1000.0) is None
    # braking from 100 to 20 mm/s at 100 mm/s^2 takes 0.8 s; afterwards the new limits
    assert limit_violation(after[810:], DT, 20.0, 200.0) is None
    assert max(abs(s[2]) for s in after[2:800]) <= 100.0 + limit_slack(100.0, 100.0, DT, 2)


def test_velocity_scale_limits_speed_and_zero_halts():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.01)
    gen.set_velocity_scale(0.25)
    gen.move_to(50.0)
    samples = run(gen, 500)
    assert max(s[1] for s in samples) <= 25.0 + 1e-9
    gen.set_velocity_scale(0.0)
    samples = run(gen, 200)
    assert samples[-1][1] == 0.0 and not gen.is_done and gen.is_halted
    gen.set_velocity_scale(1.0)
    assert not gen.is_halted
    assert run_until_done(gen)[-1][0] == 50.0


def test_jog_reaches_velocity_and_reverses():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, 0.02)
    gen.move_velocity(40.0)
    samples = run(gen, 200)
    assert samples[-1][1] == pytest.approx(40.0) and gen.mode == VELOCITY
    gen.move_velocity(-250.0)  # capped at v_max
    samples += run(gen, 1000)
    assert samples[-1][1] == pytest.approx(-100.0)
    assert not gen.is_done and gen.planned_move_time() == math.inf
    assert limit_violation(samples, DT, 100.0, 1000.0, 2 * 1000.0 / 0.02) is None


def test_stop_decelerates_at_the_given_rate_and_rests():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, 0.0)
    gen.move_velocity(100.0)
    run(gen, 500)
    p_0 = gen.output[0]
    gen.stop(4000.0)
    samples = run_until_done(gen)
    assert min(s[2] for s in samples) >= -4000.0 - limit_slack(4000.0, 100.0, DT, 2)
    assert gen.target == samples[-1][0] and gen.step()[:2] == (gen.target, 0.0)
    assert samples[-1][0] - p_0 == pytest.approx(100.0**2 / (2 * 4000.0), abs=0.1)


def test_long_jog_keeps_position_consistent():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.1)
    gen.move_velocity(100.0)
    run(gen, 100_000)
    # T-curve: 5 mm in the 0.1 s ramp, then 100 mm/s; the mean of the last 100 samples
    # lags (100 - 1)/2 cycles behind it
    expected = 5.0 + 100.0 * (100.0 - 0.1) - 100.0 * 99 / 2 * DT
    assert gen.output[0] == pytest.approx(expected, abs=1e-6)


def test_reset_drops_motion():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, 0.02)
    gen.move_to(100.0)
    run(gen, 50)
    gen.reset(12.0)
    assert gen.is_done and gen.step() == (12.0, 0.0, 0.0)


def test_smooth_time_cannot_change_while_moving():
    gen = ProfileGenerator(DT, 100.0, 1000.0, 500.0, 0.02)
    gen.move_to(1.0)
    gen.step()
    with pytest.raises(RuntimeError, match="smooth time"):
        gen.set_smooth_time(0.05)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"v_max": 0.0}, "v_max must be a positive finite number, got 0.0"),
        ({"a_max": -1.0}, "a_max must be a positive finite number, got -1.0"),
        ({"d_max": math.nan}, "d_max must be a positive finite number, got nan"),
        ({"dt": 0.0}, "dt must be a positive finite number"),
        ({"t_smooth": -0.1}, "smooth time -0.1 s is outside"),
    ],
)
def test_bad_parameters_are_rejected_naming_the_value(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        ProfileGenerator(**kwargs)


def test_bad_commands_are_rejected():
    gen = ProfileGenerator()
    with pytest.raises(ValueError, match="finite"):
        gen.move_to(math.inf)
    with pytest.raises(ValueError, match="outside 0..1"):
        gen.set_velocity_scale(1.5)
    with pytest.raises(ValueError, match="decel"):
        gen.stop(0.0)
