"""Property tests of the profile generator (Hypothesis).

Profiles: `ci` (few examples, the default, bounded for CI) and `thorough` (many, for
local runs); both derandomized so a run is reproducible. Select with
HYPOTHESIS_PROFILE=thorough. The profiles are applied per
test, so this module does not change Hypothesis settings for other test modules.
"""

from __future__ import annotations

import os

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from motionvm.motion.profile import ProfileGenerator
from motionvm.motion.tcurve import plan_position, rest_to_rest_time
from motionvm.motion.tolerances import EPS, P_TOL, limit_violation

PROFILE = settings.get_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

MAX_MOVE_TIME = 4.0  # [s] keeps one example below ~20 ms

dts = st.sampled_from([0.00025, 0.0005, 0.001, 0.002])
v_maxs = st.floats(1.0, 2000.0)
accs = st.floats(10.0, 1e5)
smooth_times = st.one_of(st.just(0.0), st.floats(0.0, 0.2))
positions = st.floats(-1e4, 1e4)
distances = st.one_of(
    st.floats(-500.0, 500.0),
    st.floats(-1e-3, 1e-3),  # very short moves: triangular profiles
    st.just(0.0),
)


def make(dt, v_max, a_max, d_max, t_smooth, p_0):
    return ProfileGenerator(dt, v_max, a_max, d_max, t_smooth, position=p_0)


def drain(gen, max_cycles):
    samples = []
    while not gen.is_done:
        samples.append(gen.step())
        assert len(samples) <= max_cycles, "the move does not end in time"
    return samples


def jerk_bound(gen, factor):
    return factor / gen.t_smooth if gen.t_smooth else None


@PROFILE
@given(dts, v_maxs, accs, accs, smooth_times, positions, distances)
def test_point_to_point_move(dt, v_max, a_max, d_max, t_smooth, p_0, distance):
    t_tc = rest_to_rest_time(distance, v_max, a_max, d_max)
    assume(t_tc + t_smooth < MAX_MOVE_TIME)
    gen = make(dt, v_max, a_max, d_max, t_smooth, p_0)
    target = p_0 + distance
    gen.move_to(target)
    samples = drain(gen, int((MAX_MOVE_TIME + 1.0) / dt))
    end = samples[-1][0] if samples else gen.output[0]
    assert end == target  # exactly, not approximately
    if gen.output[0] != p_0:
        # done at cycle ceil(T/dt) + N - 1: within one cycle of T + Ts
        assert abs(len(samples) * dt - (t_tc + gen.t_smooth)) <= dt * (1.0 + 1e-9)
    message = limit_violation(samples, dt, v_max, max(a_max, d_max), jerk_bound(gen, a_max + d_max))
    assert message is None, message


@PROFILE
@given(dts, v_maxs, accs, accs, smooth_times, distances)
def test_mirrored_input_gives_mirrored_output(dt, v_max, a_max, d_max, t_smooth, distance):
    assume(rest_to_rest_time(distance, v_max, a_max, d_max) + t_smooth < MAX_MOVE_TIME)
    gen_a = make(dt, v_max, a_max, d_max, t_smooth, 0.0)
    gen_b = make(dt, v_max, a_max, d_max, t_smooth, 0.0)
    gen_a.move_to(distance)
    gen_b.move_to(-distance)
    samples_a = drain(gen_a, int((MAX_MOVE_TIME + 1.0) / dt))
    samples_b = drain(gen_b, int((MAX_MOVE_TIME + 1.0) / dt))
    assert samples_a == [tuple(-x for x in s) for s in samples_b]


retargets = st.lists(
    st.tuples(st.integers(1, 400), st.floats(-300.0, 300.0)), min_size=1, max_size=5
)


@PROFILE
@given(dts, v_maxs, accs, accs, smooth_times, retargets)
def test_on_the_fly_retargeting_never_exceeds_limits(dt, v_max, a_max, d_max, t_smooth, plan):
    gen = make(dt, v_max, a_max, d_max, t_smooth, 0.0)
    samples = []
    for cycles, target in plan:
        gen.move_to(target)
        samples += [gen.step() for _ in range(cycles)]
    last = plan[-1][1]
    # planned_move_time() counts from the last replan, like the cycles counted here
    t_rest = gen.planned_move_time() - plan[-1][0] * dt
    assume(t_rest < 3 * MAX_MOVE_TIME)
    samples += drain(gen, max(0, int(t_rest / dt)) + 2)
    assert gen.output[0] == last
    a_lim = max(a_max, d_max)
    message = limit_violation(samples, dt, v_max, a_lim, jerk_bound(gen, 2 * a_lim))
    assert message is None, message


@PROFILE
@given(
    dts, v_maxs, accs, accs, smooth_times,
    st.floats(1.0, 300.0), st.integers(1, 300), v_maxs, accs, accs,
)  # fmt: skip
def test_limit_changes_on_the_fly(dt, v_max, a_max, d_max, t_smooth, target, k, v_2, a_2, d_2):
    gen = make(dt, v_max, a_max, d_max, t_smooth, 0.0)
    gen.move_to(target)
    samples = [gen.step() for _ in range(k)]
    gen.set_limits(v_2, a_2, d_2)
    t_rest = gen.planned_move_time()
    assume(t_rest < 3 * MAX_MOVE_TIME)
    samples += drain(gen, int(t_rest / dt) + 2)
    assert gen.output[0] == target
    a_lim = max(a_max, d_max, a_2, d_2)
    message = limit_violation(samples, dt, max(v_max, v_2), a_lim, jerk_bound(gen, 2 * a_lim))
    assert message is None, message


@PROFILE
@given(dts, v_maxs, accs, accs, smooth_times, st.floats(-3000.0, 3000.0), st.floats(10.0, 1e5))
def test_jog_then_stop(dt, v_max, a_max, d_max, t_smooth, v_jog, d_stop):
    gen = make(dt, v_max, a_max, d_max, t_smooth, 0.0)
    gen.move_velocity(v_jog)
    samples = [gen.step() for _ in range(int(0.3 / dt))]
    assume(v_max / d_stop + t_smooth < MAX_MOVE_TIME)
    gen.stop(d_stop)
    samples += drain(gen, int((MAX_MOVE_TIME + 1.0) / dt))
    assert gen.step()[1] == 0.0
    a_lim = max(a_max, d_max, d_stop)
    message = limit_violation(samples, dt, v_max, a_lim, jerk_bound(gen, 2 * a_lim))
    assert message is None, message


@PROFILE
@given(dts, v_maxs, accs, accs, st.integers(0, 50), positions, distances)
def test_stepping_equals_direct_evaluation(dt, v_max, a_max, d_max, n_avg, p_0, distance):
    t_tc = rest_to_rest_time(distance, v_max, a_max, d_max)
    assume(t_tc + n_avg * dt < MAX_MOVE_TIME)
    gen = make(dt, v_max, a_max, d_max, n_avg * dt, p_0)
    gen.move_to(p_0 + distance)
    plan = plan_position(p_0, 0.0, p_0 + distance, v_max, a_max, d_max)
    samples = drain(gen, int(MAX_MOVE_TIME / dt) + 2)
    n = max(1, n_avg)
    direct = [plan.evaluate(k * dt)[0] if k > 0 else p_0 for k in range(-n, len(samples) + 1)]
    tol = P_TOL + 64 * EPS * (abs(p_0) + abs(distance))
    for k, (p, _, _) in enumerate(samples, start=1):
        window = direct[k + 1 : k + n + 1]  # samples k-n+1 .. k
        if n == 1:
            assert p == window[0]  # bit-identical without smoothing
        else:
            assert abs(p - sum(window) / n) <= tol


@PROFILE
@given(
    dts,
    v_maxs,
    accs,
    accs,
    positions,
    st.floats(-3000.0, 3000.0),
    distances,
)
def test_a_one_way_plan_stays_within_its_bounds(dt, v_max, a_max, d_max, p_0, v_0, distance):
    """`TCurve.bounds` (the plan's position range and top speed, known when it moves one
    way only) holds every sample, up to the rounding the coast's limit check allows
    for; a plan that turns back has none."""
    plan = plan_position(p_0, v_0, p_0 + distance, v_max, a_max, d_max)
    assume(plan.duration < MAX_MOVE_TIME)
    if plan.bounds is None:
        assert v_0 != 0.0 or p_0 + distance == p_0  # a move from rest goes one way
        return
    lo, hi, top = plan.bounds
    size = max(1.0, abs(lo), abs(hi))
    n = 0
    while n * dt < plan.duration + dt:
        p, v, _ = plan.evaluate(n * dt)
        assert lo - 1e-12 * size <= p <= hi + 1e-12 * size
        assert abs(v) <= top * (1.0 + 1e-12)
        n += 1
    for _, _, _, v_s, _ in plan.segs:  # one direction only
        assert v_s == 0.0 or (v_s > 0.0) == (plan.p_f > p_0)
