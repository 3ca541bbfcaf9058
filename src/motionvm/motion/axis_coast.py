"""Closed-form advance of a moving axis over cycles nobody observes (time skipping):
the axis's part, and the order in which it advances the parts below it.

Each part advances itself next to its own `step`, with the same float operations:
the profile generator (`ProfileGenerator.sample`, `outputs`, `advance`,
`advance_smoothed`: motion/profile.py), the drive (`Cia402Drive.steady`, `clear_of`,
`land`: drives/cia402.py), its ideal motor (`IdealMechanics.holds_whole_counts`,
`held_demands`, `land`: drives/mechanics.py) and its sensors (`Sensors.update`,
`clear_of_limits`: drives/sensors.py). This module holds what ties them together:
how far the axis can go, the drive's demands from the generator's outputs, the
feedback and the status of the axis over the advance.

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

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.objects import MODE_CSP
from motionvm.motion import axis_status as st
from motionvm.motion.profile import NEVER

MIN_COAST = 4
"""Fewest cycles worth a closed-form advance (the formulas look 3 cycles back)."""

MAX_COAST = 1 << 20
"""Most cycles one advance covers (a jog can coast on forever)."""

_PG = 0  # axis_cycle.PG
_EXT = 4  # axis_cycle.EXT
_FS_HW_LIMITS = st.FS_HW_RIGHT | st.FS_HW_LEFT

__all__ = [
    "MAX_COAST",
    "MIN_COAST",
    "NEVER",
    "clear_following",
    "coast",
    "coast_cycles",
    "coast_following",
    "feedback_after",
    "following",
]


def _common(a) -> bool:
    """True if axis `a` is on the common path that `coast` computes in closed form,
    whatever the phase of its move: enabled, not in position, fed by its profile
    generator alone, on a steady CSP drive with an ideal motor (see the module docstring)."""
    if not (a.enabled and a._reference_source == _PG and a._provider is None) or a.in_pos:
        return False
    if a._cmd_path is not None:  # a filter or compensation on the command
        return False
    if (a._enabling or a._fault_reset_cycles is not None or a._command_queue
            or a._deferred_move is not None or a.op_mode != MODE_CSP
            or a.fault_status & _FS_HW_LIMITS):  # fmt: skip
        return False
    d = a.drive
    if type(d) is not Cia402Drive or not d.steady():
        return False
    return a.pg.knows_its_past(d.mechanics.delay_cycles)


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
        n_last = pg.last_sample()
        to_end = n_last - n_0
        if not (to_end < wanted and pg._n_avg == 1 and n_last != NEVER and not pg._pending()
                and _safe(a, n_0, n_last + 2)):  # fmt: skip
            k = to_end  # an advance along the T-curve (smoothed: into its flush)
            if pg._n_avg != 1 and n_last != NEVER and not pg._pending() and to_end < wanted:
                k += pg.flush_room(n_last, wanted - to_end)
            return _longest_safe(a, n_0, min(wanted, k, MAX_COAST))
        s = to_end + 1  # the output is the target from cycle s on
    else:  # the T-curve is done: the output comes to rest on the target, the axis settles
        if pg._n_avg != 1:
            return _flush_cycles(a, wanted)
        if not (pg.holds_target() and _common(a) and _safe(a, pg._n, pg._n + 2)):
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
    is done, can be advanced while its moving average flushes (`advance_smoothed`):
    `flush_room`. 0 if fewer than the formulas need."""
    pg = a.pg
    if pg._idle or not a.moving or pg._pending() or not _common(a):
        return 0
    n_0 = pg._n
    return _longest_safe(a, n_0, pg.flush_room(n_0, wanted))


def _longest_safe(a, n_0: int, k: int) -> int:
    """k, or k halved until samples n_0+1 .. n_0+k of axis `a` are `_safe`; 0 below the
    shortest advance the formulas allow."""
    shortest = max(MIN_COAST, a.drive.mechanics.delay_cycles + 3)
    while k >= shortest:
        if _safe(a, n_0, n_0 + k):
            return k
        k //= 2
    return 0


def _end(a, s: int) -> tuple[int, int, int, list[float], float]:
    """(a._cycle, s, e, feedback, p) of an axis whose output is its generator's target
    from cycle `s` on (counted from now, 1 the next cycle): e is the first cycle whose
    status tests the in-position radius (region I ends in it, or 1 if it has ended),
    `feedback` the position feedback [mm] of cycles e .. max(e, s + delay) as `step`
    leaves it (from the last on it stays the same: the motor stands on the last
    demand), p the output [mm] of cycle s - 1."""
    pg, d = a.pg, a.drive
    delay = d.mechanics.delay_cycles
    p = pg._out_p if s == 1 else pg.sample(pg._n + s - 1)
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
    s = 1 if pg._tc_done else pg.last_sample() - pg._n + 1  # the first output on p_f
    j = i - a.drive.mechanics.delay_cycles
    return _feedback(a, _demands(a, s, j, j)[0])


def _demands(a, s: int, i_lo: int, i_hi: int, p_last: float | None = None) -> list[float]:
    """The drive's demands [counts] of cycles i_lo .. i_hi (counted from now: 0 is this
    cycle, back to -delay_cycles) of an axis on the common path whose output is its
    generator's target from cycle `s` on: what the motor holds for the cycles up to now,
    then the demand of each output's rounded target counts. `p_last`: the output of
    cycle s - 1, if known."""
    d = a.drive
    pg = a.pg
    cpu, off = a.cpu, a._slave_offset
    if i_lo >= s:  # all of them the target's
        return [d.demand_for(((pg._p_f + off) * cpu).__round__())] * (i_hi - i_lo + 1)
    delay = d.mechanics.delay_cycles
    out = []
    if i_lo <= 0:
        out = d.mechanics.held_demands()[i_lo + delay : i_hi + delay + 1]
        i_lo = 1
    if i_lo <= i_hi:
        n_0 = pg._n
        for i in range(i_lo, min(i_hi, s - 1) + 1):
            p = p_last if i == s - 1 and p_last is not None else pg.sample(n_0 + i)
            out.append(d.demand_for(((p + off) * cpu).__round__()))
        if i_hi >= s:  # the target's demand from cycle s on
            d_f = d.demand_for(((pg._p_f + off) * cpu).__round__())
            out += [d_f] * (i_hi - max(i_lo, s) + 1)
    return out


def _safe(a, n_0: int, n_e: int) -> bool:
    """True if samples n_0+1 .. n_e trip no limit and no position error: the T-curve
    on the times [t_a, t_b] these samples and the motor's delay (and the moving
    average's window) span is monotonic, and its positions and highest velocity keep
    clear of the limits. A plan that moves one way only is tried whole first (its
    `bounds`: what holds for all of it holds for the span)."""
    pg = a.pg
    bounds = pg.bounds
    if bounds is not None and _clear(a, bounds[0], bounds[1], bounds[2]):
        return True
    dt = pg.dt
    delay = a.drive.mechanics.delay_cycles
    window = pg._n_avg if pg._n_avg > 1 else 0  # the moving average looks back N samples
    # (0 < t_b: the plan starts at 0)
    span = pg.span((n_0 - delay - window) * dt, n_e * dt)
    return span is not None and _clear(a, span[0], span[1], span[2])


def _clear(a, lo: float, hi: float, v_top: float) -> bool:
    """True if the reference of axis `a` moving monotonically between lo and hi [mm] at
    speeds up to v_top [mm/s] trips no limit and no position error (`_safe`)."""
    size = hi if hi >= -lo else -lo
    margin = (1e-9 * size if size > 1.0 else 1e-9) + 1e-12
    lo, hi = lo - margin, hi + margin
    if not (a._sw_stop_left < lo and hi < a._sw_stop_right):
        return False
    d = a.drive
    cpu, off = a.cpu, a._pos_offset
    if not d.clear_of((lo + off) * cpu, (hi + off) * cpu):
        return False  # an int32 object would wrap, or the motor reach a limit switch
    if not a.ignore_pe:
        # err = p(n) - p(n - delay) - c / cpu up to the rounding of the counts
        c = d.demand_shift() + a._feedback_counts - a._position_actual
        err = v_top * d.mechanics.delay_cycles * a.dt + ((c if c >= 0 else -c) + 2.0) / cpu
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
    pg = a.pg
    delay = a.drive.mechanics.delay_cycles
    if end is not None and end[0] == a._cycle:
        s = end[1]
        pending = False  # (`coast_cycles` made `end` only where no move waits)
    else:
        end = None
        s = 1 if pg._tc_done else pg.last_sample() - pg._n + 1  # the first output on p_f
        pending = pg._pending()  # a move waits (nothing of the advance changes that)
    # the drive's demands of cycles k - delay - 2 .. k (the motor's of k - 2 .. k), from
    # the generator as it is (its samples are read from its current segment on)
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
    pg.advance(k, s, None if end is None else end[4])
    x_1 = demands[-2 - delay]
    v_m_1 = a.drive.mechanics.velocity if k == 1 else (x_1 - demands[-3 - delay]) / a.dt
    _land(a, k, demands, demands[-delay:] if delay > 1 else None, x_1, demands[-1 - delay],
          v_m_1)  # fmt: skip
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


def _advance_smoothed(a, k: int) -> None:
    """Advance axis `a` (with smoothing) by `k` samples of its T-curve in closed form."""
    d = a.drive
    delay = d.mechanics.delay_cycles
    cpu, off = a.cpu, a._slave_offset
    # the generator's outputs of its last delay + 3 samples (all after the current one:
    # k >= delay + 3), and the drive's demands of them
    demands = [d.demand_for(((p + off) * cpu).__round__())
               for p in a.pg.advance_smoothed(k, delay + 2)]  # fmt: skip
    # the ideal motor, delay_cycles behind the demand: x = demand of sample n_e - delay
    x_2, x_1 = demands[0], demands[1]
    _land(a, k, demands, demands[3:] if delay != 1 else None, x_1, demands[2],
          (x_1 - x_2) / a.dt)  # fmt: skip


def following(a, link) -> bool:
    """True if axis `a` follows reference provider `link` (an axis group's) on the
    common path, in region I (`moving`: the provider keeps it there while it moves),
    so that its cycle is the reference's counts through a steady CSP drive and ideal
    motor, and nothing of its status changes (see `_common`)."""
    if not (a.enabled and a.moving and a._reference_source == _EXT and a._provider is link):
        return False
    if a._cmd_path is not None:
        return False
    if (a._enabling or a._fault_reset_cycles is not None or a._command_queue
            or a._deferred_move is not None or a.op_mode != MODE_CSP
            or a.fault_status & _FS_HW_LIMITS):  # fmt: skip
        return False
    d = a.drive
    return type(d) is Cia402Drive and d.steady()


def clear_following(a, lo: float, hi: float, v_top: float) -> bool:
    """True if the reference of axis `a` (`following`) between lo and hi [mm], at
    speeds up to v_top [mm/s], trips no limit and no position error (`_clear`)."""
    return _clear(a, lo, hi, v_top)


def coast_following(a, k: int, ps: list, ref: tuple) -> None:
    """Advance axis `a` (`following`) by k cycles (k >= delay_cycles + 3), as k steps
    would: `ps` are its references [mm] of cycles k - delay_cycles - 2 .. k, `ref` the
    reference (position, velocity, acceleration) of the last."""
    d = a.drive
    delay = d.mechanics.delay_cycles
    cpu, off = a.cpu, a._slave_offset
    demands = [d.demand_for(((p + off) * cpu).__round__()) for p in ps]
    x_2, x_1 = demands[0], demands[1]
    _land(a, k, demands, demands[3:] if delay != 1 else None, x_1, demands[2],
          (x_1 - x_2) / a.dt, ref)  # fmt: skip


def _land(a, k: int, demands: list, line: list | None, x_1: float, x: float,
          v_1: float, ref: tuple | None = None) -> None:  # fmt: skip
    """The end of an advance of axis `a` by `k` cycles: its reference `ref`, or the
    generator's output now; the drive's target from it and its demand, the last of `demands` (after
    the one before it); the motor's delay line `line` (None: kept) and its last cycle
    from x_1 to x [counts] (v_1: its velocity [counts/s] the cycle before); the axis's
    feedback, as `Axis.step` takes it."""
    d = a.drive
    a._cycle += k
    if ref is None:
        ref = a.pg.output
    a.ref_pos, a.ref_vel, a.ref_acc = ref
    demand = demands[-1]
    d.land(((ref[0] + a._slave_offset) * a.cpu).__round__(), demand,
           (demand - demands[-2]) / a.dt, line, x_1, x, v_1, a.dt)  # fmt: skip
    enc = d.position_actual
    if enc != a._position_actual:
        a._feedback_counts = counts = a._feedback_counts + (enc - a._position_actual)
        a._position_actual = enc
        a.pos_fb_raw = raw = counts / a.cpu
        a.pos_fb = raw - a._slave_offset
    di = d.digital_inputs
    if di != a._digital_inputs:
        a._hw_inputs(di)
