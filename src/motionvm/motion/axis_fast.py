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
"""

from __future__ import annotations

import math

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


def _band(s, x: float, inputs: int) -> tuple[float, float, int, int]:
    """(lo, hi, bits, external): on lo < x < hi no limit, home or index edge lies, and the
    inputs are `bits | external` (no index pulse), as `Sensors.update` computes them."""
    lo, hi = -math.inf, math.inf
    for edge in (s.negative_limit, s.positive_limit, s.home_low, s.home_high):
        if edge is not None:
            if edge < x:
                lo = max(lo, edge)
            elif edge > x:
                hi = min(hi, edge)
            else:
                return (0.0, 0.0, 0, -1)  # on an edge: no band
    spacing = s.index_spacing
    if spacing:
        n = math.floor((x - s.index_offset) / spacing)
        lo = max(lo, s.index_offset + n * spacing)
        hi = min(hi, s.index_offset + (n + 1) * spacing)
    margin = 1e-6 * max(1.0, abs(x))  # far above the rounding of the floor() above
    bits = inputs & ~(DI_INDEX_PULSE | s.external)
    return (lo + margin, hi - margin, bits, s.external)


def _inputs(axis, s, x_0: float, x_1: float) -> int:
    """`Sensors.update(x_0, x_1)`, skipped while both positions lie inside the last band."""
    lo, hi, bits, external = axis._band
    if lo < x_1 < hi and lo < x_0 < hi and external == s.external:
        return bits | external
    inputs = s.update(x_0, x_1)
    axis._band = _band(s, x_1, inputs)
    return inputs


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
    """The cycle function of `axis`, with what stays fixed until the next wake bound."""
    d = axis.drive
    m = d.mechanics
    s = d.sensors
    line = m._line
    pg = axis.pg
    pg_step = pg.step
    dt = axis.dt
    cpu = axis.cpu
    pos_offset = axis.pos_offset
    sw_check = not (axis.ignore_swl or axis.rollover or axis.error_stop)
    sw_left, sw_right = axis.sw_left, axis.sw_right
    max_pos_err = axis.max_pos_err
    ignore_pe = axis.ignore_pe
    inertia, cpr = m.inertia, m.counts_per_rev
    per_mille_per_nm = d._per_mille_per_nm
    has_switches = s.has_switches
    hw_bits = st.FS_HW_RIGHT | st.FS_HW_LEFT

    def cycle() -> bool:
        if (
            d._fault is not None
            or d.controlword != _CW_ENABLE
            or d.mode != MODE_CSP
            or s.tp_function
        ):
            return False
        axis._cycle += 1
        p, v, a = pg_step()
        axis.ref_pos, axis.ref_vel, axis.ref_acc = p, v, a
        if sw_check:
            if p >= sw_right and v > 0.0:
                axis._limit_stop(st.SWRL, st.FS_SW_RIGHT)
            elif p <= sw_left and v < 0.0:
                axis._limit_stop(st.SWLL, st.FS_SW_LEFT)
        c = round((p + pos_offset) * cpu)
        tp = d.target_position = ((c + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        # the controlword is 0x0F already (checked above) and mode_display 8 (eligible)
        # Cia402Drive._move, CSP
        r = d._r + (((tp - d._target_prev) + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        d._r = r
        d._target_prev = tp
        # IdealMechanics.step_position -> _advance
        m._demand_vel = (r - m._demand) / dt
        m._demand = r
        line.append(r)
        x = line.popleft()
        v_m = (x - m.position) / dt
        m.torque = torque_nm = inertia * (v_m - m.velocity) / dt * TWO_PI / cpr
        m.velocity = v_m
        m.position = x
        # Cia402Drive._feedback
        if not d._encoder_lost:
            d._enc = enc = round(x)
            pa = d.position_actual = ((enc + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            vel = round(v_m)
            d.velocity_actual = vel_a = ((vel + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        else:
            enc = d._enc
            pa = d.position_actual
            d.velocity_actual = vel_a = 0
        torque = round(torque_nm * per_mille_per_nm)
        if not -32768 <= torque <= 32767:
            torque = max(-32768, min(32767, torque))
        d.torque_actual = torque
        demand = round(r)
        d.position_demand = ((demand + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        d.following_error = fe = ((demand - enc + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        if has_switches:
            x_0 = d._x_prev
            lo, hi, bits, external = axis._band
            if lo < x < hi and lo < x_0 < hi and external == s.external:
                di = bits | external  # what Sensors.update would give (see _inputs)
            else:
                di = _inputs(axis, s, x_0, x)
        else:
            di = s.external
        d.digital_inputs = di
        d._x_prev = x
        if abs(fe) > d.following_error_window:
            d.inject_fault(ERR_FOLLOWING)
        sw = _SW_OE
        if abs(torque) >= d.max_torque > 0:
            sw |= SW_INTERNAL_LIMIT
        if d._fault == ERR_FOLLOWING:
            sw |= SW_FOLLOWING_ERROR
        d.statusword = sw
        # AxisCycle._feedback, enabled, no drive fault (a fault shows from the next cycle)
        delta = pa - axis._pa
        if delta:
            axis._fb_counts += ((delta + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            axis._pa = pa
            axis.pos_fb_raw = raw = axis._fb_counts / cpu
            axis.pos_fb = raw - pos_offset
        axis.vel_fb = vel_a / cpu
        if di != axis._di:
            axis._hw_inputs(di)
        if axis.fault_status & hw_bits or ignore_pe:
            axis._enabled_checks()
        else:
            err = p - axis.pos_fb
            if err > max_pos_err or -err > max_pos_err:
                axis._fault_disable(st.PERR, st.FS_POSITION_ERROR)
        if axis.moving and not axis.error_stop and not pg._tc_done:  # is_done needs _tc_done
            axis.in_pos = False
            axis._in_pos_count = 0
            axis._still = 0
            return True
        if axis.error_stop:
            axis._fast_ok = None
        axis._update_status()
        if axis._idle_candidate():
            axis._watch_rest()
        else:
            axis._still = 0
        return True

    return cycle
