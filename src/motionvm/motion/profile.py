"""The manual's profile generator for one axis: a T-curve followed by a moving average.

HIMC manual 5.1: the profile generator (PG) plans a T-curve (trapezoid in velocity)
limited by the maximum velocity, acceleration and deceleration, and smooths it with a
moving average of length Ts (the smooth time), so that

    jerk = acceleration / Ts,     total acceleration time = Ta + Ts.

Discretely, the T-curve is sampled once per controller cycle `dt` and the output is the
mean of the last N = round(Ts/dt) samples (N <= 1: no smoothing). Consequences:

* velocity and acceleration of the output never exceed those of the T-curve; the jerk
  is at most max(a_max, d_max)/(N*dt), or (a_max + d_max)/(N*dt) where an acceleration
  phase and a deceleration phase lie closer than Ts (e.g. a triangular profile), and
  at most 2*max(a_max, d_max)/(N*dt) across on-the-fly reversals (the moving average of a
  T-curve whose acceleration jumps from -d to +d within Ts);
* a move ends exactly on its target, at cycle ceil(T/dt) + N - 1 after the command,
  where T is the closed-form T-curve time (`rest_to_rest_time`): total move time T + Ts
  within one cycle.

On-the-fly changes (new target, new limits, velocity scale, jog velocity) replan the
T-curve from its current state; the filter keeps running, so the output stays smooth.
Units: positions [mm], velocities [mm/s], accelerations [mm/s^2], times [s].
"""

from __future__ import annotations

import math

from motionvm.motion.tcurve import INF, TCurve, plan_position, plan_velocity, segment_position

IDLE, POSITION, VELOCITY, STOP = "idle", "position", "velocity", "stop"

NEVER = 1 << 62
"""A sample no run reaches: the last sample of an open-ended T-curve (a jog)."""

_V_ZERO = 1e-9
"""Velocity [mm/s] below which a segment end counts as rest in `span`'s monotony check:
it moves the position by far less than the range margin of a limit check (1e-9 * x)."""


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not (value > 0.0 and math.isfinite(value)):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return value


class ProfileGenerator:
    """T-curve planner + moving-average smoothing, stepped once per controller cycle."""

    __slots__ = (
        "_base",
        "_buf",
        "_flush",
        "_from_rest",
        "_idle",
        "_inv_dt",
        "_j",
        "_n",
        "_n_avg",
        "_nseg",
        "_out_a",
        "_out_p",
        "_out_v",
        "_p_f",
        "_plan",
        "_seg_half_a",
        "_seg_i",
        "_seg_p_0",
        "_seg_t_0",
        "_seg_t_1",
        "_seg_v_0",
        "_segs",
        "_smoothing",
        "_sum",
        "_tc_done",
        "_v_cmd",
        "a_max",
        "d_max",
        "dt",
        "mode",
        "target",
        "v_max",
        "velocity_scale",
    )  # fmt: skip

    def __init__(
        self,
        dt: float = 0.001,
        v_max: float = 100.0,
        a_max: float = 1000.0,
        d_max: float = 1000.0,
        t_smooth: float = 0.0,
        position: float = 0.0,
    ):
        """`dt` cycle [s], limits [mm/s], [mm/s^2], `t_smooth` Ts [s], start `position` [mm]."""
        self.dt = _check_positive("dt", dt)
        self._inv_dt = 1.0 / self.dt
        self.v_max = _check_positive("v_max", v_max)
        self.a_max = _check_positive("a_max", a_max)
        self.d_max = _check_positive("d_max", d_max)
        self.velocity_scale = 1.0
        """Factor [-] on v_max and on the jog velocity (manual SetVelScale / 100)."""
        self.mode = IDLE
        """IDLE, POSITION (move_to), VELOCITY (move_velocity) or STOP."""
        self._n_avg = self._smooth_samples(t_smooth)
        self._smoothing = self._n_avg > 1
        self.reset(position)

    # ---- commands -------------------------------------------------------------------

    def reset(self, position: float) -> None:
        """Drop any motion and hold `position` [mm] (Disable, SetPos, follow feedback)."""
        p = float(position)
        self.mode = IDLE
        self.target = p
        """Final position [mm] of the current point-to-point move or stop."""
        self._v_cmd = 0.0
        self._set_plan(TCurve([], p))
        self._tc_done = True
        self._base = p
        self._buf = [0.0] * self._n_avg
        self._j = 0
        self._sum = 0.0
        self._flush = self._n_avg
        self._out_p, self._out_v, self._out_a = p, 0.0, 0.0  # (the output: `output`)
        self._idle = True
        self._from_rest = True

    def move_to(self, target: float) -> None:
        """Move to `target` [mm] and stop there (MoveAbs; replans a motion in progress)."""
        target = float(target)
        if not math.isfinite(target):
            raise ValueError(f"target must be finite, got {target!r}")
        self.mode = POSITION
        self.target = target
        self._replan()

    def move_velocity(self, v: float) -> None:
        """Jog at `v` [mm/s] (MoveVel): the sign is the direction; |v| is capped at v_max."""
        v = float(v)
        if not math.isfinite(v):
            raise ValueError(f"velocity must be finite, got {v!r}")
        self.mode = VELOCITY
        self._v_cmd = v
        self._replan()

    def stop(self, decel: float | None = None) -> None:
        """Decelerate to rest at `decel` [mm/s^2] (default d_max); clears the target."""
        decel = self.d_max if decel is None else _check_positive("decel", decel)
        p, v = self._tc_state()
        self.mode = STOP
        self._start(plan_velocity(p, v, 0.0, decel, decel))
        self.target = self._p_f

    def set_limits(
        self, v_max: float | None = None, a_max: float | None = None, d_max: float | None = None
    ) -> None:
        """Change limits; a move or jog in progress is replanned with them at once."""
        if v_max is not None:
            self.v_max = _check_positive("v_max", v_max)
        if a_max is not None:
            self.a_max = _check_positive("a_max", a_max)
        if d_max is not None:
            self.d_max = _check_positive("d_max", d_max)
        if self.mode in (POSITION, VELOCITY):
            self._replan()

    def set_velocity_scale(self, scale: float) -> None:
        """Scale [0..1] of v_max and of the jog velocity; 0 brings a move to a halt."""
        scale = float(scale)
        if not 0.0 <= scale <= 1.0:
            raise ValueError(f"velocity scale {scale!r} is outside 0..1")
        self.velocity_scale = scale
        if self.mode in (POSITION, VELOCITY):
            self._replan()

    def set_smooth_time(self, t_smooth: float) -> None:
        """Set Ts [s] (manual SetSMTime, 0..0.5 s); only while no motion is in progress.

        A move that has ended (`is_done`: the output rests on its target) counts as no
        motion, also in the cycle before the generator turns idle (its acceleration
        returns to 0 one cycle after its velocity)."""
        n_avg = self._smooth_samples(t_smooth)
        if not self.is_done and (not self._idle or self.mode != IDLE):
            raise RuntimeError("the smooth time cannot change while the axis moves or is halted")
        self._n_avg = n_avg
        self._smoothing = n_avg > 1
        self.reset(self._out_p)

    def _smooth_samples(self, t_smooth: float) -> int:
        """The moving average's samples N of smooth time `t_smooth` [s] (0..10 s)."""
        t_smooth = float(t_smooth)
        if not (0.0 <= t_smooth <= 10.0):
            raise ValueError(f"smooth time {t_smooth!r} s is outside 0..10 s")
        return max(1, round(t_smooth / self.dt))

    # ---- queries --------------------------------------------------------------------

    @property
    def t_smooth(self) -> float:
        """Effective smooth time N*dt [s] (0 if N <= 1, i.e. no smoothing)."""
        return self._n_avg * self.dt if self._n_avg > 1 else 0.0

    @property
    def is_done(self) -> bool:
        """True once the output is exactly on the final position: the move has ended.

        Never while jogging or halted by a zero velocity scale. The velocity of that
        cycle is still the backward difference of the last step, zero one cycle later.
        """
        return self._tc_done and self._out_p == self._p_f and not self._pending()

    @property
    def is_cruising(self) -> bool:
        """True while a jog holds its final velocity: the T-curve is in its open-ended
        cruise and every sample behind the last three outputs (the smoothing window, two
        cycles more for the velocity and acceleration differences) is on it, so the
        output moves on at that velocity until the next command."""
        first = self._n - self._n_avg - 1  # the oldest sample of the last three outputs
        return (self.mode == VELOCITY and not self._idle and self._seg_t_1 == INF
                and first >= 1 and first * self.dt >= self._seg_t_0)  # fmt: skip

    @property
    def is_halted(self) -> bool:
        """True while a move or jog rests at a zero velocity scale, waiting to go on."""
        return self._idle and self._pending()

    def _pending(self) -> bool:
        if self.mode == POSITION:
            return self._p_f != self.target
        return self.mode == VELOCITY and self._v_cmd != 0.0

    @property
    def output(self) -> tuple[float, float, float]:
        """The last (ref_pos [mm], ref_vel [mm/s], ref_acc [mm/s^2])."""
        return self._out_p, self._out_v, self._out_a

    def planned_move_time(self) -> float:
        """Closed-form time [s] from the last (re)plan to the end of motion: T + Ts.

        0 for a move that does not move; inf for a jog.
        """
        if self._idle:
            return 0.0
        return self._plan.duration + self.t_smooth

    # ---- internals ------------------------------------------------------------------

    def _tc_state(self) -> tuple[float, float]:
        """Position [mm] and velocity [mm/s] of the T-curve at the last sample."""
        if self._tc_done:
            return self._p_f, 0.0
        p, v, _ = self._plan.evaluate(self._n * self.dt)
        return p, v

    def _replan(self) -> None:
        p, v = self._tc_state()
        v_lim = self.v_max * self.velocity_scale
        if self.mode == VELOCITY:
            v_f = max(-v_lim, min(v_lim, self._v_cmd * self.velocity_scale))
            self._start(plan_velocity(p, v, v_f, self.a_max, self.d_max))
        elif v_lim > 0.0:
            self._start(plan_position(p, v, self.target, v_lim, self.a_max, self.d_max))
        else:  # halted by a zero velocity scale: stop, keep the target
            self._start(plan_velocity(p, v, 0.0, self.a_max, self.d_max))

    def _set_plan(self, plan: TCurve) -> None:
        self._plan = plan
        self._segs = plan.segs
        self._nseg = len(plan.segs)
        self._n = 0
        self._p_f = plan.p_f
        self._enter_segment(0)

    def _enter_segment(self, i: int) -> None:
        """Make segment i the current one: its fields are what `step` evaluates.

        `_seg_half_a` is 0.5 * a: `0.5 * a * x` is evaluated as `(0.5 * a) * x`, so the
        product taken once per segment gives the same bits as `TCurve.evaluate`."""
        self._seg_i = i
        if i < self._nseg:
            t_0, t_1, p_0, v_0, a = self._segs[i]
            self._seg_t_0, self._seg_t_1, self._seg_p_0, self._seg_v_0 = t_0, t_1, p_0, v_0
            self._seg_half_a = 0.5 * a
        else:  # past the last segment: the plan holds p_f
            self._seg_t_1 = INF
            self._tc_done = True

    def _segment_at(self, tau: float) -> bool:
        """Advance the current segment to the one holding time tau [s]; True if tau is
        past the last one (the T-curve is done)."""
        i = self._seg_i
        segs = self._segs
        while i < self._nseg and tau >= segs[i][1]:
            i += 1
        self._enter_segment(i)
        return self._tc_done

    def _start(self, plan: TCurve) -> None:
        # from rest the samples before the plan are its start (the filter's window, the
        # closed-form advance, `advance`); on the fly they are the old plan's
        self._from_rest = self._idle
        if self._idle:
            if not plan.segs:
                self._set_plan(plan)
                self.mode = IDLE
                return
            # From rest the filter window holds one value; store samples relative to it.
            self._base = self._out_p
            self._buf = [0.0] * self._n_avg
            self._sum = 0.0
            self._j = 0
        self._set_plan(plan)
        self._tc_done = not plan.segs
        self._flush = 0
        self._idle = False

    def step(self) -> tuple[float, float, float]:
        """Advance one cycle; return (ref_pos [mm], ref_vel [mm/s], ref_acc [mm/s^2])."""
        if self._tc_done:  # idle implies done: one test while the T-curve runs
            if self._idle:
                return self._out_p, self._out_v, self._out_a
            self._n += 1
            p = self._p_f
        else:
            n = self._n + 1
            self._n = n
            tau = n * self.dt
            if tau >= self._seg_t_1 and self._segment_at(tau):
                p = self._p_f
            else:
                x = tau - self._seg_t_0
                p = self._seg_p_0 + (self._seg_v_0 + self._seg_half_a * x) * x
        if self._smoothing:  # _n_avg > 1
            n_avg = self._n_avg
            r = p - self._base
            buf = self._buf
            j = self._j
            s = self._sum + r - buf[j]
            buf[j] = r
            j += 1
            if j == n_avg:
                j = 0
                s = math.fsum(buf)  # bounds the drift of the running sum
            self._j = j
            self._sum = s
            if self._tc_done:
                self._flush += 1
                if self._flush < n_avg:
                    p = self._base + s / n_avg
            else:
                p = self._base + s / n_avg
        inv_dt = self._inv_dt
        v = (p - self._out_p) * inv_dt
        a = (v - self._out_v) * inv_dt
        self._out_p, self._out_v, self._out_a = p, v, a
        if v == 0.0 and a == 0.0 and self._tc_done and p == self._p_f:
            self._idle = True
            if not self._pending():
                self.mode = IDLE
        return p, v, a

    # ---- closed-form advance (time skipping) ----------------------------------------
    # The cycles nobody observes are computed for their last samples only, by the same
    # float operations `step` makes (motion/axis_coast.py orchestrates the axis).

    def sample(self, n: int) -> float:
        """The T-curve's position [mm] at sample n, as `step` computes it (n lies at or
        after the current sample and before the end of the T-curve)."""
        tau = n * self.dt
        segs = self._segs
        i = self._seg_i
        while tau >= segs[i][1]:
            i += 1
        t_0, _, p_0, v_0, a = segs[i]
        return segment_position(p_0, v_0, a, tau - t_0)

    def last_sample(self) -> int:
        """The last sample n that lies before the end of the T-curve (n * dt < duration);
        NEVER for a jog's open-ended T-curve."""
        duration = self._plan.duration
        if duration == math.inf:
            return NEVER
        dt = self.dt
        n = math.ceil(duration / dt) - 1
        while (n + 1) * dt < duration:
            n += 1
        while n * dt >= duration:
            n -= 1
        return n

    def holds_target(self) -> bool:
        """True if every output from the next sample on is the final position: the
        T-curve is done, the moving average (if any) flushed, no move waits."""
        return (self._tc_done and (self._n_avg == 1 or self._flush >= self._n_avg - 1)
                and not self._pending())  # fmt: skip

    def knows_its_past(self, delay: int) -> bool:
        """True if the samples the next outputs average and the `delay` samples before
        them (a motor's delay) lie in this plan, or before it where a plan started from
        rest holds its start: what `advance` and `outputs` need."""
        if self._nseg == 0:
            return False
        back = delay + (self._n_avg + 1 if self._n_avg > 1 else 0)
        return self._n >= back or self._from_rest

    def segment_of(self, n: int) -> int:
        """The T-curve segment that holds sample n (from the current segment on, as
        `_segment_at` finds it)."""
        tau = n * self.dt
        segs = self._segs
        i = self._seg_i
        while tau >= segs[i][1]:
            i += 1
        return i

    def pass_end(self, n_last: int) -> None:
        """Past the end of the T-curve, as stepping leaves it: the segment of its last
        sample n_last entered (its fields stay), then past the last one (done)."""
        i = self.segment_of(n_last)
        if i != self._seg_i:
            self._enter_segment(i)
        self._enter_segment(self._nseg)

    @property
    def bounds(self) -> tuple[float, float, float] | None:
        """(lowest, highest position [mm], highest |velocity| [mm/s]) of the whole plan
        if it moves one way only (what holds for all of it holds for any span), else None."""
        return self._plan.bounds

    def span(self, t_a: float, t_b: float) -> tuple[float, float, float] | None:
        """(lowest, highest position [mm], highest |velocity| [mm/s]) of the T-curve on
        the times [t_a, t_b] [s], or None if it is not monotonic there."""
        # the positions at t_a and t_b (as `TCurve.evaluate`; p_f past the last segment),
        # the highest |velocity| v_top on [t_a, t_b], and that it keeps its sign there
        v_top = 0.0
        sign = 0.0
        p_a = None
        p_b = self._p_f
        for t_0, t_1, p_0, v_0, acc in self._segs:
            if t_1 <= t_a:
                continue
            if p_a is None:  # the segment that holds t_a (or the first: t_a before the plan)
                p_a = segment_position(p_0, v_0, acc, t_a - t_0 if t_a > t_0 else 0.0)
            v_1 = v_0 + acc * (t_1 - t_0) if t_1 != math.inf else v_0
            # (a segment's end below _V_ZERO counts as rest: a braking segment may end a
            # rounding below zero)
            size = v_0 if v_0 >= 0.0 else -v_0
            if size > _V_ZERO:
                if sign and (v_0 > 0.0) != (sign > 0.0):
                    return None  # not monotonic
                sign = v_0
            if size > v_top:
                v_top = size
            size = v_1 if v_1 >= 0.0 else -v_1
            if size > _V_ZERO:
                if sign and (v_1 > 0.0) != (sign > 0.0):
                    return None
                sign = v_1
            if size > v_top:
                v_top = size
            if t_b < t_1:  # the segment that holds t_b: the last on [t_a, t_b]
                p_b = segment_position(p_0, v_0, acc, t_b - t_0 if t_b > t_0 else 0.0)
                break
        if p_a is None:  # t_a past the last segment
            p_a = self._p_f
        return (p_a, p_b, v_top) if p_a <= p_b else (p_b, p_a, v_top)

    def outputs(self, n_lo: int, n_e: int) -> tuple[list, int, tuple | None]:
        """(outputs [mm] of samples n_lo .. n_e, as `step` computes them; the T-curve
        segment of sample n_e; with smoothing, the filter's (buffer, index, sum) after
        sample n_e, else None). The current sample is n_lo or before it; without
        smoothing, n_e may be the first sample after the T-curve's end (p_f).

        The moving average is replayed from the last sample at or before n_lo where the
        generator recomputed its running sum exactly (`math.fsum`, every N samples): from
        there on the running sum takes exactly the additions stepping takes."""
        segs, dt = self._segs, self.dt
        seg = self._seg_i
        n_0 = self._n
        n_segs = len(segs)
        p_f = self._p_f
        ps = []
        n_avg = self._n_avg
        if n_avg == 1:
            for n in range(n_lo, n_e + 1):
                if n == n_0:
                    ps.append(self._out_p)
                    continue
                while seg < n_segs and n * dt >= segs[seg][1]:
                    seg += 1
                if seg == n_segs:  # past the end (no smoothing): the plan holds p_f
                    ps.append(p_f)
                else:
                    t_s, _, p_0, v_0, acc = segs[seg]
                    ps.append(segment_position(p_0, v_0, acc, n * dt - t_s))
            return ps, seg, None
        base = self._base
        buf = list(self._buf)
        start = n_lo - (self._j + n_lo - n_0) % n_avg  # after it the ring index is 0: a fsum
        if start > n_0:
            for i in range(n_avg):  # the ring after `start`: buf[i] is sample start-N+1+i
                n = start - n_avg + 1 + i
                if n > n_0:
                    while seg < n_segs and n * dt >= segs[seg][1]:
                        seg += 1
                    if seg == n_segs:
                        buf[i] = p_f - base
                    else:
                        t_s, _, p_0, v_0, acc = segs[seg]
                        buf[i] = segment_position(p_0, v_0, acc, n * dt - t_s) - base
            s, j = math.fsum(buf), 0
        else:
            start, s, j = n_0, self._sum, self._j
        if start == n_lo:
            ps.append(self._out_p if start == n_0 else base + s / n_avg)
        for n in range(start + 1, n_e + 1):
            while seg < n_segs and n * dt >= segs[seg][1]:
                seg += 1
            if seg == n_segs:
                r = p_f - base
            else:
                t_s, _, p_0, v_0, acc = segs[seg]
                r = segment_position(p_0, v_0, acc, n * dt - t_s) - base
            s = s + r - buf[j]
            buf[j] = r
            j += 1
            if j == n_avg:
                j = 0
                s = math.fsum(buf)
            if n >= n_lo:
                ps.append(base + s / n_avg)
        return ps, seg, (buf, j, s)

    def flush_room(self, n_from: int, most: int) -> int:
        """How many samples (at most `most`) after sample n_from (at or after the current
        one, the last T-curve sample or later) the smoothed generator can output while
        its moving average flushes: its flush count stays below N, and no output stands
        exactly on the target (from there region I may end: `AxisCycle.step`)."""
        n_0 = self._n
        flushed = self._flush if self._tc_done else 0  # (counts the samples past the end)
        last = min(most, self._n_avg - 1 - flushed - (n_from - n_0 if self._tc_done else 0))
        if last <= 0:
            return 0
        p_f = self._p_f
        k = 0
        for p in self.outputs(n_from + 1, n_from + last)[0]:
            if p == p_f:
                break
            k += 1
        return k

    def advance(self, k: int, s: int, p_last: float | None = None) -> None:
        """Advance k samples without smoothing, as k `step`s would, whose output is the
        target from the s-th on (1: the next): samples of the T-curve, then the output on
        the target, down to rest (the generator turns idle where `step` would). `p_last`:
        the output [mm] before the s-th, if known."""
        if self._idle:  # it repeats its output
            return
        n_0 = self._n
        p_f = self._p_f
        inv_dt = self._inv_dt
        pending = self._pending()  # a move waits (nothing of the advance changes that)
        p_0, v_0 = self._out_p, self._out_v
        p = p_f if k >= s else self.sample(n_0 + k)
        p_1 = p_0 if k == 1 else p_f if k > s else self.sample(n_0 + k - 1)
        if k == 1:
            v_1 = v_0
        else:
            p_2 = p_0 if k == 2 else p_f if k > s + 1 else self.sample(n_0 + k - 2)
            v_1 = (p_1 - p_2) * inv_dt
        v = (p - p_1) * inv_dt
        acc = (v - v_1) * inv_dt
        idle = 0  # the sample at which the generator turns idle (0: not in this advance)
        if k >= s and v == 0.0 and acc == 0.0:  # at rest on the target: where it idles
            if p_last is None:  # the output before the s-th
                p_last = p_0 if s == 1 else self.sample(n_0 + s - 1)
            if (p_f - p_last) * inv_dt != 0.0:
                idle = s + 2
            else:
                if s == 1:
                    v_last = v_0
                else:
                    p_2 = p_0 if s == 2 else self.sample(n_0 + s - 2)
                    v_last = (p_last - p_2) * inv_dt
                idle = s if v_last == 0.0 else s + 1
        self._out_p, self._out_v, self._out_a = p, v, acc
        if k < s:
            self._n = n_0 + k
            i = self.segment_of(n_0 + k)
            if i != self._seg_i:
                self._enter_segment(i)
        else:
            if not self._tc_done:
                self.pass_end(n_0 + s - 1)
            if idle:
                self._idle = True
                if not pending:
                    self.mode = IDLE
                self._n = n_0 + idle
            else:
                self._n = n_0 + k

    def advance_smoothed(self, k: int, back: int) -> list:
        """Advance k samples with smoothing (on the T-curve or while the moving average
        flushes: `flush_room`), as k `step`s would; returns the outputs [mm] of the last
        back + 1 samples (the last is the output now)."""
        n_0 = self._n
        n_e = n_0 + k
        ps, i, smoothing = self.outputs(n_e - back, n_e)
        p_2, p_1, p = ps[-3], ps[-2], ps[-1]
        inv_dt = self._inv_dt
        v_1 = (p_1 - p_2) * inv_dt
        v = (p - p_1) * inv_dt
        self._n = n_e
        if self._tc_done:  # the moving average flushes
            self._flush += k
        elif i == self._nseg:  # past the T-curve's end
            n_last = self.last_sample()
            self.pass_end(n_last)
            self._flush = n_e - n_last
        elif i != self._seg_i:
            self._enter_segment(i)
        self._out_p, self._out_v, self._out_a = p, v, (v - v_1) * inv_dt
        if smoothing is not None:
            self._buf, self._j, self._sum = smoothing
        return ps
