"""One motion cycle of an axis: reference, limits, PDO out, drive step, feedback, faults, status.

Order in a cycle (after the tasks ran):
  1. reference: the profile generator, a PVT trajectory, a fault ramp, an external
     provider, or (torque mode) the feedback itself;
  2. software limits on the reference (fault reaction: stop at kill deceleration);
  3. outputs: controlword and, by op mode, target position / velocity / torque;
  4. the drive steps one cycle;
  5. feedback: position (unwrapped counts), statusword, digital inputs; drive fault or
     abnormal disable -> disable; hardware limits -> kill stop; position error beyond
     max_pos_err -> disable (table 5.1.1.4);
  6. status: moving (region I of figure 5.1.4), in position (regions II/III: within the
     target radius for the debounce time); buffered commands start.

`step` is the only implementation of this cycle. The plain cycle (a profile move or
rest in CSP on a drive in its common cycle: most cycles of most axes) runs straight
through it, with the profile generator's sample and the drive's common cycle written
out in it, one function where four would call each other (the cycle's fast path);
every other cycle takes `_step_general`, where the generator and the drive step
themselves, and every rarer case branches off into a method of its own.

An axis whose state is a fixed point (nothing changed for a few cycles, nothing pending)
rests: the motion kernel does not step it, and the controller may jump ahead. Stepping
it would give the same values, so resting changes no result. What could change them
wakes it (`wake`): every command, and every write to its drive from outside the cycle
(the drive's `on_change`: object dictionary writes and forcing, an injected fault, the
sensors' external inputs, switches or touch probe function).
"""

from __future__ import annotations

import math

from motionvm.drives.objects import (
    DI_NEGATIVE_LIMIT,
    DI_POSITIVE_LIMIT,
    MODE_CSP,
    MODE_CSV,
    SW_FAULT,
    SW_FOLLOWS_TARGET,
    SW_REMOTE,
    SW_VOLTAGE_ENABLED,
    State,
)
from motionvm.motion import axis_status as st

PG, PVT, RAMP, TORQUE, EXT = 0, 1, 2, 3, 4
"""Reference sources: profile generator, PVT, kill ramp, torque mode, an external
provider (gear slave, gantry, homing) set with `Axis.follow`."""

CW_DISABLE, CW_SHUTDOWN, CW_ENABLE, CW_FAULT_RESET = 0x00, 0x06, 0x0F, 0x80
_OPERATION_ENABLED = State.OPERATION_ENABLED
_FS_HW_LIMITS = st.FS_HW_RIGHT | st.FS_HW_LEFT
_SW_CYCLIC = (State.OPERATION_ENABLED.value | SW_VOLTAGE_ENABLED | SW_REMOTE
              | SW_FOLLOWS_TARGET)  # fmt: skip
"""The statusword of a drive in Operation enabled in a cyclic mode, without fault or limit."""

# The cycle's own copies of the reference sources and modes that other modules import
# by name: C ints in the compiled build (axis_cycle.pxd declares them, and the CW_
# constants and _SW_CYCLIC above; a C module variable is no Python attribute, hence
# the copies), the same values in pure Python.
_PG, _PVT, _RAMP, _TORQUE, _EXT = PG, PVT, RAMP, TORQUE, EXT
_MODE_CSP, _MODE_CSV = MODE_CSP, MODE_CSV

# `_round(x)` is round(x) of a float, as in cia402.py (C's rint in the compiled build).
globals()["_round"] = float.__round__
_TWO_31, _MASK_32 = 0x80000000, 0xFFFFFFFF
"""An int32 wraps as ((n + _TWO_31) & _MASK_32) - _TWO_31 (C long longs when compiled,
where the literals would be Python ints)."""


def step_axes(axes: list) -> None:
    """One cycle of each axis of `axes` that does not rest, in their order (the motion
    kernel's loop, here so that the compiled build runs it in C)."""
    for a in axes:
        if not a.resting:  # a resting axis costs this test; what changes it wakes it
            a.step()


def axes_busy(axes: list) -> bool:
    """True if an axis of `axes` moves, enables, settles into position or stops: the
    test `MotionKernel.busy` makes of each axis. An axis jogging at a constant velocity
    it has reached (`AxisCycle.cruising`) counts as settled."""
    for a in axes:
        if a._enabling:
            return True
        if (a.moving or (a.enabled and not a.in_pos)) and not a.cruising:
            return True
    return False


def step_axes_alone(order: list, axes: list, n: int, until_idle: bool) -> int:
    """Up to `n` cycles of `step_axes(order)` in a row, with nothing else in those
    cycles (`MotionKernel.step_alone`); `axes` are the same axes by id. Stops after the
    first cycle that leaves every axis resting or, with `until_idle`, none busy
    (`axes_busy`), where the run loop has something to decide. Returns the cycles run."""
    k = 0
    while k < n:
        for a in order:
            if not a.resting:
                a.step()
        k += 1
        for a in axes:
            if not a.resting:
                break
        else:
            return k  # every axis rests
        if until_idle and not axes_busy(axes):
            return k
    return k


class AxisCycle:
    """The cyclic part of `Axis` (a mixin: the attributes are set up by `Axis.__init__`).

    It holds the slots of the attributes its methods use (axis_cycle.pxd declares them
    for the optional compiled build, where this class is an extension type); `Axis`
    holds the rest."""

    __slots__ = (  # every attribute is set up in Axis.__init__
        "_cmd_path", "_command_queue", "_comp_dependents", "_cycle", "_deferred_move",
        "_digital_inputs", "_enable_cycles", "_enable_timeout_cycles", "_enabling",
        "_error_stop", "_fault_reset_cycles", "_feedback_counts", "_ignore_swl",
        "_in_pos_cycles", "_in_pos_debounce_cycles", "_last_snapshot", "_max_pos_err",
        "_min_pos_err", "_move_end_cycle", "_move_start_cycle", "_on_hw_limit", "_pos_offset",
        "_position_actual", "_provider", "_pvt_cycle", "_pvt_trajectory", "_ramp_decel",
        "_ramp_vel", "_reference_source", "_rest_after_cycles", "_rollover", "_slave_offset",
        "_still_cycles", "_sw_left", "_sw_right", "_sw_stop_left", "_sw_stop_right",
        "_torque_per_mille", "axis_id", "comp_pos", "cpu", "drive", "dt", "enabled",
        "fault_status", "halted", "ignore_hwl", "ignore_pe", "in_pos", "inpos_radius",
        "kill_dec", "last_error", "move_time_ms", "moving", "op_mode", "pg", "pos_fb",
        "pos_fb_raw", "ref_acc", "ref_pos", "ref_vel", "resting", "settling_time_ms",
        "stopping",
    )  # fmt: skip

    # ---- the cycle ------------------------------------------------------------------

    def step(self) -> None:
        """Run this axis's part of one controller cycle.

        The plain cycle, by far the most common one, is computed here in one piece (the
        fast path): a profile move or rest in CSP, enabled, nothing queued, no command
        path (filters, compensation), no fault reset running, and the drive in its
        common cycle (`Cia402Drive.step`: Operation enabled in CSP under the repeated
        enable controlword) with nothing else to check (no forced outputs, no lost
        encoder, no following-error window). Its T-curve sample inside a segment
        without a moving average and the drive's part of the cycle are written out
        here with the same operations as `ProfileGenerator.step` and
        `Cia402Drive.step`; any other sample, and the motor, step themselves. Every
        other cycle goes through `_step_general`, where each part steps itself."""
        drive = self.drive
        self._cycle += 1
        if not (self.enabled and self._reference_source == _PG and self.op_mode == _MODE_CSP
                and drive._csp_ready and drive._controlword_prev == CW_ENABLE
                and drive.mode == _MODE_CSP and self._cmd_path is None
                and self._fault_reset_cycles is None and not drive._forced
                and not drive._encoder_lost and not drive._fe_checked
                and not self._command_queue):  # fmt: skip
            enabled = self._step_general(drive)
        else:
            # 1. the profile generator
            pg = self.pg
            n = pg._n + 1
            tau = n * pg.dt
            if pg._tc_done or pg._smoothing or tau >= pg._seg_t_1:
                p, v, a = pg.step()
            else:  # inside a T-curve segment, no moving average
                pg._n = n
                x = tau - pg._seg_t_0
                p = pg._seg_p_0 + (pg._seg_v_0 + pg._seg_half_a * x) * x
                inv_dt = pg._inv_dt
                v = (p - pg._out_p) * inv_dt
                a = (v - pg._out_v) * inv_dt
                # (the T-curve runs: the generator does not idle)
                pg._out_p, pg._out_v, pg._out_a = p, v, a
            self.ref_pos = p
            self.ref_vel = v
            self.ref_acc = a
            # 2. software limits (the stop positions are +-inf while they are off)
            if not self._sw_stop_left < p < self._sw_stop_right:
                self._software_limit(p, v)
            # 3. outputs
            counts = _round((p + self._slave_offset) * self.cpu)  # noqa: F821
            if counts > 0x7FFFFFFF or counts < -0x80000000:  # beyond int32: the target wraps
                counts = ((counts + _TWO_31) & _MASK_32) - _TWO_31
            drive.target_position = counts
            drive.controlword = CW_ENABLE
            # 4. the drive's common cycle: the demand follows the target's change
            change = counts - drive._target_prev
            if change > 0x7FFFFFFF or change < -0x80000000:  # the target wrapped
                change = ((change + _TWO_31) & _MASK_32) - _TWO_31
            drive._demand = demand = drive._demand + change
            drive._target_prev = counts
            x = drive.mechanics.step_position(demand, self.dt)
            drive._encoder = enc = _round(x)  # noqa: F821
            if enc > 0x7FFFFFFF or enc < -0x80000000:  # beyond int32: the counter wraps
                enc = ((enc + _TWO_31) & _MASK_32) - _TWO_31
            drive.position_actual = position_actual = enc  # (an int32: typed when compiled)
            s = drive.sensors
            if s.quiet_low < x < s.quiet_high:  # (see `Cia402Drive.step`)
                digital_inputs = s.quiet_inputs
            elif s.has_switches or s._tp_function or s.tp_status:
                digital_inputs = s.update(drive._motor_position_prev, x)
            else:
                digital_inputs = s._external
            drive.digital_inputs = digital_inputs
            drive._motor_position_prev = x
            drive.statusword_base = _SW_CYCLIC  # `statusword` adds the internal limit bit
            # 5. feedback and faults: the drive's statusword is the cyclic one
            delta = position_actual - self._position_actual
            if delta:
                if delta > 0x7FFFFFFF or delta < -0x80000000:  # the counter wrapped
                    delta = ((delta + _TWO_31) & _MASK_32) - _TWO_31
                self._feedback_counts = counts = self._feedback_counts + delta
                self._position_actual = position_actual
                self.pos_fb_raw = raw = counts / self.cpu
                self.pos_fb = pos_fb = raw - self._slave_offset
            else:
                pos_fb = self.pos_fb
            if digital_inputs != self._digital_inputs:
                self._hw_inputs(digital_inputs)
            if self._on_hw_limit:  # fault_status & _FS_HW_LIMITS, kept by `_hw_inputs`
                self._hw_limit_stop()
            err = p - pos_fb
            if (err > self._max_pos_err or err < self._min_pos_err) and not self.ignore_pe:
                self._fault_disable(st.PERR, st.FS_POSITION_ERROR)
                enabled = False
            else:
                enabled = True
        # 6. status
        if enabled:
            src = self._reference_source
            if src == _PG:
                # region I lasts while the generator outputs new positions: until the
                # first cycle that repeats the last one (the velocity is then 0)
                moving = (self.ref_vel != 0.0 or not self.pg.is_done or bool(self._command_queue)
                          or self._deferred_move is not None
                          or (self._cmd_path is not None and self._cmd_path.pending))  # fmt: skip
            elif src == _TORQUE:
                moving = self._torque_per_mille != 0
            elif src == _EXT:  # a provider may say when its reference rests (gear, gantry)
                ext = self._provider
                moving = ext.moving(self) if hasattr(ext, "moving") else True
            else:
                moving = True
            if moving:
                # region I: not in position, nothing counts toward rest (no command
                # starts a move without `wake`, which clears the rest count, and the
                # in-position count starts from 0 where region I ends, in `_settle`)
                if not self.moving:
                    self.moving = True
                    self.in_pos = False
                    self._still_cycles = 0
                return
            self._settle()
        else:
            self.moving = self.in_pos = False
            self._in_pos_cycles = 0
        if self._idle_candidate():
            self._watch_rest()
        else:
            self._still_cycles = 0

    def _software_limit(self, p: float, v: float) -> None:
        """The reference p [mm] (velocity v [mm/s]) is outside the software limits' stop
        positions: stop at the kill deceleration if it moves outward."""
        if p >= self._sw_stop_right and v > 0.0:
            if self._reference_source != _TORQUE:
                self._limit_stop(st.SWRL, st.FS_SW_RIGHT)
        elif p <= self._sw_stop_left and v < 0.0:
            if self._reference_source != _TORQUE:
                self._limit_stop(st.SWLL, st.FS_SW_LEFT)

    def _step_general(self, drive) -> bool:
        """Parts 1.-5. of a cycle other than the plain one (each part steps itself);
        returns whether the axis is still enabled."""
        # 1.-3. reference, software limits, outputs
        if self.enabled:
            if self._reference_source == _PG and not self._command_queue:
                p, v, a = self.pg.step()
            else:
                p, v, a = self._reference()
            if self._cmd_path is not None:  # filters, compensation (axis_filters.py)
                p, v, a = self._cmd_path.step(self, p, v, a)
            self.ref_pos = p
            self.ref_vel = v
            self.ref_acc = a
            # the stop positions are +-inf while the software limits are off
            if not self._sw_stop_left < p < self._sw_stop_right:
                self._software_limit(p, v)
            mode = self.op_mode
            if mode == _MODE_CSP:
                counts = _round((p + self._slave_offset) * self.cpu)  # noqa: F821
                if counts > 0x7FFFFFFF or counts < -0x80000000:  # beyond int32: the target wraps
                    counts = ((counts + _TWO_31) & _MASK_32) - _TWO_31
                drive.target_position = counts
            elif mode == _MODE_CSV:
                drive.target_velocity = round(v * self.cpu)
            else:
                drive.target_torque = self._torque_per_mille
            drive.controlword = CW_ENABLE
        else:
            drive.controlword = self._disabled_controlword()
        if self._fault_reset_cycles is not None:
            drive.controlword |= self._fault_reset_bit()
        # 4. the drive
        drive.step(self.dt)
        # 5. feedback and faults
        position_actual = drive.position_actual
        delta = position_actual - self._position_actual
        if delta:
            if delta > 0x7FFFFFFF or delta < -0x80000000:  # beyond int32: the counter wrapped
                delta = ((delta + _TWO_31) & _MASK_32) - _TWO_31
            self._feedback_counts = counts = self._feedback_counts + delta
            self._position_actual = position_actual
            self.pos_fb_raw = raw = counts / self.cpu
            self.pos_fb = raw - self._slave_offset
        # an enabled axis needs a drive in Operation enabled following its cyclic
        # target, no fault; any other statusword is looked at closely (the internal
        # limit bit aside: the base is the statusword without it, see Cia402Drive)
        enabled = self.enabled
        if not enabled or drive.statusword_base != _SW_CYCLIC:
            self._drive_state_changed(drive)
            enabled = self.enabled
        digital_inputs = drive.digital_inputs
        if digital_inputs != self._digital_inputs:
            self._hw_inputs(digital_inputs)
        if enabled:
            if self._on_hw_limit:  # fault_status & _FS_HW_LIMITS, kept by `_hw_inputs`
                self._hw_limit_stop()
            err = self.ref_pos - self.pos_fb
            if (err > self._max_pos_err or err < self._min_pos_err) and not self.ignore_pe:
                self._fault_disable(st.PERR, st.FS_POSITION_ERROR)
                enabled = False
        return enabled

    @property
    def max_pos_err(self) -> float:
        """Position error protection range [mm]: beyond it the axis is disabled."""
        return self._max_pos_err

    @max_pos_err.setter
    def max_pos_err(self, value: float) -> None:
        value = float(value)  # (a float in either build: the compiled one types it)
        self._max_pos_err, self._min_pos_err = value, -value

    @property
    def pos_offset(self) -> float:
        """Position offset [mm] of SetPos and homing: slave = axis + pos_offset (+ comp)."""
        return self._pos_offset

    @pos_offset.setter
    def pos_offset(self, value: float) -> None:
        self._pos_offset = value
        self._slave_offset = float(value + self.comp_pos)

    @property
    def slave_offset(self) -> float:
        """[mm] slave - axis position: the position offset plus the compensation."""
        return self._slave_offset

    def _set_comp(self, comp: float) -> None:
        """Send compensation `comp` [mm] from this cycle on; the feedback follows suit."""
        self.comp_pos = comp
        self._slave_offset = float(self._pos_offset + comp)
        self.pos_fb = self.pos_fb_raw - self._slave_offset

    # ---- 2. software limits ---------------------------------------------------------

    def _software_limits_changed(self) -> None:
        """The stop positions of the cycle's limit check: the software limits while they
        apply (not ignored, no rollover, no error stop yet), else +-inf."""
        if self._ignore_swl or self._rollover or self._error_stop:
            self._sw_stop_left, self._sw_stop_right = -math.inf, math.inf
        else:
            self._sw_stop_left, self._sw_stop_right = self._sw_left, self._sw_right

    @property
    def sw_left(self) -> float:
        """Software left limit [mm] (SetSWLL)."""
        return self._sw_left

    @sw_left.setter
    def sw_left(self, value: float) -> None:
        self._sw_left = value
        self._software_limits_changed()

    @property
    def sw_right(self) -> float:
        """Software right limit [mm] (SetSWRL)."""
        return self._sw_right

    @sw_right.setter
    def sw_right(self, value: float) -> None:
        self._sw_right = value
        self._software_limits_changed()

    @property
    def ignore_swl(self) -> bool:
        """IgnoreSWL: no software limit check."""
        return self._ignore_swl

    @ignore_swl.setter
    def ignore_swl(self, value: bool) -> None:
        self._ignore_swl = value
        self._software_limits_changed()

    @property
    def rollover(self) -> float:
        """Single-turn range [mm or deg] (0: off); a rollover axis has no software limits."""
        return self._rollover

    @rollover.setter
    def rollover(self, value: float) -> None:
        self._rollover = value
        self._software_limits_changed()

    @property
    def error_stop(self) -> bool:
        """True after a fault or limit stop until Reset; the software limits rest then."""
        return self._error_stop

    @error_stop.setter
    def error_stop(self, value: bool) -> None:
        self._error_stop = value
        self._software_limits_changed()

    # ---- 1. reference ---------------------------------------------------------------

    def _reference(self) -> tuple[float, float, float]:
        """The reference of a cycle other than a plain profile move (see `step`)."""
        src = self._reference_source
        if src == _PG:
            pg = self.pg
            if self._command_queue and pg.is_done:
                self._start_next()
            if self._reference_source == _PG:
                return pg.step()
            src = self._reference_source
        if src == _PVT:
            self._pvt_cycle += 1
            t = self._pvt_cycle * self.dt
            p, v, a = self._pvt_trajectory.evaluate(t)
            if t >= self._pvt_trajectory.duration:
                self._reference_source = _PG
                self.pg.reset(p)
                return p, 0.0, (0.0 - self.ref_vel) / self.dt
            return p, v, a
        if src == _RAMP:
            v_0 = self._ramp_vel
            dv = self._ramp_decel * self.dt
            v_1 = 0.0 if abs(v_0) <= dv else v_0 - math.copysign(dv, v_0)
            p = self.ref_pos + 0.5 * (v_0 + v_1) * self.dt
            self._ramp_vel = v_1
            if v_1 == 0.0:
                self._reference_source = _PG
                self.pg.reset(p)
            return p, v_1, (v_1 - v_0) / self.dt
        if src == _EXT:
            return self._provider.reference(self)
        return self.pos_fb, self.vel_fb, 0.0  # torque mode: the reference follows

    # ---- 3. outputs while disabled --------------------------------------------------

    @property
    def vel_fb(self) -> float:
        """Velocity feedback [mm/s]: the drive's actual velocity in axis units."""
        return self.drive.velocity_actual / self.cpu

    def _disabled_controlword(self) -> int:
        drive = self.drive
        drive.target_position = drive.position_actual  # an enabled drive starts where it stands
        if not self._enabling:
            self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
            return CW_DISABLE
        self._enable_cycles += 1
        if self._enable_cycles > self._enable_timeout_cycles:
            self._enabling = False
            self.last_error = st.axis_error(st.DRIVE_ENABLE_TOUT, self.axis_id)
            return CW_DISABLE
        return (
            CW_SHUTDOWN
            if drive.state in (State.SWITCH_ON_DISABLED, State.NOT_READY_TO_SWITCH_ON)
            else CW_ENABLE
        )

    def _fault_reset_bit(self) -> int:
        """Controlword bit 7 while a drive fault is reset: a rising edge every other cycle."""
        self._fault_reset_cycles += 1
        if self._fault_reset_cycles > self._enable_timeout_cycles:
            self._fault_reset_cycles = None
            self.last_error = st.axis_error(st.DRIVE_CLEAR_ERROR_TOUT, self.axis_id)
            return 0
        return CW_FAULT_RESET if self._fault_reset_cycles % 2 else 0

    # ---- 5. feedback and faults -----------------------------------------------------

    def _drive_state_changed(self, drive) -> None:
        """A drive fault came or went, or the power state is not the axis's: fault
        reactions, the end of a fault reset, the end of the enable sequence."""
        state = drive.state
        if drive.statusword & SW_FAULT:
            self.fault_status |= st.FS_DRIVE_FAULT
            if not self.error_stop:
                self._fault_disable(st.DRIVE_FAULT, 0)
        else:
            if self.fault_status & st.FS_DRIVE_FAULT:
                self.fault_status &= ~st.FS_DRIVE_FAULT
                if self._fault_reset_cycles is not None:
                    self._fault_reset_cycles = None
                    self._clear_errors()
            if self.enabled and state is not _OPERATION_ENABLED:
                self._fault_disable(st.DRIVE_ABNORMAL_DISABLE, 0)
        if self._enabling and state is _OPERATION_ENABLED:
            self._enabling = False
            self.enabled = True
            self._reference_source = _PG
            self.pg.reset(self.pos_fb)
            self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
            self._in_pos_cycles = 0

    def _hw_inputs(self, digital_inputs: int) -> None:
        """New digital inputs: the hardware limit bits of fault_status follow the switches.

        IgnoreHWL only suppresses the limit's fault reaction (`_hw_limit_stop`); the bits
        and IsHWLL/IsHWRL still show the switches (0x60FD), as the manual's homing examples
        rely on when they search a limit switch with IgnoreHWL set."""
        self._digital_inputs = digital_inputs
        fs = self.fault_status & ~_FS_HW_LIMITS
        if digital_inputs & DI_POSITIVE_LIMIT:
            fs |= st.FS_HW_RIGHT
        if digital_inputs & DI_NEGATIVE_LIMIT:
            fs |= st.FS_HW_LEFT
        self.fault_status = fs
        # only this method changes the two bits: the cycle tests this flag instead
        self._on_hw_limit = bool(fs & _FS_HW_LIMITS)

    def _hw_limit_stop(self) -> None:
        """A hardware limit switch is on: kill stop if the reference moves into it."""
        fs = self.fault_status
        if not self.error_stop and not self.ignore_hwl:
            v = self.ref_vel
            if fs & st.FS_HW_RIGHT and v > 0.0:
                self._limit_stop(st.HWRL, st.FS_HW_RIGHT)
            elif fs & st.FS_HW_LEFT and v < 0.0:
                self._limit_stop(st.HWLL, st.FS_HW_LEFT)

    # ---- 6. status ------------------------------------------------------------------

    def _settle(self) -> None:
        """The reference rests: region I ends, then in position after the debounce time."""
        if self.moving:  # region I ends
            self.moving = False
            self.stopping = False
            self._in_pos_cycles = 0
            self._move_end_cycle = end = max(self._cycle - 1, self._move_start_cycle)
            run = end - self._move_start_cycle
            if self.pg._n_avg > 1 and run > 0:  # a smooth time (`pg.t_smooth` > 0)
                # Manual 5.1: total time = Ta + Ts. The N-sample moving average reaches
                # the target N - 1 cycles after the T-curve does; count the whole N.
                run += 1
            self.move_time_ms = run * self.dt * 1000.0
        err = self.ref_pos - self.pos_fb
        if -self.inpos_radius <= err <= self.inpos_radius:
            self._in_pos_cycles += 1
            if not self.in_pos and self._in_pos_cycles > self._in_pos_debounce_cycles:
                self.in_pos = True
                if self._move_end_cycle >= 0:
                    self.settling_time_ms = (self._cycle - self._move_end_cycle) * self.dt * 1000.0
                    self._move_end_cycle = -1
        else:
            self._in_pos_cycles = 0
            self.in_pos = False

    @property
    def cruising(self) -> bool:
        """True while the axis jogs at the constant velocity it was commanded and has
        reached (MoveVel; not stopping or halted, nothing buffered) and no software or
        hardware limit can stop it: nothing about its motion changes by itself."""
        if not (self.moving and self.enabled and self._reference_source == _PG) or (
            self.stopping or self.halted or self.error_stop or self._command_queue
            or self._deferred_move is not None or not self.pg.is_cruising
        ):  # fmt: skip
            return False
        if not (self.ignore_swl or self.rollover):
            return False  # a jog ends on a software limit, whichever way it goes
        if not self.ignore_hwl:
            sensors = self.drive.sensors
            switch = sensors.positive_limit if self.ref_vel > 0.0 else sensors.negative_limit
            if switch is not None:
                return False
        return True

    # ---- fault reactions (table 5.1.1.4) --------------------------------------------

    def _limit_stop(self, code: int, bit: int) -> None:
        """Hardware or software limit: stop at the kill deceleration, error stop until Reset."""
        self.fault_status |= bit | st.FS_ERROR_STOP
        self.error_stop = True
        self.last_error = st.axis_error(code, self.axis_id)
        self._command_queue.clear()
        self.stopping = True
        if self._reference_source == _PG:
            self.pg.stop(self.kill_dec)
        else:
            self._start_ramp(self.ref_vel, self.kill_dec)

    def _fault_disable(self, code: int, bit: int) -> None:
        """Drive fault or position error: disable the axis, error stop until Reset."""
        self.fault_status |= bit | st.FS_ERROR_STOP
        self.error_stop = True
        self.last_error = st.axis_error(code, self.axis_id)
        self._drop_motion()
        self.enabled = self._enabling = False
        self.drive.controlword = CW_DISABLE

    # ---- injected faults (a scenario's fault events, the host API) ------------------

    def drive_lost(self) -> None:
        """The drive left the bus: the axis disables as on a drive fault (table 5.1.1.4)."""
        self.wake()
        self.fault_status |= st.FS_DRIVE_FAULT
        self._fault_disable(st.DRIVE_FAULT, 0)

    def position_error_fault(self) -> None:
        """The position error exceeded its limit: disable, error stop (table 5.1.1.4)."""
        self.wake()
        self._fault_disable(st.PERR, st.FS_POSITION_ERROR)

    def _start_ramp(self, v_0: float, decel: float) -> None:
        """Brake the reference from velocity v_0 to rest at `decel` (_PVT and torque stops)."""
        if self.op_mode not in (_MODE_CSP, _MODE_CSV):
            self.op_mode = self.drive.mode = _MODE_CSP
            self._torque_per_mille = 0
        self._reference_source = _RAMP
        self._ramp_vel = v_0
        self._ramp_decel = decel

    # ---- resting --------------------------------------------------------------------

    def _idle_candidate(self) -> bool:
        if self.moving or self._enabling or self._fault_reset_cycles is not None:
            return False
        if self._cmd_path is not None and not self._cmd_path.may_rest():
            return False
        if self.enabled:
            if not self.in_pos or self._command_queue:
                return False
            src = self._reference_source
            if src != _EXT:
                return src == _PG
            # a provider with `holds_still` (an axis group) wakes its axes when its
            # reference moves again; the others keep their axes stepping
            holds_still = getattr(self._provider, "holds_still", None)
            return holds_still is not None and holds_still(self)
        return True

    def _snapshot(self) -> tuple:
        drive = self.drive
        m = drive.mechanics
        # the velocity and torque actual are the drive's stored fields (read outside
        # Operation enabled, else from the motor) with the motor's torque (its velocity
        # and the state are here already), the statusword but for the internal limit bit
        # (which follows from that torque); [8] is `drive.settled`
        return (drive.statusword_base, drive.position_actual, drive._velocity_actual,
                drive._torque_actual, drive.digital_inputs, m.position, m.velocity, drive.state,
                drive._settled is drive.state, self.fault_status, self.ref_pos, self.pos_fb,
                m.torque)  # fmt: skip

    def _watch_rest(self) -> None:
        snap = self._snapshot()
        if snap == self._last_snapshot and snap[8]:
            self._still_cycles += 1
            if self._still_cycles >= self._rest_after_cycles:
                self.resting = True
        else:
            self._still_cycles = 0
            self._last_snapshot = snap

    def wake(self) -> None:
        """Leave rest: every command calls this, and the drive's `on_change` (a write to
        the drive from outside the cycle)."""
        self.resting = False
        self._still_cycles = 0
        if self._comp_dependents:
            self._wake_dependents()

    def _wake_dependents(self) -> None:
        """This axis may move: the axes whose compensation reads it must step too."""
        for d in self._comp_dependents:
            d.resting = False
            d._still_cycles = 0
