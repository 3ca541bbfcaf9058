"""Closed-form advance of a moving axis over cycles nobody observes (time skipping).

While an axis runs a profile move on the common path, its cycle is a pure function of
the cycle number: the T-curve sample of the profile generator (with smoothing, the
moving average replayed from its last exact sum, `_outputs`), the rounded target
counts, the drive's demand (integer counts added to an integer demand: exact in
floating point), an ideal motor `delay_cycles` behind the demand, the encoder count,
the feedback. Nothing of the axis's status changes (moving, not in position, no limit,
no fault) until the T-curve reaches its end. Without smoothing the advance goes on past
it: the output then holds the target, the demand stands still, the motor reaches it
`delay_cycles` later; region I ends in the cycle whose output repeats the target
(`moving` falls), and the axis comes into position once its feedback has been inside
the radius for the debounce time (`in_pos` rises). The status of those cycles is
`AxisCycle._settle` itself, called with each cycle's feedback (`_end`); the cycles in
which only the debounce count grows are counted at once.

With smoothing the advance replays the moving average (`_outputs`) and goes on past
the end of the T-curve while the average flushes, up to the cycle before its output
stands on the target (`_flush_room`); from there the cycles are stepped.

`coast_cycles` tells how many cycles the axis can be advanced from now: to its first
status change (the cycle region I ends in) or, when nobody watches its `moving`, to the
cycle it comes into position, the first cycle a wait on `IsInPos` can see; `coast`
advances it, leaving every field exactly as `k` calls of `Axis.step` would: the same
float operations on the same operands, evaluated for the last cycles only (the sensors'
cached switch bands aside, which only spare the drive work).

An axis coasts only on the common path: enabled, profile generator (no PVT, no ramp,
no gear, gantry, group or homing provider, nothing buffered, no filter or compensation
on its command path), CSP on a `Cia402Drive` in Operation enabled with a settled
controlword, `IdealMechanics`, no touch probe armed, no following error window, a move
whose position range over the cycles stays clear of the software and hardware limits
and whose position error stays well inside max_pos_err. Any other axis answers 0
("step me"); a resting axis answers as many cycles as asked (its step does nothing
until a command wakes it).
"""

from __future__ import annotations

import math

from motionvm.drives.cia402 import _SW_CYCLIC, Cia402Drive
from motionvm.drives.mechanics import IdealMechanics
from motionvm.drives.objects import MODE_CSP, State
from motionvm.motion import axis_status as st
from motionvm.motion.profile import IDLE
from motionvm.motion.tcurve import segment_position

NEVER = 1 << 62
"""Coast horizon of an axis that rests: it never needs stepping by itself."""

MIN_COAST = 4
"""Fewest cycles worth a closed-form advance (the formulas look 3 cycles back)."""

MAX_COAST = 1 << 20
"""Most cycles one advance covers (a jog can coast on forever)."""

_EXACT = 2.0**50
"""Counts below this stay exact integers in float arithmetic, with room for sums."""

_INT32 = 2.0**31 - 2.0
"""Counts [counts] beyond which the int32 target or position could wrap."""

_V_ZERO = 1e-9
"""Velocity [mm/s] below which a segment end counts as rest in the monotony check: it
moves the position by far less than the range margin (1e-9 * position)."""

_OPERATION_ENABLED = State.OPERATION_ENABLED
_CW_ENABLE = 0x0F
_PG = 0  # axis_cycle.PG
_FS_HW_LIMITS = st.FS_HW_RIGHT | st.FS_HW_LEFT


def _common(a) -> bool:
    """True if axis `a` is on the common path that `coast` computes in closed form,
    whatever the phase of its move: enabled, not in position, fed by its profile
    generator alone, on a plain CSP drive with an ideal motor (see the module docstring)."""
    if not (a.enabled and a._reference_source == _PG and a._provider is None) or a.in_pos:
        return False
    if a._cmd_path is not None:  # a filter or compensation on the command
        return False
    if (a._enabling or a._fault_reset_cycles is not None or a._command_queue
            or a._deferred_move is not None or a.op_mode != MODE_CSP
            or a.fault_status & _FS_HW_LIMITS):  # fmt: skip
        return False
    d = a.drive
    if type(d) is not Cia402Drive or type(d.mechanics) is not IdealMechanics:
        return False
    if (d.state is not _OPERATION_ENABLED or d.mode != MODE_CSP or d._mode_prev != MODE_CSP
            or d.controlword != _CW_ENABLE or d._controlword_prev != _CW_ENABLE
            or d._settled is not d.state or d._fault is not None or d.local_demand is not None
            or d._encoder_lost or d._forced
            or d._fe_checked):  # fmt: skip
        return False
    s = d.sensors
    if s._tp_function or s.tp_status:
        return False
    pg = a.pg
    m = d.mechanics
    # the samples the next outputs average (and the motor's delay) lie in this plan, or
    # before it, where a plan started from rest holds its start
    if pg._nseg == 0 or (
        pg._n < m.delay_cycles + (pg._n_avg + 1 if pg._n_avg > 1 else 0) and not pg._from_rest
    ):
        return False
    demand = d._demand
    # (x % 1.0 == 0.0: x is a whole number, without a call of int())
    if not (-_EXACT < demand < _EXACT and demand % 1.0 == 0.0 and m._demand == demand):
        return False
    if m.delay_cycles > 1:  # (with one cycle of delay the line is not used)
        for x in m._line:  # (a loop, not all(): no closure in the compiled build)
            if not (x % 1.0 == 0.0 and abs(x) < _EXACT):
                return False
    return m.position % 1.0 == 0.0


def _holds_target(pg) -> bool:
    """True if every output of generator `pg` from its next sample on is its final
    position: the T-curve is done, the moving average (if any) flushed, no move waits."""
    return (pg._tc_done and (pg._n_avg == 1 or pg._flush >= pg._n_avg - 1)
            and not pg._pending())  # fmt: skip


def _sample(pg, n: int) -> float:
    """The generator's position [mm] at its sample n, as `ProfileGenerator.step` computes
    it (n lies before the end of the T-curve)."""
    tau = n * pg.dt
    segs = pg._segs
    i = pg._seg_i
    while tau >= segs[i][1]:
        i += 1
    t_0, _, p_0, v_0, a = segs[i]
    return segment_position(p_0, v_0, a, tau - t_0)


def _last_sample(pg) -> int:
    """The last sample n that lies before the end of the T-curve (n * dt < duration)."""
    duration = pg._plan.duration
    if duration == math.inf:
        return NEVER
    dt = pg.dt
    n = math.ceil(duration / dt) - 1
    while (n + 1) * dt < duration:
        n += 1
    while n * dt >= duration:
        n -= 1
    return n


def coast_cycles(a, wanted: int, past_moving: bool = False, memo: dict | None = None) -> int:
    """How many cycles (at most `wanted`) axis `a` can be advanced from now without an
    observer missing a change: 0 if it must be stepped, `wanted` if it rests.

    The advance ends with the first status change: the cycle in which region I ends
    (`moving` falls), or with `past_moving` (nobody watches this axis's `moving`) the
    cycle in which the axis comes into position (`in_pos` rises). `memo` (a dict) keeps
    what `coast` can reuse of the work."""
    if a.resting:
        return wanted
    pg = a.pg
    if not pg._tc_done:
        if not (a.moving and not pg._idle and _common(a)):  # on the T-curve of a move
            return 0
        n_0 = pg._n
        n_last = _last_sample(pg)
        to_end = n_last - n_0
        if not (to_end < wanted and pg._n_avg == 1 and n_last != NEVER and not pg._pending()
                and _safe(a, n_0, n_last + 2)):  # fmt: skip
            k = to_end  # an advance along the T-curve (smoothed: into its flush)
            if pg._n_avg != 1 and n_last != NEVER and not pg._pending() and to_end < wanted:
                k += _flush_room(pg, n_0, n_last, wanted - to_end)
            return _longest_safe(a, n_0, min(wanted, k, MAX_COAST))
        s = to_end + 1  # the output is the target from cycle s on
    else:  # the T-curve is done: the output comes to rest on the target, the axis settles
        if pg._n_avg != 1:
            return _flush_cycles(a, wanted)
        if not (_holds_target(pg) and _common(a) and _safe(a, pg._n, pg._n + 2)):
            return 0
        s = 1
    # the output is the generator's target from cycle s on: the horizon ends where
    # region I ends or (past_moving) where the axis comes into position
    end = _end(a, s)
    if memo is not None:
        memo[a] = end
    _, _, e, feedback, _ = end
    if not past_moving and a.moving:
        return min(wanted, e)
    # the debounce count of cycles e .. e + len(feedback) - 1, then on alike
    p_f, radius, debounce = pg._p_f, a.inpos_radius, a._in_pos_debounce_cycles
    count = 0 if a.moving else a._in_pos_cycles
    for i, fb in enumerate(feedback, e):
        err = p_f - fb
        if -radius <= err <= radius:
            count += 1
            if count > debounce:
                return min(wanted, i)
        else:
            count = 0
    if not count:  # never in position: nothing changes any more
        return min(wanted, MAX_COAST)
    return min(wanted, e + len(feedback) + debounce - count)


def _flush_cycles(a, wanted: int) -> int:
    """How many cycles (at most `wanted`) the smoothed output of axis `a`, whose T-curve
    is done, can be advanced while its moving average flushes (`_advance_smoothed`):
    `_flush_room`. 0 if fewer than the formulas need."""
    pg = a.pg
    if pg._idle or not a.moving or pg._pending() or not _common(a):
        return 0
    n_0 = pg._n
    return _longest_safe(a, n_0, _flush_room(pg, n_0, n_0, wanted))


def _longest_safe(a, n_0: int, k: int) -> int:
    """k, or k halved until samples n_0+1 .. n_0+k of axis `a` are `_safe`; 0 below the
    shortest advance the formulas allow."""
    shortest = max(MIN_COAST, a.drive.mechanics.delay_cycles + 3)
    while k >= shortest:
        if _safe(a, n_0, n_0 + k):
            return k
        k //= 2
    return 0


def _flush_room(pg, n_0: int, n_from: int, most: int) -> int:
    """How many samples (at most `most`) after sample n_from (at or after n_0, the last
    T-curve sample or later) the smoothed generator `pg` can output while its moving
    average flushes: its flush count stays below N, and no output stands exactly on the
    target (from there region I may end: `AxisCycle.step`)."""
    flushed = pg._flush if pg._tc_done else 0  # (the flush counts the samples past the end)
    last = min(most, pg._n_avg - 1 - flushed - (n_from - n_0 if pg._tc_done else 0))
    if last <= 0:
        return 0
    p_f = pg._p_f
    k = 0
    for p in _outputs(pg, n_0, n_from + 1, n_from + last)[0]:
        if p == p_f:
            break
        k += 1
    return k


def _end(a, s: int) -> tuple[int, int, int, list[float], float]:
    """(a._cycle, s, e, feedback, p) of an axis whose output is its generator's target
    from cycle `s` on (counted from now, 1 the next cycle): e is the first cycle whose
    status tests the in-position radius (region I ends in it, or 1 if it has ended),
    `feedback` the position feedback [mm] of cycles e .. max(e, s + delay) as `step`
    leaves it (from the last on it stays the same: the motor stands on the last
    demand), p the output [mm] of cycle s - 1."""
    pg, d = a.pg, a.drive
    delay = d.mechanics.delay_cycles
    p = pg._out[0] if s == 1 else _sample(pg, pg._n + s - 1)
    if a.moving:  # region I ends when the output repeats the target: velocity 0
        e = s if (pg._p_f - p) * pg._inv_dt == 0.0 else s + 1
    else:
        e = 1
    demands = _demands(a, s, e - delay, max(e, s + delay) - delay)
    # the motor follows the demand `delay` cycles later
    return a._cycle, s, e, [_feedback(a, x) for x in demands], p


def _feedback(a, x: float) -> float:
    """The position feedback [mm] of axis `a` once its motor stands at x [counts]: the
    encoder count's change added to the axis's unwrapped counts, as `Axis.step` does."""
    enc = x.__round__()
    pa = a._position_actual
    return a.pos_fb if enc == pa else (a._feedback_counts + (enc - pa)) / a.cpu - a._slave_offset


def feedback_after(a, i: int) -> float:
    """The position feedback [mm] of axis `a` after `i` more cycles (i >= 1) of an advance
    (`coast_cycles(a, k, ...)` >= i, no smoothing): the motor stands on the drive's
    demand of cycle i - delay_cycles, and the feedback follows its encoder count, as
    `_end` computes it."""
    pg = a.pg
    s = 1 if pg._tc_done else _last_sample(pg) - pg._n + 1  # the first output on p_f
    j = i - a.drive.mechanics.delay_cycles
    return _feedback(a, _demands(a, s, j, j)[0])


def _demands(a, s: int, i_lo: int, i_hi: int, p_last: float | None = None) -> list[float]:
    """The drive's demands [counts] of cycles i_lo .. i_hi (counted from now: 0 is this
    cycle, back to -delay_cycles) of an axis on the common path whose output is its
    generator's target from cycle `s` on: what the motor holds for the cycles up to now,
    then the demand of each output's rounded target counts. `p_last`: the output of
    cycle s - 1, if known."""
    d = a.drive
    if i_lo >= s:  # all of them the target's
        pg = a.pg
        target = ((pg._p_f + a._slave_offset) * a.cpu).__round__()
        return [d._demand + (target - d._target_prev)] * (i_hi - i_lo + 1)
    m = d.mechanics
    delay = m.delay_cycles
    out = []
    if i_lo <= 0:
        if delay == 0:
            known = [m.position]
        elif delay == 1:
            known = [m.position, m._demand]
        else:
            known = [m.position, *m._line]
        out = known[i_lo + delay : i_hi + delay + 1]
        i_lo = 1
    if i_lo <= i_hi:
        pg = a.pg
        cpu, off = a.cpu, a._slave_offset
        t_0, demand_0 = d._target_prev, d._demand
        n_0 = pg._n
        for i in range(i_lo, min(i_hi, s - 1) + 1):
            p = p_last if i == s - 1 and p_last is not None else _sample(pg, n_0 + i)
            out.append(demand_0 + (((p + off) * cpu).__round__() - t_0))
        if i_hi >= s:  # the target's demand from cycle s on
            d_f = demand_0 + (((pg._p_f + off) * cpu).__round__() - t_0)
            out += [d_f] * (i_hi - max(i_lo, s) + 1)
    return out


def _safe(a, n_0: int, n_e: int) -> bool:
    """True if samples n_0+1 .. n_e trip no limit and no position error: the T-curve
    on the times [t_a, t_b] these samples and the motor's delay (and the moving
    average's window) span is monotonic, and its positions and highest velocity keep
    clear of the limits. A plan that moves one way only is tried whole first (its
    `bounds`: what holds for all of it holds for the span)."""
    pg = a.pg
    bounds = pg._plan.bounds
    if bounds is not None and _clear(a, *bounds):
        return True
    dt = pg.dt
    delay = a.drive.mechanics.delay_cycles
    window = pg._n_avg if pg._n_avg > 1 else 0  # the moving average looks back N samples
    t_a, t_b = (n_0 - delay - window) * dt, n_e * dt  # (0 < t_b: the plan starts at 0)
    # the positions at t_a and t_b (as `TCurve.evaluate`; p_f past the last segment),
    # the highest |velocity| v_top on [t_a, t_b], and that it keeps its sign there
    v_top = 0.0
    sign = 0.0
    p_a = None
    p_b = pg._p_f
    for t_0, t_1, p_0, v_0, acc in pg._segs:
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
                return False  # not monotonic
            sign = v_0
        if size > v_top:
            v_top = size
        size = v_1 if v_1 >= 0.0 else -v_1
        if size > _V_ZERO:
            if sign and (v_1 > 0.0) != (sign > 0.0):
                return False
            sign = v_1
        if size > v_top:
            v_top = size
        if t_b < t_1:  # the segment that holds t_b: the last on [t_a, t_b]
            p_b = segment_position(p_0, v_0, acc, t_b - t_0 if t_b > t_0 else 0.0)
            break
    if p_a is None:  # t_a past the last segment
        p_a = pg._p_f
    return _clear(a, p_a, p_b, v_top) if p_a <= p_b else _clear(a, p_b, p_a, v_top)


def _clear(a, lo: float, hi: float, v_top: float) -> bool:
    """True if the reference of axis `a` moving monotonically between lo and hi [mm] at
    speeds up to v_top [mm/s] trips no limit and no position error (`_safe`)."""
    size = hi if hi >= -lo else -lo
    margin = (1e-9 * size if size > 1.0 else 1e-9) + 1e-12
    lo, hi = lo - margin, hi + margin
    if not (a._sw_stop_left < lo and hi < a._sw_stop_right):
        return False
    d = a.drive
    m = d.mechanics
    cpu, off = a.cpu, a._pos_offset
    shift = d._demand - d._target_prev  # motor counts minus target counts
    x_lo, x_hi = (lo + off) * cpu + shift - 2.0, (hi + off) * cpu + shift + 2.0
    if not (-_INT32 < x_lo and x_hi < _INT32):
        return False  # the int32 target and position would wrap
    s = d.sensors
    x = m.position
    if s._negative_limit is not None and not s._negative_limit < (x_lo if x_lo < x else x):
        return False
    if s._positive_limit is not None and not (x_hi if x_hi > x else x) < s._positive_limit:
        return False
    if not a.ignore_pe:
        # err = p(n) - p(n - delay) - c / cpu up to the rounding of the counts
        c = shift + a._feedback_counts - a._position_actual
        err = v_top * m.delay_cycles * a.dt + ((c if c >= 0 else -c) + 2.0) / cpu
        if err * 1.01 + 1e-9 >= a._max_pos_err:
            return False
    return True


def coast(a, k: int, memo: dict | None = None) -> None:
    """Advance axis `a` by `k` cycles (k <= `coast_cycles(a, k, ...)`), exactly as k steps;
    `memo`: the one `coast_cycles` filled."""
    if a.resting:
        return
    if a.pg._n_avg == 1:
        _advance(a, k, memo.get(a) if memo else None)
    elif k >= max(MIN_COAST, a.drive.mechanics.delay_cycles + 3):
        _advance_smoothed(a, k)
    else:  # too short for the moving average's formulas
        for _ in range(k):
            a.step()


def _advance(a, k: int, end: tuple | None = None) -> None:
    """Advance axis `a` (no smoothing) by `k` cycles in closed form: samples of its
    T-curve, then cycles in which the output holds the target, region I ends and the
    axis settles (`AxisCycle._settle` of each cycle whose feedback differs, the cycles in
    between counted at once). `end`: `_end` of the axis as it is, if known (as
    `coast_cycles` makes it: only where no move waits)."""
    d = a.drive
    m = d.mechanics
    pg = a.pg
    n_0 = pg._n
    delay = m.delay_cycles
    p_f = pg._p_f
    inv_dt = pg._inv_dt
    if end is not None and end[0] == a._cycle:
        s = end[1]
        pending = False  # (`coast_cycles` made `end` only where no move waits)
    else:
        end = None
        s = 1 if pg._tc_done else _last_sample(pg) - n_0 + 1  # the first output on p_f
        pending = pg._pending()  # a move waits (nothing of the advance changes that)
    # the generator's output of cycle k (0 is now), as `ProfileGenerator.step`
    p_0, v_0, _ = out_0 = pg._out
    was_idle = pg._idle
    idle = 0  # the cycle in which the generator turns idle (0: not in this advance)
    if was_idle:  # it repeats its output
        p, v, acc = out_0
    else:
        p = p_f if k >= s else _sample(pg, n_0 + k)
        p_1 = p_0 if k == 1 else p_f if k > s else _sample(pg, n_0 + k - 1)
        if k == 1:
            v_1 = v_0
        else:
            p_2 = p_0 if k == 2 else p_f if k > s + 1 else _sample(pg, n_0 + k - 2)
            v_1 = (p_1 - p_2) * inv_dt
        v = (p - p_1) * inv_dt
        acc = (v - v_1) * inv_dt
        if k >= s and v == 0.0 and acc == 0.0:  # at rest on the target: the sample it
            if end is None:  # (the same for any advance of the axis as it is)
                end = _end(a, s)
            v_s = (p_f - end[4]) * inv_dt  # idles
            if v_s != 0.0:
                idle = s + 2
            else:
                if s == 1:
                    v_last = v_0
                else:
                    p_2 = p_0 if s == 2 else _sample(pg, n_0 + s - 2)
                    v_last = (end[4] - p_2) * inv_dt
                idle = s if v_last == 0.0 else s + 1
    # the drive's demands of cycles k - delay - 2 .. k (the motor's of k - 2 .. k)
    demands = _demands(a, s, max(k - delay - 2, -delay), k, None if end is None else end[4])
    # the status of the cycles from the first that tests the in-position radius
    moving = a.moving
    status = (not moving or k >= s) and not (moving and pending)
    if status:
        if end is None:
            end = _end(a, s)
        e = end[2]
        status = k >= e
    if status:
        _settle_cycles(a, k, e, end[3])
    # the generator after cycle k
    if not was_idle:
        pg._out = (p, v, acc)
        if k < s:
            pg._n = n_0 + k
            i = _segment(pg, n_0 + k)
            if i != pg._seg_i:
                pg._enter_segment(i)
        else:
            if not pg._tc_done:
                _pass_end(pg, n_0 + s - 1)
            if idle:
                pg._idle = True
                if not pending:
                    pg.mode = IDLE
                pg._n = n_0 + idle
            else:
                pg._n = n_0 + k
    # the reference, the drive's target and demand, the motor
    x_1 = demands[-2 - delay]
    v_m_1 = m.velocity if k == 1 else (x_1 - demands[-3 - delay]) / a.dt
    _land(a, k, (p, v, acc), demands, demands[-delay:] if delay > 1 else None,
          x_1, demands[-1 - delay], v_m_1)  # fmt: skip
    if status:  # the end of `step`: an axis in position watches for rest
        if a._idle_candidate():
            a._watch_rest()
        else:
            a._still_cycles = 0


def _settle_cycles(a, k: int, e: int, feedback: list[float]) -> None:
    """The status of axis `a` over cycles e .. k of an advance (`_end`): its reference
    on the target, `AxisCycle._settle` of each, with that cycle's feedback."""
    cycle = a._cycle
    fb_0 = a.pos_fb
    p_f = a.ref_pos = a.pg._p_f
    last = e + len(feedback) - 1
    for i in range(e, min(k, last) + 1):
        a.pos_fb = feedback[i - e]
        a._cycle = cycle + i
        a._settle()
    if k > last:  # the feedback and the test stay the same from cycle `last` on
        a.pos_fb = fb = feedback[-1]
        err = p_f - fb
        if -a.inpos_radius <= err <= a.inpos_radius:
            # the count grows; only where it passes the debounce time is more done
            same = k - last - 1
            if not a.in_pos:
                same = min(same, max(0, a._in_pos_debounce_cycles - a._in_pos_cycles))
            a._in_pos_cycles += same
            first = last + same + 1
        else:  # each cycle clears the count alike
            first = k
        for i in range(first, k + 1):
            a._cycle = cycle + i
            a._settle()
    a.pos_fb = fb_0
    a._cycle = cycle


def _segment(pg, n: int) -> int:
    """The T-curve segment of generator `pg` that holds its sample n (from the current
    segment on, as `ProfileGenerator._segment_at` finds it)."""
    tau = n * pg.dt
    segs = pg._segs
    i = pg._seg_i
    while tau >= segs[i][1]:
        i += 1
    return i


def _pass_end(pg, n_last: int) -> None:
    """Generator `pg` past the end of its T-curve, as stepping leaves it: the segment of
    its last sample n_last entered (its fields stay), then past the last one (done)."""
    i = _segment(pg, n_last)
    if i != pg._seg_i:
        pg._enter_segment(i)
    pg._enter_segment(pg._nseg)


def _outputs(pg, n_0: int, n_lo: int, n_e: int):
    """(outputs [mm] of samples n_lo .. n_e, as `ProfileGenerator.step` computes them;
    the T-curve segment of sample n_e; with smoothing, the filter's (buffer, index, sum)
    after sample n_e, else None). n_0 < n_lo or n_0 == n_lo; without smoothing, n_e may
    be the first sample after the T-curve's end (p_f).

    The moving average is replayed from the last sample at or before n_lo where the
    generator recomputed its running sum exactly (`math.fsum`, every N samples): from
    there on the running sum takes exactly the additions stepping takes."""
    segs, dt = pg._segs, pg.dt
    seg = pg._seg_i

    n_segs = len(segs)

    def tcurve(n: int) -> float:  # samples come in increasing n
        nonlocal seg
        if seg == n_segs:
            return pg._p_f
        tau = n * dt
        while tau >= segs[seg][1]:
            seg += 1
            if seg == n_segs:  # past the end (no smoothing): the plan holds p_f
                return pg._p_f
        t_s, _, p_0, v_0, acc = segs[seg]
        return segment_position(p_0, v_0, acc, tau - t_s)

    n_avg = pg._n_avg
    if n_avg == 1:
        ps = [pg._out[0] if n == n_0 else tcurve(n) for n in range(n_lo, n_e + 1)]
        return ps, seg, None
    base = pg._base
    buf = list(pg._buf)
    start = n_lo - (pg._j + n_lo - n_0) % n_avg  # after it the ring index is 0: a fsum
    if start > n_0:
        for i in range(n_avg):  # the ring after `start`: buf[i] is sample start-N+1+i
            n = start - n_avg + 1 + i
            if n > n_0:
                buf[i] = tcurve(n) - base
        s, j = math.fsum(buf), 0
    else:
        start, s, j = n_0, pg._sum, pg._j
    ps = [pg._out[0] if start == n_0 else base + s / n_avg] if start == n_lo else []
    for n in range(start + 1, n_e + 1):
        r = tcurve(n) - base
        s = s + r - buf[j]
        buf[j] = r
        j += 1
        if j == n_avg:
            j = 0
            s = math.fsum(buf)
        if n >= n_lo:
            ps.append(base + s / n_avg)
    return ps, seg, (buf, j, s)


def _advance_smoothed(a, k: int) -> None:
    """Advance axis `a` (with smoothing) by `k` samples of its T-curve in closed form."""
    d = a.drive
    m = d.mechanics
    pg = a.pg
    n_0 = pg._n
    n_e = n_0 + k
    cpu, off = a.cpu, a._slave_offset
    delay = m.delay_cycles
    t_0 = d._target_prev  # == target_position: no wrap on the common path
    demand_0 = d._demand
    # samples n_lo .. n_e of the generator and of the drive's demand (n_lo >= n_0)
    n_lo = n_e - delay - 2
    ps, i, smoothing = _outputs(pg, n_0, n_lo, n_e)
    demands = [
        demand_0 if n == n_0 else demand_0 + (((p + off) * cpu).__round__() - t_0)
        for n, p in zip(range(n_lo, n_e + 1), ps)
    ]
    inv_dt = pg._inv_dt
    p_2, p_1, p = ps[-3], ps[-2], ps[-1]
    v_1 = (p_1 - p_2) * inv_dt
    v = (p - p_1) * inv_dt
    acc = (v - v_1) * inv_dt
    # the profile generator after sample n_e
    pg._n = n_e
    if pg._tc_done:  # the moving average flushes (`_flush_room`)
        pg._flush += k
    elif i == pg._nseg:  # past the T-curve's end
        n_last = _last_sample(pg)
        _pass_end(pg, n_last)
        pg._flush = n_e - n_last
    elif i != pg._seg_i:
        pg._enter_segment(i)
    pg._out = (p, v, acc)
    if smoothing is not None:
        pg._buf, pg._j, pg._sum = smoothing
    # the axis's reference, the drive's target and demand, and the ideal motor,
    # delay_cycles behind the demand: x = demand of sample n_e - delay
    x_2, x_1 = demands[0], demands[1]
    _land(a, k, (p, v, acc), demands, demands[3:] if delay != 1 else None,
          x_1, demands[2], (x_1 - x_2) / a.dt)  # fmt: skip


def _land(a, k: int, ref: tuple, demands: list, line: list | None, x_1: float, x: float,
          v_1: float) -> None:  # fmt: skip
    """The end of an advance of axis `a` by `k` cycles: its reference `ref` (position,
    velocity, acceleration), the drive's target from it and its demand, the last of
    `demands` (after the one before it), the motor's delay line `line` (None: kept), and
    the motor's last cycle from x_1 to x (`_motor_to`)."""
    d = a.drive
    m = d.mechanics
    a._cycle += k
    a.ref_pos, a.ref_vel, a.ref_acc = ref
    target = ((ref[0] + a._slave_offset) * a.cpu).__round__()
    d.target_position = target
    d._target_prev = target
    demand = demands[-1]
    d._demand = demand
    m._demand_vel = (demand - demands[-2]) / a.dt
    m._demand = demand
    if line is not None:
        m._line.clear()
        m._line.extend(line)
    _motor_to(a, x_1, x, v_1)


def _motor_to(a, x_1: float, x: float, v_1: float) -> None:
    """The ideal motor of axis `a` moves from x_1 to x [counts] in this cycle (v_1: its
    velocity [counts/s] of the cycle before); the drive's and the axis's feedback.

    The motor's demand, its velocity and its delay line are set for after this cycle
    (the callers'); the motor's own `step_position` makes the cycle, from the state
    before it: at x_1 with velocity v_1, x the demand that leaves the delay line now."""
    d = a.drive
    m = d.mechanics
    demand, demand_vel = m._demand, m._demand_vel
    m.position, m.velocity = x_1, v_1
    if m.delay_cycles == 1:  # the demand of the cycle before
        m._demand = x
    elif m.delay_cycles > 1:  # x first out, the newest demand back in by the step
        line = m._line
        line.pop()
        line.appendleft(x)
    m.step_position(demand, a.dt)
    m._demand_vel = demand_vel
    # the drive's feedback, as a step in Operation enabled leaves it
    d._encoder = enc = x.__round__()
    d.position_actual = enc
    d.digital_inputs = di = d.sensors.update(x_1, x)
    d._motor_position_prev = x
    d.statusword_base = _SW_CYCLIC
    d._limit_lazy = True  # `statusword` adds the internal limit bit
    # the axis's feedback
    if enc != a._position_actual:
        a._feedback_counts = counts = a._feedback_counts + (enc - a._position_actual)
        a._position_actual = enc
        a.pos_fb_raw = raw = counts / a.cpu
        a.pos_fb = raw - a._slave_offset
    if di != a._digital_inputs:
        a._hw_inputs(di)
