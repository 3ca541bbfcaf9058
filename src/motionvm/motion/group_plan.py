"""The path profile of an axis group: velocity look-ahead over the queued segments, a
closed-form T-curve per segment in path length, and the moving-average smoothing (8.1, 8.1.4).

Each queued segment (`Planned`) has a path length `length` (its translation length in
mm, or its rotation length in deg when the rotation profile takes longer: the feed
follows the slower of the two, manual 8.1) and limits `v_cap` (the programmed feed
times the velocity scale, capped by what the axes can do), `a`, `d`. Between a segment
and the next a junction speed `j_cap` applies (the buffer mode of the segment, 8.1.4):

    BM_BUFF 0 (stop), BM_LOW min(f_k, f_k+1), BM_PREV f_k, BM_NEXT f_k+1, BM_HIGH max,
    BM_LOOKAHEAD min(f_k, f_k+1, V_corner, V_arc, V_chord),

always capped by the corner limit of the axes (`corner_speed`). A backward pass gives
each segment the highest exit speed `v_end` from which every later junction, down to a
stop at the end of the queue, can still be met at the deceleration; appending a segment
only raises exit speeds, so the pass stops at the first segment it does not change.

The segment being run has a plan (`segment_profile`): ramp from the entry speed to a
cruise speed, cruise, ramp to the exit speed, constant accelerations `a` (speeding up)
and `d` (slowing down), landing exactly on the segment's end. The plan is redone from
the present state when the exit speed, the velocity scale or a halt changes it.

The path position of a cycle is the plan evaluated at a time counted from the cycle the
plan began in (`_t0 + n * dt`, never a running sum), so that any cycle of a plan can be
computed directly (`advance`, time skipping).

The raw pose (the geometry at the path position) is averaged over the last N cycles,
N = round(Ts / dt) (the smoothing time of 5.1: jerk = acceleration / Ts), in every
coordinate (motion/group_average.py): corners passed at speed are rounded over Ts
instead of jolting the axes. The averaged pose then passes through `command_filter` (None, or a callable pose -> pose:
the hook where a group input shaper plugs in; see `PathPlanner.command_filter`) and is
the group's commanded pose.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from collections import deque
from operator import sub as _sub

from motionvm.motion.group_average import PoseAverage

IDLE, RUN, BRAKE, PAUSED = "idle", "run", "brake", "paused"

BM_BUFF, BM_ABORT, BM_LOW, BM_PREV, BM_NEXT, BM_HIGH, BM_LOOKAHEAD = range(7)


def segment_profile(u_0: float, length: float, v_0: float, v_1: float, v_max: float,
                    a: float, d: float) -> tuple[list[tuple], float, float]:  # fmt: skip
    """Pieces `(t_0, t_1, u_0, v_0, acc)` from (u_0, v_0) to the end `length` with exit
    speed at most v_1; returns (pieces, duration [s], exit speed [path unit/s])."""
    dist = length - u_0
    if dist <= 0.0:
        return [], 0.0, v_0
    v_1 = min(v_1, math.sqrt(v_0 * v_0 + 2.0 * a * dist))
    if v_0 * v_0 - v_1 * v_1 > 2.0 * d * dist:  # cannot slow down in time: as fast as possible
        v_1 = math.sqrt(max(0.0, v_0 * v_0 - 2.0 * d * dist))

    def ramp(x: float, y: float) -> float:
        return (y * y - x * x) / (2.0 * a) if y >= x else (x * x - y * y) / (2.0 * d)

    v_c: float | None
    if ramp(v_0, v_max) + ramp(v_max, v_1) <= dist:
        v_c = v_max
    elif v_max >= max(v_0, v_1):
        v_c = math.sqrt((2.0 * a * d * dist + d * v_0 * v_0 + a * v_1 * v_1) / (a + d))
        v_c = min(max(v_c, v_0, v_1), v_max)
    else:
        v_c = None
    pieces: list[tuple] = []
    t, u, v = 0.0, u_0, v_0

    def add(duration: float, acc: float) -> None:
        nonlocal t, u, v
        if duration <= 0.0:
            return
        pieces.append((t, t + duration, u, v, acc))
        u += (v + 0.5 * acc * duration) * duration
        v += acc * duration
        t += duration

    if v_c is not None:
        if v_c != v_0:
            add(
                abs(v_c - v_0) / (a if v_c > v_0 else d),
                math.copysign(a if v_c > v_0 else d, v_c - v_0),
            )
            v = v_c
        cruise = (length - u) - ramp(v_c, v_1)
        if cruise > 0.0 and v_c > 0.0:
            add(cruise / v_c, 0.0)
    rem = length - u
    if rem > 0.0 and v + v_1 > 0.0:
        dur = 2.0 * rem / (v + v_1)
        add(dur, (v_1 - v) / dur)
    return pieces, t, v_1


def _plan_last(t_0: float, n_0: int, dur: float, dt: float) -> int:
    """The last cycle c (counted from the plan's cycle n_0, c >= 0) whose plan time
    t_0 + (n_0 + c) * dt is before the plan's end `dur` (the cycle after it ends it)."""
    c = max(0, int((dur - t_0) / dt) - n_0)
    while c > 0 and t_0 + (n_0 + c) * dt >= dur:
        c -= 1
    while t_0 + (n_0 + c + 1) * dt < dur:
        c += 1
    return c


class Planned:
    """One queued segment: its geometry and what the planner needs of it."""

    __slots__ = ("a", "bm", "d", "feed", "geom", "j_cap", "j_lim", "j_phys", "length", "rot", "s0", "v_cap",
                 "v_end", "v_phys", "v_arc")  # fmt: skip

    def __init__(self, geom, rot: bool, feed: float, a: float, d: float, bm: int,
                 v_phys: float, v_arc: float = math.inf):  # fmt: skip
        self.geom = geom
        self.rot = rot
        """True if the path length is the rotation length [deg] (rotation is slower)."""
        self.length = geom.lr if rot else geom.lt
        self.feed, self.a, self.d, self.bm = feed, a, d, bm
        self.v_phys = v_phys
        """Speed the axes allow on this segment [unit/s] (their velocity, arc limits)."""
        self.v_arc = v_arc
        """Look-ahead arc and chord speed limit [unit/s] (inf unless BM_LOOKAHEAD)."""
        self.v_cap = min(feed, v_phys)
        self.j_cap = 0.0
        """Junction speed into the next segment from the feeds [unit/s], times the scale."""
        self.j_phys = math.inf
        """Junction speed the corner allows [unit/s] (the axes, look-ahead), not scaled."""
        self.j_lim = 0.0
        """min(j_cap * scale, j_phys): the junction speed limit [unit/s]."""
        self.s0 = 0.0
        """Path position [unit] of the segment's start, counted from the first queued one."""
        self.v_end = 0.0


class PathPlanner:
    """The path position of one group, stepped once per cycle (see the module docstring)."""

    def __init__(self, dt: float, pose) -> None:
        self.dt = dt
        self._inv_dt = 1.0 / dt
        self.queue: deque[Planned] = deque()
        self.scale = 1.0
        self.halted = False
        self.mode = IDLE
        self.u = self.v = self.acc = 0.0
        """Path position in the current segment [unit], speed [unit/s], acceleration."""
        self.s_done = 0.0
        """Path length [unit] of the segments finished since the path last started from rest."""
        self._pieces: list[tuple] = []
        self._pi = 0
        self._t0 = 0.0  # the plan's time [s] at cycle 0 of it
        self._n = 0  # cycles since the plan began: its time is _t0 + _n * dt
        self._dur = 0.0
        self._v_exit = 0.0
        self._stopping = False
        self._dwell = 0
        self._stale: Planned | None = None  # where a deferred backward pass begins
        self._v_hi = 0.0  # highest cap or junction speed queued [unit/s]
        self._d_lo = math.inf  # lowest deceleration queued [unit/s^2]
        self._pending: list[Planned] = []
        self._bounds_memo: tuple | None = None  # (`_segment_bounds`)
        self._room_plans: list[tuple] = []  # (`_room_across`)
        self._room_catch = 0  # the cycle `_room_catch_up` runs the deferred pass in (0: none)
        self._profiles: dict[tuple, tuple] = {}  # the plans `_room_across` looked ahead at
        self.raw = list(pose)
        """The pose at the path position (before smoothing)."""
        self.command_filter = None
        """None or a callable pose -> pose applied to every commanded pose after the
        smoothing, once per cycle while the group moves (the hook of a group input
        shaper); it may have a `busy` attribute, True while its output would still change
        with a constant input (a shaper's tail), which keeps the group moving."""
        self._n_avg = 1
        self._avg = PoseAverage(1, self.raw)
        self.out = list(pose)
        """The commanded pose of the last cycle (smoothed, filtered)."""
        self.out_vel = [0.0] * len(self.raw)
        self.out_acc = [0.0] * len(self.raw)
        self.window_time = dt
        """The averaging window [s] (at least one cycle): corners take this long."""

    # ---- queries --------------------------------------------------------------------

    @property
    def active(self) -> bool:
        """True while the path moves or the smoothing (or the command filter: its `busy`)
        still changes the output."""
        return (self.mode != IDLE or self._avg.flush < self._n_avg or any(self.out_vel)
                or getattr(self.command_filter, "busy", False))  # fmt: skip

    @property
    def path_pos(self) -> float:
        """grp_pg_pos: path length [unit] from where the path last started from rest."""
        return self.s_done + self.u

    @property
    def waiting(self) -> bool:
        """True while halted (or at a zero scale) with motion left to do."""
        return self.mode == PAUSED

    # ---- set-up ---------------------------------------------------------------------

    def set_smoothing(self, t_smooth: float) -> None:
        """Averaging window Ts [s]; takes effect only while the path rests."""
        if self.active:
            return
        self._n_avg = max(1, round(t_smooth / self.dt))
        self.window_time = self._n_avg * self.dt
        self._reset_window(self.out)

    def reset(self, pose) -> None:
        """Drop every segment and hold `pose` (enable, disable)."""
        self.queue.clear()
        self.mode = IDLE
        self.halted = False
        self.u = self.v = self.acc = 0.0
        self.raw = list(pose)
        self.out = list(pose)
        self.out_vel = [0.0] * len(pose)
        self.out_acc = [0.0] * len(pose)
        self._reset_window(pose)

    def _reset_window(self, pose) -> None:
        self._avg = PoseAverage(self._n_avg, pose)

    # ---- the queue ------------------------------------------------------------------

    def append(self, seg: Planned, j_cap_prev: float = 0.0, j_phys_prev: float = math.inf,
               replan: bool = False) -> None:  # fmt: skip
        """Queue `seg`; `j_cap_prev`, `j_phys_prev` are the junction speeds from the last
        queued segment into it; `replan`: the running segment was changed (trimmed).

        The backward pass is deferred while the new segment lies beyond the braking
        horizon of the running one (`_horizon`): nothing there can change the running
        segment's plan yet. `_maybe_catch_up` runs it once the path comes near."""
        seg.v_cap = min(seg.feed * self.scale, seg.v_phys, seg.v_arc)
        q = self.queue
        if q:
            prev = q[-1]
            prev.j_cap = j_cap_prev
            # a junction never exceeds what the axes allow on either side
            prev.j_phys = min(j_phys_prev, prev.v_phys, prev.v_arc, seg.v_phys, seg.v_arc)
            prev.j_lim = min(j_cap_prev * self.scale, prev.j_phys)
            seg.s0 = prev.s0 + prev.length
            if prev.j_lim > self._v_hi:
                self._v_hi = prev.j_lim
        else:
            seg.s0 = 0.0
            self._v_hi, self._d_lo, self._stale = 0.0, math.inf, None
        if seg.v_cap > self._v_hi:
            self._v_hi = seg.v_cap
        if seg.d < self._d_lo:
            self._d_lo = seg.d
        q.append(seg)
        seg.v_end = 0.0
        if self.mode == RUN and not replan and len(q) > 1:
            if self._stale is not None:
                return
            if seg.s0 - (q[0].s0 + self.u) > self._horizon():
                self._stale = q[-2]
                return
        if self._stale is not None:
            self._catch_up()
        if (self._backward(len(q) - 2) or replan) and self.mode == RUN:
            self._replan()
        if self.mode == IDLE:
            self._start()

    def _horizon(self) -> float:
        """Path length [unit] beyond which no exit speed can bind the running segment:
        the braking distance from the highest speed queued, with a margin."""
        return 1.5 * self._v_hi * self._v_hi / (2.0 * self._d_lo) + 1e-9

    def _maybe_catch_up(self) -> bool:
        """Run a deferred backward pass if the path has come near; True if the running
        segment's exit speed changed."""
        stale = self._stale
        q = self.queue
        if stale is None or not q:
            return False
        if self._far(self.u):
            return False
        return self._catch_up()

    def _catch_up(self) -> bool:
        """The deferred backward pass: from the last segment down, past the segment the
        deferral began at, until an exit speed does not change (`_catch_up_preview`'s
        exit speeds, applied)."""
        changed, v_ends = self._catch_up_preview()
        self._stale = None
        for seg, v in v_ends.items():
            seg.v_end = v
        return changed

    def _backward(self, i: int) -> bool:
        """Backward pass from segment i (the one before the last) down; True if the
        running segment's exit speed changed. Speeds are compared squared: no sqrt
        where the junction's own limit binds."""
        q = self.queue
        it = reversed(q)
        nxt = next(it)
        v2 = nxt.v_end * nxt.v_end + 2.0 * nxt.d * nxt.length
        sqrt = math.sqrt
        for seg in it:
            lim = seg.j_lim
            v = lim if lim * lim <= v2 else sqrt(v2)
            if v == seg.v_end:
                return False
            seg.v_end = v
            if i == 0:
                return True
            i -= 1
            v2 = v * v + 2.0 * seg.d * seg.length
        return False

    def rescan(self) -> None:
        """Recompute every cap and exit speed (a new scale); replan the running segment."""
        q = self.queue
        self._stale = None
        self._v_hi = 0.0
        for seg in q:
            seg.v_cap = min(seg.feed * self.scale, seg.v_phys, seg.v_arc)
            seg.j_lim = min(seg.j_cap * self.scale, seg.j_phys)
            self._v_hi = max(self._v_hi, seg.v_cap, seg.j_lim)
        if q:
            q[-1].v_end = 0.0
            for i in range(len(q) - 2, -1, -1):
                nxt, seg = q[i + 1], q[i]
                seg.j_lim = min(seg.j_cap * self.scale, seg.j_phys)
                seg.v_end = min(seg.j_lim, math.sqrt(nxt.v_end**2 + 2.0 * nxt.d * nxt.length))
        self._update_mode()

    def set_scale(self, scale: float) -> None:
        self.scale = scale
        self.rescan()

    def halt(self) -> None:
        self.halted = True
        self._update_mode()

    def resume(self) -> None:
        self.halted = False
        self._update_mode()

    def stop(self) -> list[float]:
        """Brake to rest along the path at the deceleration and drop what lies beyond;
        returns the pose where the path will rest."""
        self.halted = False
        self._pending = []
        self._stale = None
        q = self.queue
        if self.mode in (IDLE, PAUSED):
            self._finish_at(self.u)
            return list(self.raw)
        dist = self.v * self.v / (2.0 * q[0].d)
        rem = self.u + dist
        k = 0
        while k < len(q) - 1 and rem > q[k].length:
            rem -= q[k].length
            k += 1
        while len(q) > k + 1:
            q.pop()
        seg = q[k]
        rem = min(rem, seg.length)
        pose = seg.geom.point(rem / seg.length) if seg.length > 0.0 else list(seg.geom.end)
        self._brake()
        self._stopping = True
        return pose

    def after_stop(self, seg: Planned) -> None:
        """Queue `seg` to start when the braking of `stop` ends (BM_ABORT)."""
        if self.mode == IDLE:
            self.append(seg)
        else:
            self._pending.append(seg)

    def _update_mode(self) -> None:
        if not self.queue:
            return
        if self.halted or self.scale == 0.0:
            if self.mode == RUN:
                self._brake()
            elif self.mode == IDLE:
                self.mode = PAUSED
        elif self.mode in (RUN, PAUSED, IDLE):
            self._replan()
            self.mode = RUN
        elif self.mode == BRAKE and not self._stopping:
            self._replan()
            self.mode = RUN

    def _start(self) -> None:
        if not self.queue:
            return
        self.u = self.v = 0.0
        self.s_done = 0.0
        self._stopping = False
        if self.halted or self.scale == 0.0:
            self.mode = PAUSED
            return
        self._replan()
        self.mode = RUN

    def _set_pieces(self, pieces, duration) -> None:
        self._pieces = pieces
        self._pi = 0
        self._t0 = 0.0
        self._n = 0
        self._dur = duration

    def _replan(self) -> None:
        self._dwell = 0
        self._maybe_catch_up()
        seg = self.queue[0]
        pieces, dur, v_1 = segment_profile(self.u, seg.length, self.v, seg.v_end, seg.v_cap,
                                           seg.a, seg.d)  # fmt: skip
        self._set_pieces(pieces, dur)
        self._v_exit = v_1
        self.mode = RUN

    def _brake(self) -> None:
        self._dwell = 0
        seg = self.queue[0]
        d = seg.d
        dur = self.v / d
        self._set_pieces([(0.0, dur, self.u, self.v, -d)] if dur > 0.0 else [], dur)
        self._v_exit = 0.0
        self.mode = BRAKE

    # ---- the cycle ------------------------------------------------------------------

    def _eval(self, t: float) -> tuple[float, float, float]:
        self._pi = i = self._piece_at(t)
        return self._on_piece(i, t)

    def _eval_at(self, t: float) -> float:
        """The path position [unit] `_eval(t)` gives, for t at or after the present
        time, leaving the piece index as it is."""
        return self._on_piece(self._piece_at(t), t)[0]

    def _piece_at(self, t: float) -> int:
        """The index of the piece time `t` (at or after the present) falls in."""
        pieces = self._pieces
        i = self._pi
        while i < len(pieces) and t >= pieces[i][1]:
            i += 1
        return i

    def _on_piece(self, i: int, t: float) -> tuple[float, float, float]:
        """(u, v, a) at time `t` on piece `i`; past the last piece, where it ended."""
        pieces = self._pieces
        if i >= len(pieces):
            if pieces:
                t_0, t_1, u_0, v_0, a = pieces[-1]
                x = t_1 - t_0
                return u_0 + (v_0 + 0.5 * a * x) * x, v_0 + a * x, 0.0
            return self.u, self.v, 0.0
        t_0, _t_1, u_0, v_0, a = pieces[i]
        x = t - t_0
        return u_0 + (v_0 + 0.5 * a * x) * x, v_0 + a * x, a

    def _positions(self, c_0: int, c_1: int) -> list[float]:
        """The path positions [unit] `_eval_at` gives at the times of cycles c_0 .. c_1
        of the plan (c_0 >= 1: from the present time on), a piece at a time."""
        dt, t_0, n_0 = self.dt, self._t0, self._n
        ts = [t_0 + (n_0 + c) * dt for c in range(c_0, c_1 + 1)]
        pieces = self._pieces
        i, m = self._pi, len(pieces)
        us: list[float] = []
        lo, hi = 0, len(ts)
        while lo < hi:
            t = ts[lo]
            while i < m and t >= pieces[i][1]:
                i += 1
            if i >= m:  # past the plan's end: its end position
                us += [self._eval_at(t)] * (hi - lo)
                break
            p_t0, p_t1, u_0, v_0, a = pieces[i]
            end = bisect_left(ts, p_t1, lo, hi)  # (the times grow with the cycle)
            us += [u_0 + (v_0 + 0.5 * a * x) * x for x in [t - p_t0 for t in ts[lo:end]]]
            lo = end
        return us

    def _advance(self) -> None:
        """The path position of the next cycle (RUN or BRAKE)."""
        if self._dwell:
            self._dwell -= 1
            if not self._dwell:
                self._replan()
            return
        n = self._n + 1
        t = self._t0 + n * self.dt
        q = self.queue
        if self.mode == BRAKE:
            if t >= self._dur:
                u, v, acc = self._eval(self._dur)
                v, acc = 0.0, 0.0
                done = True
            else:
                u, v, acc = self._eval(t)
                done = False
            while q and u > q[0].length and len(q) > 1:
                u -= q[0].length
                self.s_done += q.popleft().length
            if q and u >= q[0].length:
                u = q[0].length
            self._n, self.u, self.v, self.acc = n, u, v, acc
            if done:
                if self._stopping or not q:
                    self._stopping = False
                    self._finish_at(u)
                else:
                    self.mode = PAUSED
            return
        while t >= self._dur:
            t -= self._dur
            n = 0  # the next plan's time starts at the remainder t
            v_in = self._v_exit
            seg = q.popleft()
            self.s_done += seg.length
            if not q:
                self.raw = list(seg.geom.end)
                self.mode = IDLE
                self.u = self.v = self.acc = 0.0
                return
            self.u, self.v = 0.0, v_in
            if v_in == 0.0 and self._n_avg > 1:
                # a stop between two segments: the output comes to rest on the corner
                # (the smoothing window fills with it) before the next one starts
                self.acc = 0.0
                self._dwell = self._n_avg - 1
                return
            self._replan()
        if n:
            self._n = n
        else:
            self._t0, self._n = t, 0
        self.u, self.v, self.acc = self._eval(t)

    def _finish_at(self, u: float) -> None:
        q = self.queue
        if q:
            seg = q[0]
            f = u / seg.length if seg.length > 0.0 else 1.0
            self.raw = seg.geom.point(f) if f < 1.0 else list(seg.geom.end)
        q.clear()
        self.mode = IDLE
        self.u = self.v = self.acc = 0.0
        pending, self._pending = self._pending, []
        for seg in pending:
            self.append(seg)
        if pending and self._n_avg > 1 and self.mode == RUN:
            self._dwell = self._n_avg - 1  # settle where the brake ended, as BM_BUFF

    def step(self) -> list[float]:
        """Advance one cycle; return the commanded pose."""
        self._path_step()
        return self._smooth()

    def _path_step(self) -> None:
        """The path position and raw pose of the next cycle (`step` before smoothing)."""
        if self._stale is not None and self.mode == RUN and self._maybe_catch_up():
            self._replan()
        if self.mode in (RUN, BRAKE):
            self._advance()
            q = self.queue
            if q and self.mode != IDLE:
                seg = q[0]
                length = seg.length
                self.raw = seg.geom.point(self.u / length) if length > 0.0 else list(seg.geom.end)

    # ---- closed-form advance (time skipping: motion/group_coast.py) -----------------

    def coast_room(self, wanted: int) -> int:
        """How many cycles (at most `wanted`) `advance` can compute from now, in which
        the planner stays active and nothing but its position, its output and its queue
        of segments changes: the path runs on inside its segment (up to the cycle before
        the segment ends; through the cycle a deferred backward pass comes due in, when
        that is inside the plan: `_room_catch_up`) and, with no pass deferred, on across
        the ends of segments it runs through at speed into the next (`_room_across`), or
        rests on a corner (up to the cycle before the next
        segment starts), halted, or while its smoothing flushes (up to the cycle before
        the output stands on the end). 0: step it. A command filter (a group input
        shaper) is stepped."""
        self._room_plans = []
        self._room_catch = 0
        if self.command_filter is not None or wanted <= 0:
            return 0
        mode = self.mode
        if mode == IDLE:
            return max(0, min(wanted, self._n_avg - 1 - self._avg.flush))
        if mode == PAUSED:
            return wanted
        if mode != RUN:
            return 0
        if self._dwell:  # (each step of a dwell tests the same position)
            if self._stale is not None and not self._far(self.u):
                return 0
            return min(wanted, self._dwell - 1)
        if not self.queue[0].length > 0.0:
            return 0
        dt, t_0, n_0, dur = self.dt, self._t0, self._n, self._dur
        c = int((dur - t_0) / dt) - n_0
        if c > wanted + 1:
            c = wanted + 1
        while c > 0 and t_0 + (n_0 + c) * dt >= dur:
            c -= 1
        k = min(wanted, c)
        if self._stale is None and k == c and k < wanted and c == _plan_last(t_0, n_0, dur, dt):
            return self._room_across(wanted, c)
        if self._stale is not None and k > 0:
            # step i tests the position of cycle i - 1 (`_maybe_catch_up`); the position
            # grows, so the first step that finds it near ends the room
            def far(i: int) -> bool:
                return self._far(self.u if i == 0 else self._eval_at(t_0 + (n_0 + i) * dt))

            if not far(k - 1):
                if not far(0):
                    return 0
                lo, hi = 0, k - 1  # far(lo) holds, far(hi) does not
                while hi - lo > 1:
                    mid = (lo + hi) // 2
                    if far(mid):
                        lo = mid
                    else:
                        hi = mid
                k = lo + 1  # steps 1 .. lo + 1 test positions 0 .. lo
                if k < wanted and k < c and c == _plan_last(t_0, n_0, dur, dt):
                    return self._room_catch_up(wanted, k, c)
        return k

    def _room_catch_up(self, wanted: int, k: int, c: int) -> int:
        """`coast_room` on from cycle k, whose next step runs the deferred backward pass
        (`_maybe_catch_up`), inside the running plan (which ends at cycle c): that
        cycle as `_path_step` makes it (the pass, and a new plan from the state of cycle
        k if the running segment's exit speed changes), then `_room_across`."""
        dt = self.dt
        changed, v_ends = self._catch_up_preview()
        seg = self.queue[0]
        if changed:
            u, v, _acc = self._state_at(self._t0 + (self._n + k) * dt)
            pieces, dur, v_1 = segment_profile(u, seg.length, v, v_ends[seg], seg.v_cap, seg.a,
                                               seg.d)  # fmt: skip
            if not dt < dur:
                return k
            self._room_plans.append((seg, pieces))
            c = k + _plan_last(0.0, 0, dur, dt)
            plan = (0.0, 0, dur, k, v_1)
        else:
            plan = (self._t0, self._n, self._dur, 0, self._v_exit)
        self._room_catch = k + 1
        return self._room_across(wanted, c, plan, v_ends)

    def _catch_up_preview(self) -> tuple[bool, dict]:
        """What `_catch_up` would do now, doing nothing: (True if the running segment's
        exit speed changes, {segment: its new exit speed})."""
        stale = self._stale
        q = self.queue
        new: dict = {}
        it = reversed(q)
        nxt = next(it)
        v2 = nxt.v_end * nxt.v_end + 2.0 * nxt.d * nxt.length
        i = len(q) - 2
        seen = False
        sqrt = math.sqrt
        for seg in it:
            lim = seg.j_lim
            v = lim if lim * lim <= v2 else sqrt(v2)
            if seg is stale:
                seen = True
            if v == seg.v_end:
                if seen:
                    return False, new
            else:
                new[seg] = v
                if i == 0:
                    return True, new
            i -= 1
            v2 = v * v + 2.0 * seg.d * seg.length
        return False, new

    def _state_at(self, t: float) -> tuple[float, float, float]:
        """What `_eval(t)` gives, for t at or after the present time, leaving the piece
        index as it is."""
        pieces = self._pieces
        i = self._pi
        while i < len(pieces) and t >= pieces[i][1]:
            i += 1
        if i >= len(pieces):
            if pieces:
                t_0, t_1, u_0, v_0, a = pieces[-1]
                x = t_1 - t_0
                return u_0 + (v_0 + 0.5 * a * x) * x, v_0 + a * x, 0.0
            return self.u, self.v, 0.0
        t_0, _t_1, u_0, v_0, a = pieces[i]
        x = t - t_0
        return u_0 + (v_0 + 0.5 * a * x) * x, v_0 + a * x, a

    def _room_across(self, wanted: int, c: int, plan: tuple | None = None,
                     v_ends: dict | None = None) -> int:  # fmt: skip
        """`coast_room` on from the last cycle c of the running plan, across the ends of
        segments that the path runs through at speed (no stop on the corner, the next
        segment queued, of some length, and its first plan longer than the rest of the
        cycle it starts in), as `_advance` would plan them; each crossing is kept in
        `_room_plans` (segment, its pieces) for `coast_bounds`. `plan`: (t_0, n_0, dur,
        the cycle of n_0, exit speed) of the plan running at cycle c if not the present
        one; `v_ends`: the segments' exit speeds where a backward pass changes them."""
        dt = self.dt
        if plan is None:
            plan = (self._t0, self._n, self._dur, 0, self._v_exit)
        t_0, n_0, dur, base, v_in = plan
        q = self.queue
        i = 0
        plans = self._room_plans
        memo = self._profiles  # (segment_profile is a function of its arguments)
        while c < wanted:
            if (v_in == 0.0 and self._n_avg > 1) or i + 1 >= len(q):
                break
            seg = q[i + 1]
            if not seg.length > 0.0:
                break
            c_e = c + 1  # the cycle the next segment starts in
            r = (t_0 + (n_0 + c_e - base) * dt) - dur
            v_end = seg.v_end if v_ends is None else v_ends.get(seg, seg.v_end)
            key = (seg.length, v_in, v_end, seg.v_cap, seg.a, seg.d)
            found = memo.get(key)
            if found is None:
                if len(memo) > 64:
                    memo.clear()
                memo[key] = found = segment_profile(0.0, *key)
            pieces, dur_2, v_1 = found
            if not r < dur_2:
                break
            plans.append((seg, pieces))
            t_0, n_0, dur, base, v_in = r, 0, dur_2, c_e, v_1
            c = c_e + _plan_last(t_0, 0, dur, dt)
            i += 1
        return min(wanted, c)

    def _raws_across(self, k: int, c_lo: int) -> list[list[float]]:
        """Run the path k cycles on (`coast_room`: inside the running segment, or across
        the ends `_room_across` allows, each such cycle stepped by `_path_step`); returns
        the raw poses of cycles c_lo .. k, one list per coordinate."""
        dt = self.dt
        cols: list[list[float]] = [[] for _ in self.raw]
        base = 0  # the cycle of the plan's count `_n`
        c = 0  # the cycles run so far
        while True:
            seg = self.queue[0]
            geom, length = seg.geom, seg.length
            t_0, n_0 = self._t0, self._n
            end = min(k, base + _plan_last(t_0, n_0, self._dur, dt))
            catch = self._room_catch
            if c < catch <= end:  # the deferred pass runs in cycle `catch`
                end = catch - 1
            a = max(c + 1, c_lo)
            if a <= end:
                fs = [u / length for u in self._positions(a - base, end - base)]
                for col, new in zip(cols, geom.points(fs)):
                    col += new
            if end == k:
                self._n = n = n_0 + k - base
                self.u, self.v, self.acc = self._eval(t_0 + n * dt)
                self.raw = geom.point(self.u / length)
                return cols
            self._n = n = n_0 + end - base  # the plan's count at cycle `end`
            if end + 1 == catch:
                self.u, self.v, self.acc = self._eval(t_0 + n * dt)
            self._path_step()  # cycle end + 1: the pass, or the next segment starts
            c = base = end + 1
            if c >= c_lo:
                for col, x in zip(cols, self.raw):
                    col.append(x)
            if c == k:
                return cols

    def _far(self, u: float) -> bool:
        """True if `_maybe_catch_up` at path position u leaves the deferred pass waiting."""
        stale, q = self._stale, self.queue
        return stale.s0 + stale.length - (q[0].s0 + u) > self._horizon() + self._v_hi * self.dt

    def coast_bounds(self) -> tuple[list[float], list[float], list[float]] | None:
        """(lowest, highest value of each coordinate, its highest speed [unit/s]) of the
        commanded poses of the cycles `coast_room` allows, or wider; None if unknown.
        The output averages the raw poses of the window and of the advance: within
        their range, and no faster than they move."""
        window = self._avg.window
        j = self._avg.j
        cols = list(zip(*window[j:], *window[:j]))  # each coordinate, oldest first
        lo = list(map(min, cols))
        hi = list(map(max, cols))
        inv = self._inv_dt
        speed = [max(map(abs, map(_sub, c[1:], c)), default=0.0) * inv for c in cols]
        if self.mode == RUN and not self._dwell:
            seg = self.queue[0]
            if not seg.length > 0.0:
                return None
            s_lo, s_hi, rates, v_top = self._segment_bounds(seg)
            scale = max(v_top, abs(self.v)) / seg.length
            for i, r in enumerate(rates):
                lo[i] = min(lo[i], s_lo[i])
                hi[i] = max(hi[i], s_hi[i])
                speed[i] = max(speed[i], r * scale)
            prev, s_prev = seg, [r * scale for r in rates]
            for nxt, pieces in self._room_plans:  # the segments the room runs into
                geom = nxt.geom
                s_lo, s_hi = geom.bounds()
                v_top = 0.0
                for _t0, _t1, _u0, v_0, a in pieces:
                    v_top = max(v_top, abs(v_0), abs(v_0 + a * (_t1 - _t0)))
                scale = v_top / nxt.length
                s_next = [r * scale for r in geom.rates()]
                for i, x in enumerate(s_next):
                    lo[i] = min(lo[i], s_lo[i])
                    hi[i] = max(hi[i], s_hi[i])
                    # the cycle across the corner: the rest of one, the gap, the start of the other
                    gap = 0.0 if nxt is prev else abs(geom.start[i] - prev.geom.end[i]) * inv
                    speed[i] = max(speed[i], x, max(x, s_prev[i]) + gap)
                prev, s_prev = nxt, s_next
        return lo, hi, speed

    def _segment_bounds(self, seg: Planned) -> tuple:
        """(lowest, highest value of each coordinate, the largest rate of each, the
        highest speed [unit/s] of the plan's pieces from the present one on) of the
        running segment `seg`; kept while the plan and its piece stay the same."""
        memo = self._bounds_memo
        pieces, pi = self._pieces, self._pi
        if memo is not None and memo[0] is seg and memo[1] is pieces and memo[2] == pi:
            return memo[3]
        v_top = 0.0
        for _t0, _t1, _u0, v_0, a in pieces[pi:]:
            v_top = max(v_top, abs(v_0), abs(v_0 + a * (_t1 - _t0)))
        s_lo, s_hi = seg.geom.bounds()
        found = (s_lo, s_hi, seg.geom.rates(), v_top)
        self._bounds_memo = (seg, pieces, pi, found)
        return found

    def advance(self, k: int, back: int) -> list[list[float]]:
        """Advance k cycles (k <= `coast_room(k)`, k > back >= 2) as k `step`s would;
        returns the commanded poses of cycles k - back .. k (the last is `out`)."""
        mode = self.mode
        if mode == RUN and not self._dwell:
            c_lo = max(1, self._avg.first_read(k, back))
            cols = self._raws_across(k, c_lo)
            outs = self._avg.advance(
                k, lambda c_0, c_1: [col[c_0 - c_lo : c_1 - c_lo + 1] for col in cols], False, back
            )
        else:
            if mode == RUN:  # resting on a corner: the raw pose is that of the path position
                self._dwell -= k
                seg = self.queue[0]
                length = seg.length
                self.raw = seg.geom.point(self.u / length) if length > 0.0 else list(seg.geom.end)
            raw = self.raw
            outs = self._avg.advance(k, lambda c_0, c_1: [[x] * (c_1 - c_0 + 1) for x in raw],
                                     mode == IDLE, back)  # fmt: skip
        inv = self._inv_dt
        p_2, p_1, out = outs[-3], outs[-2], outs[-1]
        v_1 = [(x - y) * inv for x, y in zip(p_1, p_2)]
        vel = [(x - y) * inv for x, y in zip(out, p_1)]
        self.out_acc = [(x - y) * inv for x, y in zip(vel, v_1)]
        self.out_vel = vel
        self.out = out
        return outs

    def _smooth(self) -> list[float]:
        prev = self.out
        out = self._avg.step(self.raw, self.mode == IDLE)  # (raw poses are never changed in place)
        if self.command_filter is not None:
            out = self.command_filter(out)
        inv = self._inv_dt
        vel = [(x - y) * inv for x, y in zip(out, prev)]
        self.out_acc = [(x - y) * inv for x, y in zip(vel, self.out_vel)]
        self.out_vel = vel
        self.out = out
        return out
