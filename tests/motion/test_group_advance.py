"""A group's path planner advanced in closed form (`PathPlanner.advance`, the moving
average's `PoseAverage.advance`, the geometry's `points`) lands on exactly the floats
stepping computes: outputs, sums, window, path position."""

from __future__ import annotations

import math
import os

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from motionvm.motion.group_path import Arc, Line, Polyline
from motionvm.motion.group_plan import BM_BUFF, BM_LOOKAHEAD, PathPlanner, Planned

settings.register_profile("group-advance-ci", max_examples=60, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("group-advance-thorough", max_examples=2000, derandomize=True,
                          deadline=None, suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("group-advance-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

DT = 0.001
coord = st.integers(-40, 40).map(float)
segment = st.tuples(st.sampled_from(["line", "arc", "poly"]), coord, coord,
                    st.sampled_from([90.0, -200.0, 30.0]))  # fmt: skip


def _planner(n_avg: int, segments, bm: int) -> PathPlanner:
    pl = PathPlanner(DT, [0.0, 0.0])
    pl.set_smoothing(n_avg * DT)
    pos = (0.0, 0.0)
    for kind, x, y, angle in segments:
        if kind == "line" or (x, y) == pos:
            geom = Line(pos, (x, y))
        elif kind == "arc":
            phi = math.radians(angle)
            c, s = math.cos(phi), math.sin(phi)
            dx, dy = pos[0] - x, pos[1] - y  # about (x, y)
            end = (x + c * dx - s * dy, y + s * dx + c * dy)
            geom = Arc(pos, end, (x, y), (0.0, 0.0, 1.0), phi)
        else:
            geom = Polyline([pos, ((pos[0] + x) / 2.0, y), (x, y)])
        if not geom.lt > 0.0:
            continue
        pl.append(Planned(geom, False, 60.0, 400.0, 300.0, bm, 100.0), 60.0)
        pos = tuple(geom.end)
    return pl


def _state(pl: PathPlanner) -> tuple:
    avg = pl._avg
    return (repr(pl.out), repr(pl.out_vel), repr(pl.out_acc), repr(pl.raw), pl.u, pl.v, pl.acc,
            pl.mode, pl._n, repr(avg.sums), avg.j, avg.flush,
            repr([tuple(p) for p in avg.window]))  # fmt: skip


@PROFILE
@given(st.sampled_from([1, 2, 7, 50]), st.lists(segment, min_size=1, max_size=5),
       st.sampled_from([BM_BUFF, BM_LOOKAHEAD]), st.integers(0, 2500), st.integers(3, 4000),
       st.integers(2, 6))  # fmt: skip
def test_advance_lands_on_the_floats_of_stepping(n_avg, segments, bm, before, k, back):
    stepped, coasted = _planner(n_avg, segments, bm), _planner(n_avg, segments, bm)
    for pl in (stepped, coasted):
        for _ in range(before):
            pl.step()
    assume(coasted.active)
    k = coasted.coast_room(k)
    assume(k > back)
    outs = coasted.advance(k, back)
    seen = [stepped.step() for _ in range(k)]
    assert repr([list(p) for p in outs]) == repr(seen[-back - 1 :])
    assert _state(coasted) == _state(stepped)


def test_points_are_the_poses_of_point():
    fs = [i / 97.0 for i in range(98)] + [1.0]
    geoms = [Line((1.0, 2.0, 3.0, 10.0), (-4.0, 5.5, 0.25, -20.0)),
             Arc((10.0, 0.0, 0.0, 5.0), (0.0, 10.0, 3.0, 9.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0),
                 math.pi / 2),
             Arc((3.0, 0.0), (3.0, 0.0), (0.0, 0.0), (0.0, 0.0, 1.0), -2.0 * math.pi),
             Polyline([(0.0, 0.0), (1.0, 2.0), (3.0, -1.0)])]  # fmt: skip
    for g in geoms:
        for part in (fs, fs[:-1], []):
            cols = g.points(part)
            assert len(cols) == g.n
            assert repr([list(p) for p in zip(*cols)]) == repr([g.point(f) for f in part])
