"""The common axis cycle in one function: a profile move in CSP on an ideal drive.

`fast_step(axis)` does exactly what `AxisCycle.step` + `Cia402Drive.step` +
`IdealMechanics.step_position` do for an enabled axis that follows its profile
generator in CSP on an ideal drive that is in Operation enabled, settled, without
fault, touch probes or a buffered command to start, and returns True; in any other
case it does nothing and returns False, and the general path runs. The same
arithmetic in the same order gives bit-identical results
(tests/motion/test_axis_fast.py steps both paths side by side and compares every
variable). It exists for speed alone: it saves about half of an axis's cycle, which
is most of the motion kernel's time with many moving axes (bench/motion.py).

It reads and writes the drive's internal state; a change to `Cia402Drive._move`,
`_feedback` or `IdealMechanics._advance` must be mirrored here (the test catches it).

Values no cycle reads are not computed each cycle: the cycle leaves the drive's
velocity_actual, torque_actual, position_demand, following_error, the mechanics'
_demand_vel and the axis's vel_fb None, and their properties compute them when read,
from the state the cycle left, with the same arithmetic (every general step sets them
again). The following error window is checked only where an int32 error can exceed it,
the internal limit bit only where the torque can reach max_torque. The limit and home
switches are checked by position band, the index pulse by index interval: both without
a call while the position stays inside (`_switch_band`, `_index_band`).
"""

from __future__ import annotations

import math

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.mechanics import TWO_PI, IdealMechanics
from motionvm.drives.objects import (
    DI_INDEX_PULSE,
    ERR_FOLLOWING,
    MODE_CSP,
    SW_FOLLOWING_ERROR,
    SW_FOLLOWS_TARGET,
    SW_INTERNAL_LIMIT,
    State,
)
from motionvm.motion import axis_status as st
from motionvm.motion.profile import IDLE

_OE = State.OPERATION_ENABLED
_SW_OE = State.OPERATION_ENABLED.value | 0x10 | 0x200 | SW_FOLLOWS_TARGET  # voltage, remote
_CW_ENABLE = 0x0F


def eligible(axis) -> bool:
    """True if `fast_step` may run this cycle."""
    d = axis.drive
    return (
        axis.enabled
        and axis._source == 0
        and axis.op_mode == MODE_CSP
        and axis._clearing is None
        and not axis._queue
        and d.state is _OE
        and d._settled is _OE
        and d._cw_prev == _CW_ENABLE
        and d._fault is None
        and d._mode_prev == MODE_CSP
        and d.mode_display == MODE_CSP
        and d.mode == MODE_CSP
        and type(d.mechanics) is IdealMechanics
        and not d.sensors.tp_function
        and not d.sensors.tp_status
    )


def _switch_band(s, x: float, inputs: int) -> tuple[float, float, int, int]:
    """(lo, hi, bits, external): on lo < x < hi no limit or home edge lies, and the
    inputs without the index pulse are `bits | external` (as `Sensors.update` computes
    them); an empty band if x is on an edge. `Sensors.update` reads the position before
    the cycle only for the index pulse and the touch probes (off on the fast path)."""
    lo, hi = -math.inf, math.inf
    for edge in (s.negative_limit, s.positive_limit, s.home_low, s.home_high):
        if edge is not None:
            if edge < x:
                lo = max(lo, edge)
            elif edge > x:
                hi = min(hi, edge)
            else:
                return (0.0, 0.0, 0, -1)  # on an edge: no band
    bits = inputs & ~(DI_INDEX_PULSE | s.external)
    if lo == -math.inf and hi == math.inf:
        return (lo, hi, bits, s.external)
    margin = 1e-6 * max(1.0, abs(x))  # far above any rounding of x
    return (lo + margin, hi - margin, bits, s.external)


def _index_band(x: float, spacing: float, offset: float) -> tuple[int, float, float]:
    """(n, lo, hi): n = floor((x - offset) / spacing), the index interval `Sensors` finds x
    in, and on lo < x' < hi the same n for x' (a margin far above the rounding of the
    floor; an empty band where it does not fit)."""
    n = math.floor((x - offset) / spacing)
    lo = offset + n * spacing
    hi = offset + (n + 1) * spacing
    margin = 1e-6 * max(1.0, abs(lo), abs(hi), abs(offset))
    return n, lo + margin, hi - margin


def fast_step(axis) -> bool:
    """One cycle of `axis` on the fast path; False (and nothing done) if not eligible.

    `axis._fast_ok` caches the decision: None = check again, False = not eligible, else
    the cycle function built for the axis. Any command (`Axis.wake`) and any cycle of
    the general path reset it to None.
    """
    f = axis._fast_ok
    if f is None:
        f = axis._fast_ok = _make(axis) if eligible(axis) else False
    if f is False:
        return False
    if f():
        return True
    axis._fast_ok = None
    return False


def _make(axis):
    """The cycle function of `axis`, with what stays fixed until the next wake bound.

    Written for speed: what the cycle reads more than once is a local, int32 wraps are
    skipped where the value is in range already (the wrap is then the identity), and a
    profile generator without smoothing is stepped inline (`ProfileGenerator.step`,
    N <= 1: the same operations in the same order)."""
    d = axis.drive
    m = d.mechanics
    s = d.sensors
    line = m._line
    append, popleft = line.append, line.popleft
    pg = axis.pg
    pg_step = pg.step
    pg_dt = pg.dt
    inv_dt = pg._inv_dt
    pg_pending = pg._pending
    dt = axis.dt
    cpu = axis.cpu
    pos_offset = axis.pos_offset
    sw_check = not (axis.ignore_swl or axis.rollover or axis.error_stop)
    sw_left, sw_right = axis.sw_left, axis.sw_right
    limit_stop = axis._limit_stop
    max_pos_err = axis.max_pos_err
    ignore_pe = axis.ignore_pe
    inertia, cpr = m.inertia, m.counts_per_rev
    per_mille_per_nm = d._per_mille_per_nm
    has_switches = s.has_switches
    hw_bits = st.FS_HW_RIGHT | st.FS_HW_LEFT
    swrl, fs_sw_right, swll, fs_sw_left = st.SWRL, st.FS_SW_RIGHT, st.SWLL, st.FS_SW_LEFT
    round_ = round

    max_torque = d.max_torque
    tq_bound = float(max_torque - 1) if max_torque > 0 else math.inf
    # lazy: leave the drive's velocity_actual, torque_actual, position_demand,
    # following_error and the axis's vel_fb unset (None); their properties compute them
    # when read
    lazy = isinstance(d, Cia402Drive) and isinstance(getattr(type(axis), "vel_fb", None), property)
    if lazy:
        d._velocity_actual = d._torque_actual = d._position_demand = None
        d._following_error = axis._vel_fb = None
    # lazy_m: leave the mechanics' _demand_vel unset (None) likewise; its property needs
    # the last two demands: a delay line with the last demand last (always so after a step)
    lazy_m = len(line) >= 1 and m._demand is line[-1]
    if lazy_m:
        m._dv = None
        m._lazy_dt = dt
    spacing, offset = s.index_spacing, s.index_offset
    # the switch band starts empty (the first cycle calls Sensors.update); n_prev is
    # the index interval of the position before the cycle (Sensors._index_crossed)
    sb_lo, sb_hi, sb_bits, sb_ext = 0.0, 0.0, 0, -1
    i_n, i_lo, i_hi = 0, 0.0, 0.0
    n_prev = math.floor((d._x_prev - offset) / spacing) if spacing else 0

    clean = False  # in_pos, _in_pos_count and _still are False, 0, 0 already

    def cycle() -> bool:
        nonlocal sb_lo, sb_hi, sb_bits, sb_ext, i_n, i_lo, i_hi, n_prev, clean
        if (
            d._fault is not None
            or d._encoder_lost
            or d.controlword != 15
            or d.mode != 8
            or s.tp_function
        ):
            return False  # 15: _CW_ENABLE, 8: MODE_CSP
        axis._cycle += 1
        if pg._n_avg <= 1:  # ProfileGenerator.step without smoothing, inline
            if pg._idle:
                p, v, a = pg._out
            else:
                n = pg._n + 1
                pg._n = n
                if pg._tc_done:
                    p = pg._p_f
                else:
                    tau = n * pg_dt
                    i = pg._seg_i
                    segs = pg._segs
                    seg = segs[i]
                    if tau >= seg[1]:
                        nseg = pg._nseg
                        while tau >= seg[1]:
                            i += 1
                            if i == nseg:
                                break
                            seg = segs[i]
                        pg._seg_i = i
                        if i == nseg:
                            pg._tc_done = True
                            p = pg._p_f
                        else:
                            x = tau - seg[0]
                            p = seg[2] + (seg[3] + 0.5 * seg[4] * x) * x
                    else:
                        x = tau - seg[0]
                        p = seg[2] + (seg[3] + 0.5 * seg[4] * x) * x
                p_prev, v_prev, _ = pg._out
                v = (p - p_prev) * inv_dt
                a = (v - v_prev) * inv_dt
                pg._out = (p, v, a)
                if v == 0.0 and a == 0.0 and pg._tc_done and p == pg._p_f:
                    pg._idle = True
                    if not pg_pending():
                        pg.mode = IDLE
        else:
            p, v, a = pg_step()
        axis.ref_pos = p
        axis.ref_vel = v
        axis.ref_acc = a
        if sw_check:
            if p >= sw_right and v > 0.0:
                limit_stop(swrl, fs_sw_right)
            elif p <= sw_left and v < 0.0:
                limit_stop(swll, fs_sw_left)
        tp = round_((p + pos_offset) * cpu)
        if not -0x80000000 <= tp <= 0x7FFFFFFF:
            tp = ((tp + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        d.target_position = tp
        # the controlword is 0x0F already (checked above) and mode_display 8 (eligible)
        # Cia402Drive._move, CSP
        dtp = tp - d._target_prev
        if not -0x80000000 <= dtp <= 0x7FFFFFFF:
            dtp = ((dtp + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        d._r = r = d._r + dtp
        d._target_prev = tp
        # IdealMechanics.step_position -> _advance
        if not lazy_m:  # else IdealMechanics._demand_vel computes it when read
            m._dv = (r - m._demand) / dt
        m._demand = r
        append(r)
        x = popleft()
        v_m = (x - m.position) / dt
        m.torque = torque_nm = inertia * (v_m - m.velocity) / dt * TWO_PI / cpr
        m.velocity = v_m
        m.position = x
        # Cia402Drive._feedback (the encoder is not lost: checked above)
        d._enc = enc = round_(x)
        pa = enc
        if not -0x80000000 <= pa <= 0x7FFFFFFF:
            pa = ((pa + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        d.position_actual = pa
        tq = torque_nm * per_mille_per_nm
        sw = _SW_OE
        if lazy:
            # velocity_actual, torque_actual, position_demand, following_error and vel_fb
            # stay None: their properties compute them when read (the same values)
            window = d.following_error_window
            if window < 0x80000000:  # else no int32 following error exceeds it
                fe = round_(r) - enc
                if not -0x80000000 <= fe <= 0x7FFFFFFF:
                    fe = ((fe + 0x80000000) & 0xFFFFFFFF) - 0x80000000
                if (fe if fe >= 0 else -fe) > window:
                    d.inject_fault(ERR_FOLLOWING)  # d._fault was None (checked above)
                    sw |= SW_FOLLOWING_ERROR
        else:
            demand = round_(r)
            vel_a = round_(v_m)
            if not -0x80000000 <= vel_a <= 0x7FFFFFFF:
                vel_a = ((vel_a + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            d.velocity_actual = vel_a
            axis.vel_fb = vel_a / cpu
            torque = round_(tq)
            if not -32768 <= torque <= 32767:
                torque = max(-32768, min(32767, torque))
            d.torque_actual = torque
            d.position_demand = ((demand + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            fe = demand - enc
            if not -0x80000000 <= fe <= 0x7FFFFFFF:
                fe = ((fe + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            d.following_error = fe
            if (fe if fe >= 0 else -fe) > d.following_error_window:
                d.inject_fault(ERR_FOLLOWING)  # d._fault was None (checked above)
                sw |= SW_FOLLOWING_ERROR
        if has_switches:
            # Sensors.update(x_0, x), skipped while x stays inside the switch band and
            # the index interval is known without a division (see _switch_band)
            if sb_lo < x < sb_hi and s.external == sb_ext:
                di = sb_bits | sb_ext
                if spacing:
                    if i_lo < x < i_hi:
                        n_1 = i_n
                    else:
                        i_n, i_lo, i_hi = _index_band(x, spacing, offset)
                        n_1 = i_n
                    if n_1 != n_prev:  # an index pulse passed (x_0 != x then)
                        di |= DI_INDEX_PULSE
                    n_prev = n_1
            else:
                di = s.update(d._x_prev, x)
                sb_lo, sb_hi, sb_bits, sb_ext = _switch_band(s, x, di)
                if spacing:
                    i_n, i_lo, i_hi = _index_band(x, spacing, offset)
                    n_prev = i_n
        else:
            di = s.external
        d.digital_inputs = di
        d._x_prev = x
        # the internal limit bit, abs(torque_actual) >= max_torque > 0: clear below the
        # bound, where round() cannot reach max_torque (as at the last wake)
        if not (-tq_bound < tq < tq_bound and d.max_torque == max_torque):
            torque = round_(tq)
            if not -32768 <= torque <= 32767:
                torque = max(-32768, min(32767, torque))
            if (torque if torque >= 0 else -torque) >= d.max_torque > 0:
                sw |= SW_INTERNAL_LIMIT
        d.statusword = sw
        # AxisCycle._feedback, enabled, no drive fault (a fault shows from the next cycle)
        delta = pa - axis._pa
        if delta:
            if not -0x80000000 <= delta <= 0x7FFFFFFF:
                delta = ((delta + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            axis._fb_counts = fb = axis._fb_counts + delta
            axis._pa = pa
            axis.pos_fb_raw = raw = fb / cpu
            axis.pos_fb = pos_fb = raw - pos_offset
        else:
            pos_fb = axis.pos_fb
        if di != axis._di:
            axis._hw_inputs(di)
        if axis.fault_status & hw_bits or ignore_pe:
            axis._enabled_checks()
        else:
            err = p - pos_fb
            if err > max_pos_err or -err > max_pos_err:
                axis._fault_disable(st.PERR, st.FS_POSITION_ERROR)
        if axis.moving and not axis.error_stop and not pg._tc_done:  # is_done needs _tc_done
            if not clean:  # only _update_status, _watch_rest (below) or a wake change them
                axis.in_pos = False
                axis._in_pos_count = 0
                axis._still = 0
                clean = True
            return True
        clean = False
        if axis.error_stop:
            axis._fast_ok = None
        axis._update_status()
        if axis._idle_candidate():
            axis._watch_rest()
        else:
            axis._still = 0
        return True

    return cycle
