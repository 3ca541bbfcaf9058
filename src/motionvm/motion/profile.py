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

from motionvm.motion.tcurve import INF, TCurve, plan_position, plan_velocity

IDLE, POSITION, VELOCITY, STOP = "idle", "position", "velocity", "stop"


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
        "_out",
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
        self._n_avg = 1
        self._smoothing = False
        self._out = None  # (set by `reset`; None: not yet, for `set_smooth_time`)
        self.set_smooth_time(t_smooth)
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
        self._out = (p, 0.0, 0.0)
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
        t_smooth = float(t_smooth)
        if not (0.0 <= t_smooth <= 10.0):
            raise ValueError(f"smooth time {t_smooth!r} s is outside 0..10 s")
        if self._out is not None and not self.is_done and (not self._idle or self.mode != IDLE):
            raise RuntimeError("the smooth time cannot change while the axis moves or is halted")
        self._n_avg = max(1, round(t_smooth / self.dt))
        self._smoothing = self._n_avg > 1
        if self._out is not None:
            self.reset(self._out[0])

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
        return self._tc_done and self._out[0] == self._p_f and not self._pending()

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
        return self._out

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
        # closed-form advance of motion/axis_coast.py); on the fly they are the old plan's
        self._from_rest = self._idle
        if self._idle:
            if not plan.segs:
                self._set_plan(plan)
                self.mode = IDLE
                return
            # From rest the filter window holds one value; store samples relative to it.
            self._base = self._out[0]
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
                return self._out
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
        p_prev, v_prev, _ = self._out
        inv_dt = self._inv_dt
        v = (p - p_prev) * inv_dt
        a = (v - v_prev) * inv_dt
        self._out = res = (p, v, a)
        if v == 0.0 and a == 0.0 and self._tc_done and p == self._p_f:
            self._idle = True
            if not self._pending():
                self.mode = IDLE
        return res
