"""Error maps of manual 14.1 on their own: linear (1-D), bilinear, trilinear and spline
interpolation, the nearest point beyond the table, the table layout, bad maps."""

from __future__ import annotations

import pytest

from motionvm.motion.compensation import ALG_LINEAR, ALG_SPLINE, MapError, build

EX1 = [-0.2, 0.1, -0.3, 0.4, -0.1]  # manual 14.1.1 example 1, base -100, interval 200
EX2 = [0.3, 0.1, -0.4, -0.4, 0.0, 0.2, 0.2, -0.1, 0.5]  # example 2, 3 x 3


def table(values, start=0):
    return [0.0] * start + list(values) + [9.9] * 3


@pytest.mark.parametrize(
    ("x", "value"),
    [(-100, -0.2), (100, 0.1), (300, -0.3), (500, 0.4), (700, -0.1),
     (0, -0.05), (200, -0.1), (400, 0.05), (650, 0.025),
     (-1e6, -0.2), (1e6, -0.1)],
)  # fmt: skip
def test_1d_linear_between_points_and_the_nearest_point_beyond(x, value):
    m = build([-100.0], [200.0], [5], 1, table(EX1, 1), ALG_LINEAR)
    assert m.value([x]) == pytest.approx(value, abs=1e-15)


def test_2d_dimension_0_varies_fastest():
    m = build([-100.0, -100.0], [200.0, 100.0], [3, 3], 3, table(EX2, 3), ALG_LINEAR)
    assert m.value([-100, -100]) == pytest.approx(0.3)
    assert m.value([100, -100]) == pytest.approx(0.1)  # the second value: next x
    assert m.value([-100, 0]) == pytest.approx(-0.4)  # the fourth: next y
    assert m.value([300, 100]) == pytest.approx(0.5)
    assert m.value([0, -50]) == pytest.approx((0.3 + 0.1 - 0.4 + 0.0) / 4)
    assert m.value([500, 500]) == pytest.approx(0.5)  # beyond both ends: the corner


def test_3d_trilinear():
    vals = [float(i) / 100 for i in range(27)]
    m = build([-10.0, 5.0, 0.0], [20.0, 10.0, 30.0], [3, 3, 3], 0, table(vals), ALG_LINEAR)
    assert m.value([-10, 5, 0]) == pytest.approx(0.0)
    assert m.value([10, 15, 30]) == pytest.approx((1 + 3 * 1 + 9 * 1) / 100)
    # the value is linear in each index here, so interpolation is exact anywhere inside
    assert m.value([0, 10, 15]) == pytest.approx((0.5 + 3 * 0.5 + 9 * 0.5) / 100)


def test_spline_goes_through_the_points_and_is_smooth_between():
    m = build([0.0], [10.0], [4], 0, table([0.0, 1.0, 1.0, 0.0]), ALG_SPLINE)
    for i, v in enumerate([0.0, 1.0, 1.0, 0.0]):
        assert m.value([10.0 * i]) == pytest.approx(v, abs=1e-15)
    assert m.value([15.0]) == pytest.approx(1.15)  # natural spline: overshoots the points
    assert m.value([-5.0]) == 0.0 and m.value([99.0]) == 0.0


def test_2d_spline_reproduces_a_bilinear_plane():
    vals = [0.01 * i + 0.03 * j for j in range(3) for i in range(4)]
    m = build([0.0, 0.0], [1.0, 1.0], [4, 3], 0, table(vals), ALG_SPLINE)
    assert m.value([1.5, 0.5]) == pytest.approx(0.015 + 0.015, abs=1e-12)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([0.0], [0.0], [3], 0, ALG_LINEAR), "interval"),
        (([0.0], [-1.0], [3], 0, ALG_LINEAR), "interval"),
        (([float("nan")], [1.0], [3], 0, ALG_LINEAR), "base"),
        (([0.0], [1.0], [1], 0, ALG_LINEAR), "num_pt"),
        (([0.0], [1.0], [5], 10, ALG_LINEAR), "do not fit"),
        (([0.0], [1.0], [5], -1, ALG_LINEAR), "do not fit"),
        (([0.0] * 3, [1.0] * 3, [2, 2, 2], 0, ALG_SPLINE), "spline"),
    ],
)
def test_bad_maps_are_refused_naming_the_parameter(args, message):
    base, interval, num_pt, start, alg = args
    with pytest.raises(MapError, match=message):
        build(base, interval, num_pt, start, [0.0] * 12, alg)
