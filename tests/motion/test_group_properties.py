"""Property tests of axis group paths (Hypothesis): random polylines, arcs and their
mixes with random buffer and transition modes, profiles and velocity scales.

At every cycle: the path speed is at most the highest programmed feed (or transition
speed) times the scale, every axis within its velocity and acceleration limits, the
commanded path within the transition tolerance of the programmed geometry; the last
pose is exactly the last target; after an error stop nothing moves once the brake ends.
Profiles `ci` (default, derandomized) and `thorough` (HYPOTHESIS_PROFILE=thorough).
"""

from __future__ import annotations

import math
import os

from group_util import Recorder, cycle, distance_to_segment, grouped, until
from hypothesis import HealthCheck, Phase, assume, example, given, settings
from hypothesis import strategies as hs

from motionvm.motion.group_coords import CS_MCS
from motionvm.motion.group_path import Arc, Line
from motionvm.motion.tolerances import limit_slack

# no shrinking in CI: one example runs up to a few thousand cycles; a failure is
# reproducible as it stands (derandomized)
settings.register_profile(
    "group-ci", max_examples=15, derandomize=True, deadline=None,
    phases=[Phase.explicit, Phase.reuse, Phase.generate],
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)  # fmt: skip
settings.register_profile(
    "group-thorough", max_examples=300, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)  # fmt: skip
PROFILE = settings.get_profile(
    "group-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "group-ci"
)

AXIS_VEL, AXIS_ACC = 1000.0, 10000.0  # the default axes
coords = hs.floats(-40.0, 40.0, allow_nan=False).map(lambda x: round(x, 3))
points = hs.tuples(coords, coords)
feeds = hs.floats(20.0, 400.0)
accs = hs.floats(200.0, 20000.0)
smooth = hs.sampled_from([0.0, 5.0, 20.0, 50.0])
buffer_modes = hs.sampled_from([0, 2, 3, 4, 5, 6])
trans_modes = hs.sampled_from([0, 0, 2, 3, 4, 5])


@hs.composite
def moves(draw):
    """(kind, target, centre or None, turns, profile, bm, tm, trans parameters)."""
    kind = draw(hs.sampled_from(["line", "line", "arc"]))
    target = draw(points)
    center = draw(points) if kind == "arc" else None
    turns = draw(hs.sampled_from([-2, -1, 0, 1, 2])) if kind == "arc" else 0
    profile = [draw(feeds), draw(accs), draw(accs), draw(smooth)]
    prm = [draw(hs.floats(0.0, 300.0)), draw(hs.floats(0.0, 30.0)),
           draw(hs.floats(0.0, 5.0)), draw(hs.floats(0.0, 1.0))]  # fmt: skip
    return kind, target, center, turns, profile, draw(buffer_modes), draw(trans_modes), prm


def _queue(c, mv) -> bool:
    kind, target, center, turns, profile, bm, tm, prm = mv
    pose = [target[0], target[1], 0, 0, 0, 0]
    if kind == "line":
        status = c.LineAbs(0, pose, profile, CS_MCS, bm, tm, prm)
    else:
        status = c.CircleAbs(0, [*center, 0], [0, 0, 1], turns, pose, profile, CS_MCS, bm, tm, prm)
    return status == 0


def _geometry(g):
    return [seg.geom for seg in g.planner.queue]


def _distance_to(p, geom) -> float:
    """Distance from p to a line, a planar arc or a blend polyline."""
    if isinstance(geom, Line):
        return distance_to_segment(p, geom.start, geom.end)
    if isinstance(geom, Arc):  # its radius may change by RADIUS_TOL from start to end
        return _distance_to_helix(p, geom)
    pts = geom._pts
    return min(distance_to_segment(p, a, b) for a, b in zip(pts, pts[1:]))


# found by the property test: a corner on y = 0 trimmed by 3.4e-124 mm made a blend of
# rounding noise that crept for ever (the arcs are refused: unequal radii)
_CREEP = [
    ("line", (-4.898, -0.0), None, 0, [72.5, 5928.9, 3993.0, 0.0], 2, 4, [281.0, 15.7, 2.78, 0.0]),
    ("arc", (-0.0, -11.297), (-3.01, -19.849), 2, [162.3, 11570.9, 2000.0, 50.0], 4, 2,
     [244.3, 6.247, 9.5e-106, 0.88]),
    ("line", (-25.065, -33.033), None, 0, [303.3, 19999.0, 999.05, 0.0], 6, 4,
     [142.46, 3.3696900149282853e-124, 1.93, 0.2]),
]  # fmt: skip


@PROFILE
@given(hs.lists(moves(), min_size=1, max_size=5), hs.sampled_from([100.0, 100.0, 60.0]))
@example(_CREEP, 100.0)
@example(  # found by the property test: end radius 0.09 % off, the end was a jump
    [("line", (14.0, 1.906), None, 0, [20.0, 200.0, 200.0, 0.0], 0, 0, [0.0] * 4),
     ("arc", (2.0, 14.0), (0.0, 0.0), -2, [20.0, 200.0, 200.0, 0.0], 0, 0, [0.0] * 4)],
    100.0,
)  # fmt: skip
def test_random_paths_keep_every_limit(mvs, scale):
    c = grouped(2)
    g = c.motion.groups[0]
    c.SetGrpVelScale(0, scale)
    until(c, lambda: c.IsGrpInPos(0))
    geoms, feed_max, last, t_w = [], 0.0, None, 0.0
    for mv in mvs:
        before = list(g.planner.queue)
        if not _queue(c, mv):
            continue
        feed_max = max(feed_max, mv[4][0], mv[7][0])
        last = list(g.end_pose())
        t_w = max(t_w, g.planner.window_time)
        geoms += [s.geom for s in g.planner.queue if all(s is not b for b in before)]
        geoms += [s.geom for s in before]  # trimmed in place by a transition
    if last is None:
        return
    # a path that needs minutes at its programmed feeds (a long blend at trans_vel
    # 0.02 mm/s) is slow, not creeping: left out; any other comes to rest within 400 s
    assume(sum(s.length / (s.feed * g.planner.scale) for s in g.planner.queue) <= 200.0)
    rec = Recorder(c)
    rec.run(limit=400_000)
    dt = c.motion.dt
    for speed in rec.speeds:
        assert speed <= feed_max * scale / 100.0 * (1 + 1e-6) + 1e-6
    p_scale = max(max(abs(x) for x in p) for p in rec.poses)
    v_slack = limit_slack(AXIS_VEL, p_scale, dt, 1)
    a_slack = limit_slack(AXIS_ACC, p_scale, dt, 2)
    for v in rec.axis_vel:
        assert max(abs(x) for x in v) <= AXIS_VEL + v_slack
    for a in rec.axis_acc:
        assert max(abs(x) for x in a) <= AXIS_ACC + a_slack
    assert rec.poses[-1] == [float(x) for x in last]
    # smoothing rounds a corner passed at speed v by at most v * T_w / 4
    tol = feed_max * t_w / 4.0 + 1e-6
    sample = rec.poses[:: max(1, len(rec.poses) // 300)]
    for p in sample:
        assert min(_distance_to(p, gm) for gm in geoms) <= tol


@PROFILE
@given(hs.lists(points, min_size=2, max_size=5), hs.integers(20, 800))
def test_no_motion_after_an_error_stop(pts, when):
    c = grouped(3, n=4)
    g = c.motion.groups[0]
    for x, y in pts:
        c.LineAbs3D(0, x, y, 1.0)
    cycle(c, when)
    c.Disable(2)
    cycle(c)
    assert c.IsGrpErrorStop(0) == 1
    until(c, lambda: not c.IsGrpMoving(0))
    rest = [a.ref_pos for a in g.axes[:2]]
    for _ in range(100):
        cycle(c)
        assert [a.ref_pos for a in g.axes[:2]] == rest
    assert c.LineAbs2D(0, 0, 0) != 0


def _distance_to_helix(p, arc: Arc) -> float:
    """Distance from p to a 3-D arc or helix: the nearest of the points at p's angle
    about the axis, over every turn, and the two ends."""
    r = [x - c for x, c in zip(p, arc.center)]
    a = math.atan2(sum(x * e for x, e in zip(r, arc._e2)), sum(x * e for x, e in zip(r, arc._e1)))
    best = min(math.dist(p, arc.start), math.dist(p, arc.end))
    turns = int(abs(arc.phi) / (2 * math.pi)) + 2
    for k in range(-turns, turns + 1):
        f = (a + 2 * math.pi * k) / arc.phi
        if 0.0 <= f <= 1.0:
            best = min(best, math.dist(p, arc.point(f)))
    return best


unit = hs.floats(-1.0, 1.0)


@PROFILE
@given(
    hs.lists(
        hs.tuples(
            hs.booleans(),
            points,
            coords,
            hs.tuples(unit, unit, unit),
            hs.sampled_from([-2, -1, 1, 3]),
        ),
        min_size=1,
        max_size=3,
    ),
    hs.sampled_from([0, 6]),
)
def test_random_3d_arcs_and_helices(mvs, bm):
    """Lines and circles about random normals, some rising (helices): the path stays on
    the programmed geometry within the smoothing's rounding, the axes within their
    limits, the last target exact."""
    c = grouped(3)
    g = c.motion.groups[0]
    until(c, lambda: c.IsGrpInPos(0))
    geoms, last = [], None
    profile = [150, 3000, 3000, 20]
    for is_arc, (x, y), z, normal, turns in mvs:
        start = g.end_pose()
        if is_arc:
            if sum(v * v for v in normal) < 0.01:
                continue
            # a centre 20 mm from the start, off the normal's direction
            center = [start[0] + 20.0, start[1], start[2]]
            target = list(start)
            target[2] += z / 4.0  # rise along the axis for a helix (0 if the normal is off Z)
            status = c.CircleAbs(0, center, list(normal), turns, target + [0, 0, 0], profile,
                                 CS_MCS, bm, 0, None)  # fmt: skip
        else:
            status = c.LineAbs(0, [x, y, z, 0, 0, 0], profile, CS_MCS, bm, 0, None)
        if status == 0:
            geoms.append(g.planner.queue[-1].geom)
            last = g.end_pose()
    if last is None:
        return
    rec = Recorder(c)
    rec.run(limit=400_000)
    p_scale = max(max(abs(x) for x in p) for p in rec.poses)
    for v in rec.axis_vel:
        assert max(abs(x) for x in v) <= AXIS_VEL + limit_slack(AXIS_VEL, p_scale, 0.001, 1)
    for a in rec.axis_acc:
        assert max(abs(x) for x in a) <= AXIS_ACC + limit_slack(AXIS_ACC, p_scale, 0.001, 2)
    assert rec.poses[-1] == [float(x) for x in last]
    tol = 150 * 0.02 / 4.0 + 1e-6
    for p in rec.poses[:: max(1, len(rec.poses) // 200)]:
        assert min(_distance_to_helix(p, gm) if isinstance(gm, Arc) else _distance_to(p, gm)
                   for gm in geoms) <= tol  # fmt: skip


@PROFILE
@given(
    hs.lists(hs.tuples(points, hs.floats(-180.0, 180.0), buffer_modes), min_size=1, max_size=4),
    hs.floats(30.0, 720.0),
)
def test_random_moves_with_rotation(mvs, ang_vel):
    """Lines that also turn axis A (deg): the feed follows the slower of the translation
    and rotation profiles; the axes stay within their limits; targets exact."""
    c = grouped(4)
    c.SetGrpAngMotionProfile(0, ang_vel, 3600, 3600, 20)
    until(c, lambda: c.IsGrpInPos(0))
    last = None
    for (x, y), a, bm in mvs:
        if c.LineAbs(0, [x, y, 0, a, 0, 0], [200, 2000, 2000, 20], CS_MCS, bm, 0, None) == 0:
            last = c.motion.groups[0].end_pose()
    if last is None:
        return
    rec = Recorder(c)
    rec.run(limit=400_000)
    p_scale = max(max(abs(x) for x in p) for p in rec.poses)
    for v in rec.axis_vel:
        assert max(abs(x) for x in v) <= AXIS_VEL + limit_slack(AXIS_VEL, p_scale, 0.001, 1)
        assert abs(v[3]) <= ang_vel * (1 + 1e-6) + 1e-6 or max(abs(x) for x in v[:2]) > 0.0
    for acc in rec.axis_acc:
        assert max(abs(x) for x in acc) <= AXIS_ACC + limit_slack(AXIS_ACC, p_scale, 0.001, 2)
    assert rec.poses[-1] == [float(x) for x in last]
