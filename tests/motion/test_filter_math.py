"""Command filters of manual 15.1 on their own: the InShape shapers (ZV, ZVD) and the VSF notch.

An ideal oscillator (a mass on a spring, frequency f, damping ratio zeta) driven by the
commanded position held over each cycle is simulated exactly (closed-form transition
matrix); its residual vibration after a move is the amplitude of the free oscillation
about the target. Property tests (Hypothesis, derandomized `ci` / `thorough` profiles as
elsewhere): random moves of the manual's profile generator through a random shaper reach
the target exactly, exactly `length` cycles after the unshaped move, never leave the
range of the unshaped reference, and leave no residual vibration at f.
"""

from __future__ import annotations

import cmath
import math
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.motion import inshape, vsf
from motionvm.motion.profile import ProfileGenerator
from motionvm.motion.tolerances import FILTER_SETTLE

settings.register_profile(
    "filters-ci", max_examples=40, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "filters-thorough", max_examples=400, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "filters-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "filters-ci"
)

RESIDUAL_REL = 1e-9
"""Residual vibration [-] relative to the move distance that counts as none."""


def residual(commands: list[float], f: float, zeta: float, dt: float, x_0: float) -> float:
    """Amplitude [mm] of the free vibration left in an oscillator (f [Hz], zeta) that
    starts at rest at x_0 and is driven by `commands` held one cycle each."""
    w = 2.0 * math.pi * f
    sigma, w_d = zeta * w, w * math.sqrt(1.0 - zeta * zeta)
    c, s, ex = math.cos(w_d * dt), math.sin(w_d * dt), math.exp(-sigma * dt)
    p11, p12 = ex * (c + sigma / w_d * s), ex * s / w_d
    p21, p22 = -ex * w * w / w_d * s, ex * (c - sigma / w_d * s)
    x, v = x_0, 0.0
    for u in commands:
        e = x - u
        e, v = p11 * e + p12 * v, p21 * e + p22 * v
        x = e + u
    e = x - commands[-1]
    return math.hypot(e, (v + sigma * e) / w_d)


def profile(dt, distance, v_max, acc, t_smooth) -> list[tuple[float, float, float]]:
    """A rest-to-rest move of the profile generator from 0, and 3 cycles at rest."""
    gen = ProfileGenerator(dt, v_max, acc, acc, t_smooth, position=0.0)
    gen.move_to(distance)
    out = []
    while not gen.is_done:
        out.append(gen.step())
    return out + [gen.step() for _ in range(3)]


def rest_index(samples) -> int:
    """The first index of the final run of samples equal in position and velocity."""
    i = len(samples) - 1
    while i > 0 and samples[i - 1][:2] == samples[-1][:2]:
        i -= 1
    return i


def run(state, samples, extra: int):
    """Feed `samples` then `extra` copies of the last one; the outputs and the index of
    the first output after which nothing is pending."""
    feed = samples + [samples[-1]] * extra
    outs, done_at = [], None
    for k, (p, v, a) in enumerate(feed):
        outs.append(state.step(p, v, a))
        if done_at is None and not state.pending and k >= rest_index(samples):
            done_at = k
    return outs, done_at


# ---- the shaper's design ----------------------------------------------------------


@pytest.mark.parametrize("shaper_type", inshape.SHAPER_TYPES)
@pytest.mark.parametrize("f", [1.5, 5.5, 10.0, 33.3, 100.0, 300.0])
@pytest.mark.parametrize("zeta", [0.0, 0.03, 0.3])
def test_gains_are_positive_sum_to_1_and_cancel_the_mode(shaper_type, f, zeta):
    dt = 0.001
    sh = inshape.design(f, zeta, shaper_type, dt)
    assert sum(sh.gains) == pytest.approx(1.0, abs=1e-12)
    assert all(g > 0.0 for g in sh.gains)
    assert list(sh.delays) == sorted(set(sh.delays)) and sh.delays[0] == 0
    w = 2.0 * math.pi * f
    z = cmath.exp(complex(-zeta * w, w * math.sqrt(1 - zeta * zeta)) * dt)
    h = sum(g * z ** (-d) for d, g in zip(sh.delays, sh.gains))
    assert abs(h) < 1e-12
    if shaper_type == inshape.SHAPER_ROBUST:  # a double zero: robust to the frequency
        dh = sum(-d * g * z ** (-d - 1) for d, g in zip(sh.delays, sh.gains))
        assert abs(dh) < 1e-9


def test_zv_is_two_impulses_half_a_period_apart_when_that_is_on_the_grid():
    sh = inshape.design(10.0, 0.0, inshape.SHAPER_NORMAL, 0.001)  # T/2 = 50 ms
    assert sh.delays == (0, 50)
    assert sh.gains == pytest.approx((0.5, 0.5))
    k = math.exp(-0.1 * math.pi / math.sqrt(1 - 0.01))  # damped: the classic 1/(1+K), K/(1+K)
    sh = inshape.design(10.0 / math.sqrt(1 - 0.01), 0.1, inshape.SHAPER_NORMAL, 0.001)
    assert sh.gains == pytest.approx((1 / (1 + k), k / (1 + k)), abs=1e-9)


def test_the_robust_shaper_is_twice_as_long():
    zv = inshape.design(5.5, 0.03, inshape.SHAPER_NORMAL, 0.001)
    zvd = inshape.design(5.5, 0.03, inshape.SHAPER_ROBUST, 0.001)
    assert zv.length == 91 and zvd.length == 2 * zv.length


def test_a_frequency_too_high_for_the_cycle_cannot_be_shaped():
    with pytest.raises(inshape.ShaperDesignError, match="shorter than the cycle"):
        inshape.design(300.0, 0.0, inshape.SHAPER_NORMAL, 0.004)


# ---- shaping a move ---------------------------------------------------------------


def test_zv_move_reaches_the_target_exactly_one_shaper_later_without_residual():
    dt, f, zeta = 0.001, 5.5, 0.03
    samples = profile(dt, 100.0, 1000.0, 10000.0, 0.0)
    sh = inshape.design(f, zeta, inshape.SHAPER_NORMAL, dt)
    outs, done_at = run(inshape.ShaperState(sh, 0.0), samples, sh.length + 5)
    assert done_at == rest_index(samples) + sh.length
    assert outs[-1] == (100.0, 0.0, 0.0)
    shaped = residual([o[0] for o in outs], f, zeta, dt, 0.0)
    unshaped = residual([s[0] for s in samples] * 1, f, zeta, dt, 0.0)
    assert shaped < 100.0 * RESIDUAL_REL
    assert unshaped > 1.0  # the same move unshaped rings by millimetres


def test_a_resting_shaper_passes_its_input_through_unchanged():
    state = inshape.ShaperState(inshape.design(5.5, 0.03, 1, 0.001), 12.5)
    assert not state.pending
    assert state.step(12.5, 0.0, 0.0) == (12.5, 0.0, 0.0)
    state.reset(-3.0)
    assert state.last_out == (-3.0, 0.0, 0.0) and not state.pending


dts = st.sampled_from([0.0005, 0.001, 0.002])
frequencies = st.floats(3.0, 120.0)
dampings = st.one_of(st.just(0.0), st.floats(0.0, 0.3))
distances = st.one_of(st.floats(-200.0, 200.0), st.floats(-1e-3, 1e-3))


@PROFILE
@given(
    dt=dts, f=frequencies, zeta=dampings, shaper_type=st.sampled_from(inshape.SHAPER_TYPES),
    distance=distances, v_max=st.floats(50.0, 2000.0), acc=st.floats(500.0, 1e5),
    t_smooth=st.one_of(st.just(0.0), st.floats(0.0, 0.05)),
)  # fmt: skip
def test_property_shaped_moves_end_exactly_later_by_the_shaper_without_residual(
    dt, f, zeta, shaper_type, distance, v_max, acc, t_smooth
):
    sh = inshape.design(f, zeta, shaper_type, dt)
    samples = profile(dt, distance, v_max, acc, t_smooth)
    outs, done_at = run(inshape.ShaperState(sh, 0.0), samples, sh.length + 3)
    target = samples[-1][0]
    # the target exactly, `length` cycles after the unshaped reference rests
    moved = rest_index(samples) > 0
    assert done_at == (rest_index(samples) + sh.length if moved else 0)
    assert all(o[0] == target for o in outs[done_at:])
    # positive gains: never beyond the range of the unshaped reference
    lo = min(0.0, *(s[0] for s in samples))
    hi = max(0.0, *(s[0] for s in samples))
    slack = 1e-12 * max(abs(lo), abs(hi), 1.0)
    assert all(lo - slack <= o[0] <= hi + slack for o in outs)
    # no vibration left at the shaper's frequency
    res = residual([o[0] for o in outs], f, zeta, dt, 0.0)
    assert res <= max(abs(distance), 1e-3) * RESIDUAL_REL


# ---- VSF ----------------------------------------------------------------------------


def test_vsf_notch_has_unit_dc_gain_and_a_zero_at_its_frequency():
    dt, f = 0.001, 25.0
    nt = vsf.design(f, 1.0, dt)
    w = 2.0 * math.pi * f

    def h(z):
        num = nt.g * (1.0 - 2.0 * nt.c / z + 1.0 / z**2)
        return num / (1.0 + nt.a1 / z + nt.a2 / z**2)

    assert abs(h(1.0)) == pytest.approx(1.0, abs=1e-12)
    assert abs(h(cmath.exp(1j * w * dt))) < 1e-12
    assert abs(h(cmath.exp(1j * 0.2 * w * dt))) == pytest.approx(1.0, abs=0.1)


@pytest.mark.parametrize("zeta", [0.7, 1.0, 1.5])
def test_vsf_move_settles_exactly_on_the_target_without_residual_at_f(zeta):
    dt, f = 0.001, 8.0
    samples = profile(dt, 50.0, 500.0, 5000.0, 0.0)
    state = vsf.VsfState(vsf.design(f, zeta, dt), 0.0, dt)
    outs, done_at = run(state, samples, 5000)
    assert done_at is not None and done_at > rest_index(samples)
    assert outs[done_at] == (50.0, 0.0, 0.0) and outs[-1] == (50.0, 0.0, 0.0)
    assert abs(outs[done_at - 1][0] - 50.0) < FILTER_SETTLE
    # an undamped mode at f is not excited (only the filter's own, well-damped response)
    assert residual([o[0] for o in outs], f, 0.0, dt, 0.0) < 50.0 * 1e-7
    assert residual([s[0] for s in samples], f, 0.0, dt, 0.0) > 0.1


def test_vsf_refuses_frequencies_at_the_nyquist_limit():
    with pytest.raises(vsf.VsfDesignError, match="Nyquist"):
        vsf.design(200.0, 1.0, 0.004)
