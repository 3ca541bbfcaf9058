"""Settings and read-outs of an axis (HIMC manual 5.3), and its variables by name (5.1.1).

A mixin of `Axis`. Setters raise `AxisCommandError` with the manual's codes for a value
out of range (eERR_AXIS_CMD_INVALID_VEL ...) or a forbidden state (moving, enabled).
Velocity, acceleration, deceleration and kill deceleration have the machine file's
ranges (`axis_config.check_range`: 1e-6 .. 1e12; a subnormal velocity would make a move
that never ends); an acceleration time so short the acceleration overflows is refused.
Limits changed while moving apply on the fly (the profile generator replans).
Units: [mm or deg], [mm/s], [mm/s^2]; times [ms] as the HMPL functions take them.
"""

from __future__ import annotations

import math

from motionvm.drives.objects import (
    DI_HOME_SWITCH,
    DI_NEGATIVE_LIMIT,
    DI_POSITIVE_LIMIT,
    MODE_CSP,
    MODES,
)
from motionvm.motion import axis_status as st
from motionvm.motion.axis_config import check_range, range_text
from motionvm.motion.axis_cycle import PG
from motionvm.motion.axis_status import AxisCommandError
from motionvm.runtime.scope import ScopeAxis


def _positive(value: float, code: int, what: str, axis_id: int) -> float:
    if not (math.isfinite(value) and value > 0.0):
        raise AxisCommandError(code, f"axis {axis_id}: {what} {value!r} must be a positive number")
    return value


def _in_range(key: str, value: float, code: int, what: str, axis_id: int) -> float:
    """`value` if it lies in the machine file's range of `key`, else the manual's code."""
    if not check_range(key, value):
        raise AxisCommandError(
            code, f"axis {axis_id}: {what} {value!r} must be in {range_text(key)}"
        )
    return value


class AxisSettings(ScopeAxis):
    """5.3 Get/Set functions of `Axis`, and its variables by name (a `ScopeAxis`)."""

    __slots__ = ()

    # ---- profile limits (5.3.1-5.3.10, 5.3.15-5.3.16) -------------------------------

    def set_vel(self, vel: float) -> None:
        self.wake()
        v = _in_range("max_vel", vel, st.CMD_INVALID_VEL, "velocity", self.axis_id)
        self.pg.set_limits(v_max=v)

    def set_acc(self, acc: float) -> None:
        self.wake()
        a = _in_range("max_acc", acc, st.CMD_INVALID_ACC, "acceleration", self.axis_id)
        self.pg.set_limits(a_max=a)

    def set_dec(self, dec: float) -> None:
        self.wake()
        d = _in_range("max_dec", dec, st.CMD_INVALID_DEC, "deceleration", self.axis_id)
        self.pg.set_limits(d_max=d)

    def set_acc_time(self, ms: float) -> None:
        """Acceleration = maximum velocity / acc_time."""
        ms = _positive(ms, st.CMD_INVALID_ACC, "acceleration time", self.axis_id)
        self.set_acc(self.pg.v_max / ms * 1000.0)  # a tiny ms overflows to inf: refused

    def set_dec_time(self, ms: float) -> None:
        ms = _positive(ms, st.CMD_INVALID_DEC, "deceleration time", self.axis_id)
        self.set_dec(self.pg.v_max / ms * 1000.0)

    def set_kill_dec(self, dec: float) -> None:
        self.wake()
        self.kill_dec = _in_range("kill_dec", dec, st.CMD_INVALID_KILL_DEC, "kill deceleration",
                                  self.axis_id)  # fmt: skip

    def set_smooth_time(self, ms: float) -> None:
        """Ts [ms], 0..500; not while moving (5.3.16)."""
        self._require_still()
        if not (math.isfinite(ms) and 0.0 <= ms <= 500.0):
            raise AxisCommandError(
                st.CMD_INVALID_SM_TIME,
                f"axis {self.axis_id}: smooth time {ms!r} ms is not in 0..500",
            )
        try:
            self.pg.set_smooth_time(ms / 1000.0)
        except RuntimeError:
            raise AxisCommandError(
                st.CMD_INVALID_MOVING, f"axis {self.axis_id} is moving"
            ) from None

    @property
    def smooth_time_ms(self) -> float:
        return self.pg.t_smooth * 1000.0

    # ---- software limits (5.3.11-5.3.14) --------------------------------------------

    def set_sw_right(self, pos: float) -> None:
        self.wake()
        if not (math.isfinite(pos) and pos > self.sw_left):
            raise AxisCommandError(
                st.CMD_INVALID_POS,
                f"axis {self.axis_id}: right limit {pos!r} is not above "
                f"the left limit {self.sw_left:g}",
            )
        self.sw_right = pos

    def set_sw_left(self, pos: float) -> None:
        self.wake()
        if not (math.isfinite(pos) and pos < self.sw_right):
            raise AxisCommandError(
                st.CMD_INVALID_POS,
                f"axis {self.axis_id}: left limit {pos!r} is not below "
                f"the right limit {self.sw_right:g}",
            )
        self.sw_left = pos

    # ---- position (5.3.19-5.3.32) ---------------------------------------------------

    def set_pos(self, pos: float) -> None:
        """Make the current position read `pos` by changing the position offset (5.3.19).

        Not applicable (5.3.19) to an axis added to an axis group, enabled or not, with
        eERR_AXIS_CMD_INVALID_GROUPED: the group's pose is made of its axes' positions;
        to one in the synchronous state (a coupled gear slave, IsSync 1) with
        eERR_AXIS_CMD_INVALID_IN_SYNC: its position is the master's; nor while it is in
        error stop (eERR_AXIS_CMD_INVALID_ERROR_STATE). Refused with
        eERR_AXIS_CMD_INVALID_COMP_ENABLED while an active compensation fixes its
        coordinates (14.1: it is compensated, or a reference axis of a compensation).
        """
        self.wake()
        if self.filters.locks_origin:
            raise AxisCommandError(
                st.CMD_INVALID_COMP_ENABLED,
                f"axis {self.axis_id}: dynamic error compensation fixes its origin",
            )
        if self.extra_status & st.MS_GROUP:
            raise AxisCommandError(
                st.CMD_INVALID_GROUPED, f"axis {self.axis_id} is in an axis group"
            )
        if self.extra_status & st.MS_SYNC:
            raise AxisCommandError(
                st.CMD_INVALID_IN_SYNC, f"axis {self.axis_id} is synchronous (a gear slave)"
            )
        self._require_still()
        if self.error_stop:
            raise AxisCommandError(
                st.CMD_INVALID_ERROR_STATE, f"axis {self.axis_id} is in error stop"
            )
        if not math.isfinite(pos):
            raise AxisCommandError(st.CMD_INVALID_POS, f"axis {self.axis_id}: position {pos!r}")
        self.shift_origin(self.pos_fb, pos)
        self._in_pos_cycles = 0
        self.in_pos = False

    def shift_origin(self, anchor: float, value: float) -> None:
        """Make the position `anchor` [mm] read `value` by changing the position offset.

        The feedback and the reference shift alike. A reference within half an encoder
        count of `anchor` is the same position as far as the encoder can tell: it reads
        exactly `value` (an axis at rest on its target after SetPos(a, 0) has
        GetRefPos(a) == 0.0, as the homing example of 20.1.2 tests), not `value` plus
        the rounding of the floating-point shift. SetPos and homing (homing.py) both
        shift the origin here.
        """
        shift = value - anchor
        self.pos_offset -= shift
        self.pos_fb = self.pos_fb_raw - self.slave_offset
        if abs(self.ref_pos - anchor) * self.cpu < 0.5:
            self.ref_pos = value
        else:
            self.ref_pos += shift
        self.pg.reset(self.ref_pos)

    @property
    def pos_out(self) -> float:
        """Position command without offset [mm]: the reference plus the compensation."""
        return self.ref_pos + self.comp_pos

    def _wrapped(self, x: float) -> float:
        r = self.rollover
        return x % r if r else x

    @property
    def rollover_turns(self) -> int:
        r = self.rollover
        return math.floor(self.pos_fb / r) if r else 0

    @property
    def current_fb(self) -> float:
        """Current feedback [A] = torque actual [N*m] / torque constant."""
        torque = self.drive.torque_actual * self.drive.rated_torque_nm / 1000.0
        return torque / self.config.torque_constant

    # ---- notifications, scale, rollover, modes (5.3.33-5.3.44) ----------------------

    def set_ignore(self, which: str, on: int) -> None:
        """IgnoreHWL / IgnoreSWL / IgnorePE: `which` is "hwl", "swl" or "pe"."""
        self.wake()
        if on not in (0, 1):
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"axis {self.axis_id}: cmd {on} must be 0 or 1"
            )
        setattr(self, "ignore_" + which, bool(on))
        if which == "hwl":
            self._digital_inputs = -1  # re-evaluate the switch bits next cycle

    def set_vel_scale(self, percent: float) -> None:
        self.wake()
        if not (math.isfinite(percent) and 0.0 <= percent <= 100.0):
            raise AxisCommandError(
                st.CMD_INVALID_VEL_SCALE,
                f"axis {self.axis_id}: velocity scale {percent!r} is not in 0..100",
            )
        self.vel_scale = percent
        if not self.halted:
            self.pg.set_velocity_scale(percent / 100.0)
            if percent > 0.0 and self._deferred_move is not None:
                self._start(self._deferred_move)

    def set_rollover(self, value: float) -> None:
        """Single-turn range [mm or deg], 0 = off; only while disabled (5.3.39). A range
        below one encoder count (1 / counts_per_unit) is refused: no position fits in it."""
        self.wake()
        if self.enabled or self._enabling:
            raise AxisCommandError(st.CMD_INVALID_ENABLED, f"axis {self.axis_id} is enabled")
        if not (math.isfinite(value) and value >= 0.0):
            raise AxisCommandError(
                st.CMD_INVALID_ROLLOVER_POS,
                f"axis {self.axis_id}: rollover {value!r} must be positive (0: off)",
            )
        if value and value * self.cpu < 1.0:
            raise AxisCommandError(
                st.CMD_INVALID_ROLLOVER_POS,
                f"axis {self.axis_id}: rollover {value!r} is below one encoder count "
                f"({1.0 / self.cpu:g})",
            )
        self.rollover = value

    def set_op_mode(self, mode: int) -> None:
        """8 CSP, 9 CSV, 10 CST; not while moving. Leaving CST holds the position."""
        self._require_still()
        if mode not in MODES or mode < MODE_CSP:
            raise AxisCommandError(
                st.CMD_INVALID_OP_MODE, f"axis {self.axis_id}: op mode {mode} is not 8, 9 or 10"
            )
        self.op_mode = self.drive.mode = mode
        self._torque_per_mille = 0
        self.drive.target_torque = 0
        self.drive.target_velocity = 0
        self._reference_source = PG
        self.pg.reset(self.pos_fb)
        self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0

    def set_buffer_mode(self, mode: int) -> None:
        self.wake()
        if mode not in (0, 1):
            raise AxisCommandError(
                st.CMD_INVALID_BUFFER_MODE, f"axis {self.axis_id}: buffer mode {mode} is not 0 or 1"
            )
        if self._command_queue:
            raise AxisCommandError(
                st.CMD_INVALID_SETBUFFERMODE, f"axis {self.axis_id} has buffered commands"
            )
        self.buffer_mode = mode

    @property
    def cmd_num(self) -> int:
        """Commands waiting in the buffer (the one running is not counted)."""
        return len(self._command_queue)

    # ---- times the controller variables set (manual 17.1.1.2) ------------------------

    @property
    def inpos_debounce_ms(self) -> float:
        """In-position settling time [ms] (HCV_ID_pos_tr_t), a whole number of cycles."""
        return self._in_pos_debounce_cycles * self.dt * 1000.0

    @inpos_debounce_ms.setter
    def inpos_debounce_ms(self, ms: float) -> None:
        self.wake()
        self._in_pos_debounce_cycles = round(ms / 1000.0 / self.dt)

    @property
    def enable_timeout_ms(self) -> float:
        """Enable timeout [ms] (HCV_ID_en_delay), a whole number of cycles."""
        return self._enable_timeout_cycles * self.dt * 1000.0

    @enable_timeout_ms.setter
    def enable_timeout_ms(self, ms: float) -> None:
        self._enable_timeout_cycles = math.ceil(ms / 1000.0 / self.dt - 1e-9)

    # ---- status words (tables 5.1.1.4, 5.1.1.5) -------------------------------------

    @property
    def accelerating(self) -> bool:
        """|ref_vel| grows; an |ref_acc| below 1e-6 * max_acc is rounding of a cruise."""
        a = self.ref_acc
        return self.moving and self.ref_vel * a > 0.0 and abs(a) > 1e-6 * self.pg.a_max

    @property
    def motion_status(self) -> int:
        s = 0
        if self.enabled:
            s |= st.MS_ENABLED
        if self.moving:
            s |= st.MS_MOVING
        if self.in_pos:
            s |= st.MS_IN_POSITION
        if self.accelerating:
            s |= st.MS_ACCELERATING
        return s | self.extra_status

    # ---- variables by name (5.1.1) --------------------------------------------------

    def variable(self, name: str) -> float | int:
        """The axis variable `name` of manual 5.1.1 (e.g. "ref_pos", "fault_status")."""
        getter = _GETTERS.get(name)
        if getter is None:
            raise KeyError(f"no axis variable '{name}' (known: {', '.join(st.VARIABLES)})")
        return getter(self)


def _w(attr: str):
    return lambda a: a._wrapped(getattr(a, attr))


_GETTERS = {
    "sync_pos_set": _w("ref_pos"),
    "pg_pos_cmd": lambda a: a._wrapped(a.pg.target if a._reference_source == PG else a.ref_pos),
    "ref_pos": _w("ref_pos"),
    "ref_vel": lambda a: a.ref_vel,
    "ref_acc": lambda a: a.ref_acc,
    "comp_pos_set": lambda a: a.comp_pos,
    "pos_comp": _w("pos_out"),
    "pos_offset": lambda a: a.pos_offset,
    "pos_out": _w("pos_out"),
    "vel_out": lambda a: a.ref_vel,
    "acc_out": lambda a: a.ref_acc,
    "offset_pos_out": lambda a: a.ref_pos + a.slave_offset,
    "pos_fb_raw": lambda a: a.pos_fb_raw,
    "offset_pos_fb": lambda a: a.pos_fb + a.slave_offset,
    "pos_fb": _w("pos_fb"),
    "vel_fb": lambda a: a.vel_fb,
    "pos_err": lambda a: a.ref_pos - a.pos_fb,
    "vel_err": lambda a: a.ref_vel - a.vel_fb,
    "movetime": lambda a: a.move_time_ms,
    "settlingtime": lambda a: a.settling_time_ms,
    "max_vel": lambda a: a.pg.v_max,
    "max_acc": lambda a: a.pg.a_max,
    "max_dec": lambda a: a.pg.d_max,
    "sm_factor": lambda a: a.smooth_time_ms,
    "fault_status": lambda a: a.fault_status,
    "motion_status": lambda a: a.motion_status,
    "power_drive_st": lambda a: a.drive.state.value,
    "coe_controlword": lambda a: a.drive.controlword,
    "coe_statusword": lambda a: a.drive.statusword,
    "servo_type": lambda a: a.drive.mode,
    "coe_op_modes_display": lambda a: a.drive.mode_display,
    "coe_pos_cmd": lambda a: a.drive.target_position,
    "coe_vel_cmd": lambda a: a.drive.target_velocity,
    "coe_trq_cmd": lambda a: a.drive.target_torque,
    "coe_pos_fb": lambda a: a.drive.position_actual,
    "coe_vel_fb": lambda a: a.drive.velocity_actual,
    "coe_trq_fb": lambda a: a.drive.torque_actual,
    "tp_function": lambda a: a.drive.tp_function,
    "tp_status": lambda a: a.drive.tp_status,
    "tp1_positive_edge": lambda a: a.drive.tp1_positive_edge,
    "tp1_negative_edge": lambda a: a.drive.tp1_negative_edge,
    "tp2_positive_edge": lambda a: a.drive.tp2_positive_edge,
    "tp2_negative_edge": lambda a: a.drive.tp2_negative_edge,
    "di_bit_HWLL": lambda a: 1 if a.drive.digital_inputs & DI_NEGATIVE_LIMIT else 0,
    "di_bit_HWRL": lambda a: 1 if a.drive.digital_inputs & DI_POSITIVE_LIMIT else 0,
    "di_bit_HOME": lambda a: 1 if a.drive.digital_inputs & DI_HOME_SWITCH else 0,
}
assert set(_GETTERS) == set(st.VARIABLES)
