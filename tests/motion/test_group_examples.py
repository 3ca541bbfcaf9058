"""What the text of the manual's examples 8.1.6 states, measured on the motion commands:
the hand-over speeds of example 2, the transition curves of examples 3-1 and 3-2, the
helix of example 4, the coordinate chain of example 5-3; and look-ahead (8.1.4)."""

from __future__ import annotations

import math

import pytest
from group_util import Recorder, distance_to_segment, grouped, until

from motionvm.motion.group_coords import CS_MCS, CS_OFFSET, CS_PCS
from motionvm.motion.group_motion import TM_CORNER_DIST, TM_MAX_CORNER_CURV, TM_MAX_CORNER_DEV
from motionvm.motion.group_plan import BM_BUFF, BM_LOOKAHEAD, BM_LOW, BM_NEXT, BM_PREV

ZERO4 = [0.0] * 4


def _nearest(rec: Recorder, point) -> int:
    """The cycle whose commanded pose is nearest to `point`."""
    d = [math.dist(p[:2], point) for p in rec.poses]
    return d.index(min(d))


def test_example2_hand_over_speeds():
    c = grouped(2)
    vel_high, vel, vel_low = [150, 1000, 1000, 50], [100, 5000, 5000, 50], [50, 250, 250, 50]
    p1, p2, p3 = [100, 0, 0, 0, 0, 0], [100, 100, 0, 0, 0, 0], [0, 100, 0, 0, 0, 0]
    rec = Recorder(c)
    assert c.LineAbs(0, p1, vel_high, CS_MCS, BM_PREV, 0, ZERO4) == 0
    assert c.CircleAbs(0, [100, 50, 0], [0, 0, 1], 0, p2, vel, CS_MCS, BM_NEXT, 0, ZERO4) == 0
    assert c.LineAbs(0, p3, vel_low, CS_MCS, BM_PREV, 0, ZERO4) == 0
    rec.run()
    # p1: BM_PREV, the speed of path 1 (150); p2: BM_NEXT, the speed of path 3 (50)
    assert rec.junctions == pytest.approx([150.0, 50.0], abs=5.0 + 1e-9)
    # on the arc the feed of path 2 (100), the arc bulging to x = 150 (counter-clockwise)
    i = _nearest(rec, (150, 50))
    assert rec.speeds[i] == pytest.approx(100.0, rel=0.01)
    # p3: path 4 arrives after the group is in position: the hand-over is ignored (rest)
    assert rec.poses[-1][:2] == [0.0, 100.0] and rec.speeds[-1] == 0.0


def test_example2_without_blending_stops_at_every_end():
    c = grouped(2)
    rec = Recorder(c)
    c.LineAbs(0, [100, 0, 0, 0, 0, 0], [150, 1000, 1000, 50], CS_MCS, BM_BUFF, 0, ZERO4)
    c.LineAbs(0, [100, 100, 0, 0, 0, 0], [150, 1000, 1000, 50], CS_MCS, BM_BUFF, 0, ZERO4)
    rec.run()
    assert rec.junctions == [0.0]
    # the output comes to rest on the corner: the corner is traced exactly
    assert [100.0, 0.0] in rec.poses
    assert min(distance_to_segment(p, (100, 0), (100, 100)) for p in rec.poses[-900:]) == 0.0


def _rectangle(c, tm: int) -> Recorder:
    rec = Recorder(c)
    c.LineAbs2D(0, 100, 0)
    c.LineAbs2D(0, 100, 100)
    c.SetGrpTransMode(0, tm)
    c.LineAbs2D(0, 0, 100)
    c.SetGrpTransMode(0, 0)
    c.LineAbs2D(0, 0, 0)
    rec.run()
    return rec


@pytest.mark.parametrize(
    "tm, trim",
    [
        (TM_CORNER_DIST, 40.0),
        (TM_MAX_CORNER_DEV, 2 * 4 / math.cos(math.pi / 4)),  # trans_dev 4 at 90 degrees
        (TM_MAX_CORNER_CURV, 4 / (0.04 * 2**1.5)),  # curvature 0.04 at 90 degrees
    ],
)
def test_example3_1_transition_at_p2_only(tm, trim):
    c = grouped(2)
    c.SetGrpBufferMode(0, BM_LOW)
    c.SetGrpTransPrm(0, 50, 40, 4, 0.04)
    rec = _rectangle(c, tm)
    # the blend is the quadratic Bezier with its control point at the corner p2: it
    # leaves the corner by trim/2 * cos(45 deg) at its middle
    dev = min(math.dist(p[:2], (100, 100)) for p in rec.poses)
    assert dev == pytest.approx(trim / 2 * math.cos(math.pi / 4), rel=0.02)
    if tm == TM_MAX_CORNER_DEV:
        assert dev == pytest.approx(4.0, rel=0.02)
    # the blend starts `trim` before p2 and ends `trim` after it, run at trans_vel (50)
    mid = _nearest(rec, (100 - trim / 4, 100 - trim / 4))
    assert rec.speeds[mid] == pytest.approx(50.0, rel=0.02)
    # p1 and p3 have no transition: the path passes them within the smoothing's rounding
    for corner in ((100, 0), (0, 100)):
        near = min(math.dist(p[:2], corner) for p in rec.poses)
        assert near < 100.0 * 0.05 / 4 + 1e-9
    assert rec.poses[-1][:2] == [0.0, 0.0]


def test_example3_2_rounded_rectangle_ends_past_p0():
    c = grouped(2)
    c.SetGrpTransMode(0, TM_CORNER_DIST)
    c.SetGrpTransPrm(0, 50, 20, 0, 0)
    rec = Recorder(c)
    for x, y in ((0, 0), (100, 0), (100, 100), (0, 100), (0, 0), (20, 0)):
        assert c.LineAbs2D(0, x, y) == 0
    rec.run()
    # every corner is cut: the path stays 20 mm * cos(45) / 2 from each
    for corner in ((100, 0), (100, 100), (0, 100)):
        dev = min(math.dist(p[:2], corner) for p in rec.poses)
        assert dev == pytest.approx(10 * math.cos(math.pi / 4), rel=0.02)
    assert rec.poses[-1][:2] == [20.0, 0.0]


def test_example4_helix():
    c = grouped(3)
    rec = Recorder(c)
    vel = [100, 5000, 5000, 50]
    assert (
        c.CircleAbs(
            0, [0, 50, 0], [0, 0, 1], 5, [0, 0, 100, 0, 0, 0], vel, CS_MCS, BM_BUFF, 0, None
        )
        == 0
    )
    rec.run()
    # five turns of radius 50 about (0, 50), rising linearly to z = 100
    for p in rec.poses[::97]:
        assert math.hypot(p[0], p[1] - 50) == pytest.approx(50.0, abs=0.2)
    turns = sum(1 for a, b in zip(rec.poses, rec.poses[1:]) if a[0] < 0.0 <= b[0] and b[1] < 50)
    assert turns == 5
    assert rec.poses[-1] == [0.0, 0.0, 100.0]
    assert max(rec.speeds) == pytest.approx(100.0, rel=0.01)


def test_example5_3_coordinate_chain():
    c = grouped(2)
    c.SetGrpCoordTrans(0, CS_PCS, [100, 50, 0, 0, 0, 45])
    c.SetGrpCoordTrans(0, 1 << 4, [400, 400, 0, 0, 0, 0])
    c.SetGrpCoordTrans(0, CS_OFFSET, [0, -100, 0, 0, 0, 0])
    cs = CS_OFFSET | (1 << 4) | CS_PCS
    c.SetGrpCoordSys(0, cs)
    c.LineAbs2D(0, 10, 10)
    until(c, lambda: c.IsGrpInPos(0))
    status, mcs = c.GetGrpPoseCmd(0, CS_MCS)
    assert mcs[:2] == pytest.approx(
        [500.0, 250.0 + 100.0 + 10 * math.sqrt(2) + 4.0 - 4.0], abs=1e-9
    )
    assert c.GetGrpPoseCmd(0, cs)[1][:2] == pytest.approx([10.0, 10.0])


def test_lookahead_short_segments_run_at_the_feed():
    """A straight-ish polyline of 0.5 mm segments: with look-ahead the group cruises at
    its feed; stopping at every end it would crawl."""
    c = grouped(2)
    rec = Recorder(c)
    c.SetGrpMotionProfile(0, 100, 2000, 2000, 20)
    c.SetGrpBufferMode(0, BM_LOOKAHEAD)
    y = 0.0
    for i in range(1, 401):
        y = 0.05 if i % 2 else 0.0  # small zig-zag: corners of about 11 degrees
        assert c.LineAbs2D(0, 0.5 * i, y) == 0
    n = rec.run()
    assert n * 0.001 < 200 / 100 * 1.3
    cruising = sorted(rec.speeds)[len(rec.speeds) // 2]
    assert cruising > 0.5 * 100


def test_lookahead_corner_stays_within_the_corner_acceleration():
    c = grouped(2)
    rec = Recorder(c)
    c.SetGrpMotionProfile(0, 200, 5000, 5000, 20)
    c.SetGrpBufferMode(0, BM_LOOKAHEAD)
    c.SetGrpLookAheadPrm(0, 0, 1000.0)
    c.LineAbs2D(0, 100, 0)
    c.LineAbs2D(0, 100, 100)
    rec.run()
    corner = rec.junctions[0]
    # V_corner = A_corner * Ts / |t1 - t0| = 1000 * 0.02 / sqrt(2)
    assert corner == pytest.approx(1000 * 0.02 / math.sqrt(2), abs=5.0)  # + one cycle of a
    assert max(abs(a) for acc in rec.axis_acc for a in acc) <= 5000 * (1 + 1e-6) + 1000


def test_polyline_never_leaves_the_programmed_path_by_more_than_the_rounding():
    c = grouped(2)
    rec = Recorder(c)
    pts = [(0, 0), (10, 0), (10, 10), (20, 5), (30, 30)]
    c.SetGrpBufferMode(0, BM_LOW)
    for p in pts[1:]:
        c.LineAbs2D(0, *p)
    rec.run()
    tol = 100 * 0.05 / 4 + 1e-6
    for p in rec.poses:
        assert min(distance_to_segment(p, a, b) for a, b in zip(pts, pts[1:])) <= tol


def test_deferred_lookahead_pass_changes_nothing(monkeypatch):
    """The backward pass deferred beyond the braking horizon gives the same path, cycle
    for cycle, as a pass on every append."""
    import random

    from motionvm.motion.group_plan import PathPlanner

    def run() -> list[list[float]]:
        c = grouped(2)
        c.SetGrpBufferMode(0, BM_LOOKAHEAD)
        c.SetGrpQueueSize(0, 10)
        rnd = random.Random(3)
        x = y = 0.0
        rec = Recorder(c)
        for _ in range(600):
            x += rnd.uniform(0.1, 0.5)
            y += rnd.uniform(-0.3, 0.3)
            assert c.LineAbs2D(0, x, y) == 0
            rec.step()
        rec.run()
        return rec.poses

    deferred = run()
    monkeypatch.setattr(PathPlanner, "_horizon", lambda self: math.inf)
    assert run() == deferred


def test_collinear_short_segments_cruise_at_the_feed():
    """Look-ahead: 400 collinear 0.5 mm segments run at the programmed feed."""
    c = grouped(2)
    c.SetGrpBufferMode(0, BM_LOOKAHEAD)
    rec = Recorder(c)
    for i in range(1, 401):
        c.LineAbs2D(0, 0.5 * i, 0.25 * i)
    rec.run()
    feed = c.GetGrpMaxVel(0)
    assert max(rec.speeds) == pytest.approx(feed, rel=1e-9)
    cruising = [v for v in rec.path_speeds if v == pytest.approx(feed, rel=1e-9)]
    assert len(cruising) > 0.8 * (400 * 0.5 * math.hypot(1, 0.5) / feed) / 0.001


def test_stepping_and_skipping_give_the_same_run(tmp_path):
    from motionvm.api import Simulation

    src = tmp_path / "g.hmpl"
    src.write_text(
        "void main() {\n"
        "    Enable(0); Enable(1); Till(IsEnabled(0) && IsEnabled(1));\n"
        "    SetupGroup(0, 0, 1);\n"
        "    LineAbs2D(0, 10, 20); Till(IsGrpInPos(0)); Sleep(500);\n"
        "    ArcCW2D(0, 10, 10, 10, 0); Till(IsGrpInPos(0));\n"
        '    Print("%.6f %.6f", GetPosFb(0), GetPosFb(1));\n'
        "}\n"
    )
    runs = []
    for skip in (True, False):
        with Simulation.from_files([str(src)], stamp=True, skip=skip) as sim:
            sim.run(timeout=30)
            runs.append(sim.messages)
    assert runs[0] == runs[1] and runs[0][0].endswith("10.000000 0.000000")
