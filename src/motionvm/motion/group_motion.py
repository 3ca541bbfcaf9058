"""Group motion commands turned into planned segments (manual 8.2, 8.5, 8.1.4, 8.1.5).

`queue_line`, `queue_arc` and `jog` take poses already in machine coordinates (MCS; the
command layer converts from the group's coordinate system) and queue one segment on
the group's planner, with:

- the feed: the translation profile (the command's motion_profile, or the group's) on
  the translation length, the rotation profile on the rotation length; the one that
  takes longer (closed-form T-curve time, `rest_to_rest_time`) is the path length the
  segment is planned in (manual 8.1);
- the axes' limits (`_axis_caps`, see motion/group.py);
- the junction from the segment before (its buffer mode, 8.1.4; `junction`);
- the transition curve at the corner (the new segment's transition mode, 8.1.5;
  `_transition`).

Decisions where the manual is silent: a target outside an axis's software limits is
refused (eERR_CRD_CMD_INVALID_POS; an arc that bulges past a limit stops there, the
group in error stop). The buffer mode of a segment governs the hand-over
at its end (BM_PREV: the speed of this segment, BM_NEXT: of the one after), except
BM_ABORT, which acts when the command arrives: the path brakes to rest at the
deceleration and the new segment starts from there. Two segments planned in different
units (one translating, one only rotating) meet at rest. The transition mode of a
segment governs the corner at its start; the blend curve runs at trans_vel (or the
lower feed when trans_vel is 0) whatever the buffer modes, tangent to both neighbours.
Transition distances: TM_CORNER_DIST and TM_CONST_VEL trim trans_dis from both
segments; TM_MAX_CORNER_DEV trims at most trans_dis, less if the blend would leave the
corner by more than trans_dev (deviation = d/2 * cos(theta/2), theta the corner angle);
TM_MAX_CORNER_CURV trims so that the blend's curvature is trans_curv at most
(kappa = 4 sin(theta) / (d (2 - 2 cos(theta))^1.5)). A trim longer than what is left of
either segment, a parameter of 0 that the mode needs, or a trim below the position
resolution at the corner (`P_TOL`, `_resolved`) leaves the corner as it is.
Look-ahead corner speed: V_corner = A_corner * T_w / |t_1 - t_0| (T_w the smoothing
window, at least one cycle; t the unit directions): the velocity turns over T_w with at
most A_corner. The manual's table writes the denominator as 1 - cos(theta); this form
bounds the acceleration the same for every angle.
"""

from __future__ import annotations

import math

from motionvm.motion.group import (
    CRD_INVALID_MOVING,
    CRD_INVALID_POS,
    CRD_QUEUE_FULL,
    AxisGroup,
)
from motionvm.motion.group_path import Arc, Line, blend, turn_angle
from motionvm.motion.group_plan import (
    BM_ABORT,
    BM_BUFF,
    BM_HIGH,
    BM_LOOKAHEAD,
    BM_LOW,
    BM_NEXT,
    BM_PREV,
    Planned,
)
from motionvm.motion.tcurve import rest_to_rest_time
from motionvm.motion.tolerances import P_TOL

TM_NONE, TM_START_VEL, TM_CONST_VEL, TM_CORNER_DIST, TM_MAX_CORNER_DEV, TM_MAX_CORNER_CURV = range(
    6
)
JOG_LENGTH = 1e9
"""Length [mm or deg] of the segment a jog runs on (it ends by StopGroup or a limit)."""


def _axis_limits(group: AxisGroup) -> tuple[list[float], list[float]]:
    return [a.pg.v_max for a in group.axes], [a.pg.a_max for a in group.axes]


def _rates(geom, rot: bool, length: float) -> list[float]:
    """Upper bounds of |d pose_i / d u| along the segment."""
    n = geom.n
    out = []
    for i in range(n):
        delta = abs(geom.end[i] - geom.start[i])
        if isinstance(geom, Line):
            out.append(delta / length if length > 0.0 else 0.0)
        elif i < 3 and not rot:
            out.append(1.0)
        else:
            out.append(2.0 * delta / length if length > 0.0 else 0.0)
    return out


def _axis_caps(group: AxisGroup, geom, rot: bool, length: float, a: float, d: float):
    """(v_phys, a, d) of a segment within every axis's velocity and half its acceleration."""
    v_max, a_max = _axis_limits(group)
    v_cap = math.inf
    for rate, vm, am in zip(_rates(geom, rot, length), v_max, a_max):
        if rate > 0.0:
            v_cap = min(v_cap, vm / rate)
            a = min(a, 0.5 * am / rate)
            d = min(d, 0.5 * am / rate)
    k = geom.lt / length if length > 0.0 else 0.0  # translation [mm] per unit of path
    if k > 0.0 and math.isfinite(geom.radius):
        v_cap = min(v_cap, math.sqrt(_a_corner_phys(group) * geom.radius) / k)
    turn = getattr(geom, "max_turn", 0.0)  # a blend's corners, each spread over T_w
    if k > 0.0 and turn > 0.0:
        v_cap = min(v_cap, _a_corner_phys(group) * group.planner.window_time / (turn * k))
    return v_cap, a, d


def _a_corner_phys(group: AxisGroup) -> float:
    """Acceleration [mm/s^2] left for corners and arcs: half the weakest translation axis's."""
    accs = [a.pg.a_max for a in group.axes[:3]]
    return 0.5 * min(accs) if accs else math.inf


def junction(group: AxisGroup, prev: Planned, nxt: Planned) -> tuple[float, float]:
    """(feed part, corner part) of the speed from `prev` into `nxt` (8.1.4)."""
    bm = prev.bm
    if bm in (BM_BUFF, BM_ABORT) or prev.rot != nxt.rot or prev.length <= 0.0:
        return 0.0, math.inf
    f_0, f_1 = prev.feed, nxt.feed
    if bm == BM_PREV:
        feed = f_0
    elif bm == BM_NEXT:
        feed = f_1
    elif bm == BM_HIGH:
        feed = f_0 if f_0 > f_1 else f_1
    else:  # BM_LOW, BM_LOOKAHEAD
        feed = f_0 if f_0 < f_1 else f_1
    spacing = min(prev.length, nxt.length)
    # every axis: the jump of its rate d pose_i / d u, turned over the window T_w
    corner = math.inf
    r_0, r_1 = _rate(prev, 1.0), _rate(nxt, 0.0)
    for x, y, a in zip(r_0, r_1, group.axes):
        jump = abs(y - x)
        if jump > 1e-12:
            corner = min(corner, _corner_speed(group, 0.5 * a.pg.a_max, jump, spacing))
    if bm == BM_LOOKAHEAD and not prev.rot:
        t_0, t_1 = prev.geom.tangent(1.0), nxt.geom.tangent(0.0)
        dt_norm = math.sqrt(sum((x - y) ** 2 for x, y in zip(t_0, t_1)))
        if dt_norm > 1e-12:
            corner = min(corner, _corner_speed(group, group.lookahead[0], dt_norm, spacing))
    return feed, corner


def _rate(seg: Planned, f: float) -> list[float]:
    """d pose / d u [per path unit] of a segment at its start (f 0) or end (f 1)."""
    geom, length = seg.geom, seg.length
    if length <= 0.0:
        return [0.0] * geom.n
    if isinstance(geom, Line):
        return [(e - s) / length for s, e in zip(geom.start, geom.end)]
    eps = 1e-6
    a, b = (
        (geom.point(1.0 - eps), geom.point(1.0)) if f >= 1.0 else (geom.point(0.0), geom.point(eps))
    )
    return [(y - x) / (eps * length) for x, y in zip(a, b)]


def _corner_speed(group: AxisGroup, acc: float, dt_norm: float, spacing: float) -> float:
    """The speed [mm/s] at which the velocity's turn |t_1 - t_0| at a corner takes `acc`:
    spread over the smoothing window T_w (an isolated corner), or, with corners closer
    than the path of one window, over the time to the next one (a polyline that
    approximates a curve: then like an arc of radius spacing / turn)."""
    t_w = group.planner.window_time
    return min(acc * t_w / dt_norm, math.sqrt(acc * 0.5 * spacing / dt_norm))


def _lookahead_arc(group: AxisGroup, geom) -> float:
    r = geom.radius
    if not math.isfinite(r):
        return math.inf
    v = math.sqrt(group.lookahead[1] * r)
    eps = group.lookahead[2]
    if 0.0 < eps < r:
        v = min(v, 2.0 * r * math.sin(math.acos(1.0 - eps / r)) / group.dt)
    return v


def make_segment(group: AxisGroup, geom, profile, bm: int) -> Planned:
    """A `Planned` of `geom` with the translation `profile` (vel, acc, dec, sm) or the
    group's, and the group's rotation profile."""
    vel, acc, dec = profile[0], profile[1], profile[2]
    ang = group.ang
    rot = False
    if geom.lr > 0.0:
        t_lin = rest_to_rest_time(geom.lt, vel, acc, dec) if vel > 0.0 else math.inf
        t_rot = rest_to_rest_time(geom.lr, ang.vel, ang.acc, ang.dec)
        rot = t_rot > t_lin or geom.lt == 0.0
    if rot:
        vel, acc, dec = ang.vel, ang.acc, ang.dec
    length = geom.lr if rot else geom.lt
    v_phys, acc, dec = _axis_caps(group, geom, rot, length, acc, dec)
    v_arc = _lookahead_arc(group, geom) if bm == BM_LOOKAHEAD and not rot else math.inf
    return Planned(geom, rot, vel, acc, dec, bm, v_phys, v_arc)


def _check_queue(group: AxisGroup) -> None:
    group.require_motion()
    if group.jogging:
        raise group.fail(CRD_INVALID_MOVING, "is jogging (call StopGroup first)")
    if len(group.planner.queue) + len(group.planner._pending) >= group.queue_size:
        raise group.fail(CRD_QUEUE_FULL, f"its queue of {group.queue_size} commands is full")


def _trim_length(group: AxisGroup, tm: int, prm, alpha: float) -> float:
    """The trim d [mm] of a corner with turn angle alpha [rad]; 0: no transition."""
    trans_vel, dis, dev, curv = prm
    theta = math.pi - alpha  # the corner angle
    if tm in (TM_CONST_VEL, TM_CORNER_DIST):
        return dis
    if tm == TM_MAX_CORNER_DEV:
        if dev <= 0.0:
            return 0.0
        d = 2.0 * dev / math.cos(theta / 2.0)
        return min(d, dis) if dis > 0.0 else d
    if tm == TM_MAX_CORNER_CURV:
        if curv <= 0.0:
            return 0.0
        # the limit divides last: curv * (...) of a subnormal curv is 0 (inf here: no blend)
        return 4.0 * math.sin(theta) / (2.0 - 2.0 * math.cos(theta)) ** 1.5 / curv
    return 0.0


def _resolved(d: float, corner) -> bool:
    """True if a trim of d [mm] at `corner` is above the position resolution there
    (`P_TOL`, relative to the corner's coordinates beyond 1 mm). A smaller trim would
    make a blend of rounding noise: points that differ by the rounding of the
    coordinates, a length of noise (7e-15 mm from a 1e-100 mm trim) and kinks whose
    radius (1e-127 mm next to a zero coordinate) caps its speed near zero, a path that
    never ends. Such a trim rounds the corner by less than `P_TOL`: the corner stays."""
    return d > P_TOL * max(1.0, max(abs(x) for x in corner[:3]))


def _transition(group: AxisGroup, prev: Planned, new_geom, tm: int, prm):
    """Trim `prev` and `new_geom` at their corner; (blend geometry, trimmed new geometry,
    prev changed while running) or None if the corner stays."""
    if tm == TM_NONE or prev.rot or new_geom.lt <= 0.0 or prev.length <= 0.0:
        return None
    q = group.planner.queue
    running = q and q[0] is prev and group.planner.mode != "idle"
    t_0, t_1 = prev.geom.tangent(1.0), new_geom.tangent(0.0)
    alpha = turn_angle(t_0, t_1)
    if alpha < 1e-6 or alpha > math.pi - 1e-6:
        return None
    d = _trim_length(group, tm, prm, alpha)
    left = prev.length - (group.planner.u if running else 0.0)
    if not (_resolved(d, prev.geom.end) and d <= left and d <= new_geom.lt):
        return None
    f_cut = 1.0 - d / prev.length
    p_geom = prev.geom.sub(0.0, f_cut)
    n_geom = new_geom.sub(d / new_geom.lt, 1.0) if d < new_geom.lt else None
    tc_0 = prev.geom.tangent(f_cut)
    tc_1 = new_geom.tangent(d / new_geom.lt)
    b = blend(p_geom.end, tc_0, new_geom.point(d / new_geom.lt) if n_geom else new_geom.end,
              tc_1, d, d)  # fmt: skip
    prev.geom = p_geom
    prev.length = p_geom.lt
    return b, n_geom, running


def queue_geometry(group: AxisGroup, geom, profile, bm: int, tm: int, prm) -> None:
    """Queue one segment of `geom` (a Line or an Arc in MCS) with buffer mode `bm` and
    transition mode `tm` (parameters `prm`)."""
    _check_queue(group)
    for a, x in zip(group.axes, geom.end):
        if not (a.ignore_swl or a.rollover) and not a.sw_left <= x <= a.sw_right:
            raise group.fail(CRD_INVALID_POS, f"axis {a.axis_id}: target {x:g} is outside its "
                             f"software limits {a.sw_left:g} .. {a.sw_right:g}")  # fmt: skip
    planner = group.planner
    if bm == BM_ABORT and planner.active:
        start = planner.stop()
        geom = _restart(geom, start)
        seg = make_segment(group, geom, profile, bm)
        planner.after_stop(seg)
        group.last_end = list(geom.end)
        return
    q = planner.queue
    prev = q[-1] if q and not planner._pending else None
    if prev is not None:
        tr = _transition(group, prev, geom, tm, prm)
        if tr is not None:
            b_geom, n_geom, changed = tr
            v_b = prm[0] if prm[0] > 0.0 else min(prev.feed, profile[0])
            b_seg = make_segment(group, b_geom, (v_b, profile[1], profile[2]), BM_LOW)
            planner.append(b_seg, min(prev.feed, v_b), math.inf, replan=changed)
            if n_geom is None:
                group.last_end = list(geom.end)
                return
            geom = n_geom
            seg = make_segment(group, geom, profile, bm)
            planner.append(seg, min(v_b, seg.feed), math.inf)
            group.last_end = list(geom.end)
            return
    seg = make_segment(group, geom, profile, bm)
    if prev is not None:
        feed, corner = junction(group, prev, seg)
        planner.append(seg, feed, corner)
    else:
        planner.set_smoothing(profile[3] / 1000.0)
        planner.append(seg)
    group.last_end = list(geom.end)


def _restart(geom, start):
    """The same segment kind from a new start (BM_ABORT): a line to the target, or the
    arc about the same centre (from the start's angle) to the same end."""
    if isinstance(geom, Arc):
        from motionvm.motion.group_path import sweep

        phi = sweep(start, geom.end, geom.center, geom.normal, 1 if geom.phi > 0 else -1)
        return Arc(start, geom.end, geom.center, geom.normal, phi)
    return Line(start, geom.end)


def queue_line(group: AxisGroup, target, profile, bm: int, tm: int, prm) -> None:
    start = group.end_pose()
    queue_geometry(group, Line(start, target), profile, bm, tm, prm)


def queue_arc(group: AxisGroup, center, normal, phi: float, target, profile, bm, tm, prm):
    start = group.end_pose()
    queue_geometry(group, Arc(start, target, center, normal, phi), profile, bm, tm, prm)


def jog(group: AxisGroup, dim: int, vel: float) -> None:
    """JogGroup / JogGroupAxis: move coordinate `dim` at `vel` until StopGroup (0: stop)."""
    group.require_motion()
    planner = group.planner
    if vel == 0.0:
        if group.jogging:
            group.stop()
        return
    if planner.active and not group.jogging:
        raise group.fail(CRD_INVALID_MOVING, "is moving")
    if group.jogging:
        planner.stop()
    start = group.end_pose() if not planner.active else planner.stop()
    target = list(start)
    target[dim] += math.copysign(JOG_LENGTH, vel)
    prof = group.lin if dim < 3 else group.ang
    geom = Line(start, target)
    rot = dim >= 3
    length = geom.lr if rot else geom.lt
    v_phys, acc, dec = _axis_caps(group, geom, rot, length, prof.acc, prof.dec)
    seg = Planned(geom, rot, min(abs(vel), prof.vel), acc, dec, BM_BUFF, v_phys)
    if planner.active:
        planner.after_stop(seg)
    else:
        planner.set_smoothing(prof.sm_ms / 1000.0)
        planner.append(seg)
    group.jogging = True
    group.last_end = None
