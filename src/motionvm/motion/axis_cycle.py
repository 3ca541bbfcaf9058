"""One motion cycle of an axis: reference, limits, PDO out, drive step, feedback, faults, status.

Order in a cycle (after the tasks ran):
  1. reference: the profile generator, a PVT trajectory, a fault ramp, or (torque mode)
     the feedback itself;
  2. software limits on the reference (fault reaction: stop at kill deceleration);
  3. outputs: controlword and, by op mode, target position / velocity / torque;
  4. the drive steps one cycle;
  5. feedback: position (unwrapped counts), velocity, statusword, digital inputs;
     drive fault or abnormal disable -> disable; hardware limits -> kill stop;
     position error beyond max_pos_err -> disable (table 5.1.1.4);
  6. status: moving (region I of figure 5.1.4), in position (regions II/III: within the
     target radius for the debounce time), accelerating; buffered commands start.

An axis whose state is a fixed point (nothing changed for a few cycles, nothing pending)
rests: its step only checks that no command or input woke it. Stepping it would give
the same values, so resting changes no result, and the controller may jump ahead.
"""

from __future__ import annotations

import math

from motionvm.drives.objects import (
    DI_HOME_SWITCH,
    DI_NEGATIVE_LIMIT,
    DI_POSITIVE_LIMIT,
    MODE_CSP,
    MODE_CSV,
    SW_FAULT,
    State,
)
from motionvm.motion import axis_status as st
from motionvm.motion.axis_fast import fast_step

PG, PVT, RAMP, TORQUE, EXT = 0, 1, 2, 3, 4
"""Reference sources: profile generator, PVT, kill ramp, torque mode, an external
provider (gear slave, gantry, homing) set with `Axis.follow`."""

CW_DISABLE, CW_SHUTDOWN, CW_ENABLE, CW_FAULT_RESET = 0x00, 0x06, 0x0F, 0x80


class AxisCycle:
    """The cyclic part of `Axis` (a mixin: the attributes are set up by `Axis.__init__`)."""

    fast_path = True
    """Use `axis_fast.fast_step` where it applies (False: always the general path)."""

    # ---- 1. reference ---------------------------------------------------------------

    def _reference(self) -> tuple[float, float, float]:
        src = self._source
        if src == PG:
            pg = self.pg
            if self._queue and pg.is_done:
                self._start_next()
                pg = self.pg
            if self._source == PG:
                return pg.step()
            src = self._source
        if src == PVT:
            self._n += 1
            p, v, a = self._pvt.evaluate(self._n * self.dt)
            if self._n * self.dt >= self._pvt.duration:
                self._source = PG
                self.pg.reset(p)
                return p, 0.0, (0.0 - self.ref_vel) / self.dt
            return p, v, a
        if src == RAMP:
            v_0 = self._ramp_v
            dv = self._ramp_d * self.dt
            v_1 = 0.0 if abs(v_0) <= dv else v_0 - math.copysign(dv, v_0)
            p = self.ref_pos + 0.5 * (v_0 + v_1) * self.dt
            self._ramp_v = v_1
            if v_1 == 0.0:
                self._source = PG
                self.pg.reset(p)
            return p, v_1, (v_1 - v_0) / self.dt
        if src == EXT:
            return self._ext.reference(self)
        return self.pos_fb, self.vel_fb, 0.0  # torque mode: the reference follows

    # ---- the cycle ------------------------------------------------------------------

    def step(self) -> None:
        """Run this axis's part of one controller cycle."""
        if self._rest:
            if self._wake_key() == self._rest_key:
                return
            self._rest = False
            self._still = 0
        if self.fast_path and fast_step(self):
            return
        self._fast_ok = None
        d = self.drive
        self._cycle += 1
        if self.enabled:
            p, v, a = self._reference()
            self.ref_pos, self.ref_vel, self.ref_acc = p, v, a
            if not (self.ignore_swl or self.rollover or self.error_stop) and self._source != TORQUE:
                if p >= self.sw_right and v > 0.0:
                    self._limit_stop(st.SWRL, st.FS_SW_RIGHT)
                elif p <= self.sw_left and v < 0.0:
                    self._limit_stop(st.SWLL, st.FS_SW_LEFT)
            mode = self.op_mode
            if mode == MODE_CSP:
                c = round((p + self.pos_offset) * self.cpu)
                d.target_position = ((c + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            elif mode == MODE_CSV:
                d.target_velocity = round(v * self.cpu)
            else:
                d.target_torque = self._torque_pm
            cw = CW_ENABLE
        else:
            cw = self._disabled_controlword()
        if self._clearing is not None:
            cw |= self._fault_reset_bit()
        d.controlword = cw
        d.step(self.dt)
        self._feedback()
        if self._idle_candidate():
            self._watch_rest()
        else:
            self._still = 0

    @property
    def vel_fb(self) -> float:
        """Velocity feedback [mm/s]: the drive's actual velocity in axis units (the fast
        cycle, axis_fast.py, leaves None: it is then computed when read)."""
        v = self._vel_fb
        return self.drive.velocity_actual / self.cpu if v is None else v

    @vel_fb.setter
    def vel_fb(self, value: float) -> None:
        self._vel_fb = value

    def _disabled_controlword(self) -> int:
        d = self.drive
        pa = d.position_actual
        d.target_position = pa  # an enabled drive then starts where it stands
        if not self._enabling:
            self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
            return CW_DISABLE
        self._enable_cycles += 1
        if self._enable_cycles > self._enable_timeout:
            self._enabling = False
            self.last_error = st.axis_error(st.DRIVE_ENABLE_TOUT, self.axis_id)
            return CW_DISABLE
        return (
            CW_SHUTDOWN
            if d.state in (State.SWITCH_ON_DISABLED, State.NOT_READY_TO_SWITCH_ON)
            else CW_ENABLE
        )

    def _fault_reset_bit(self) -> int:
        """Controlword bit 7 while a drive fault is reset: a rising edge every other cycle."""
        self._clearing += 1
        if self._clearing > self._enable_timeout:
            self._clearing = None
            self.last_error = st.axis_error(st.DRIVE_CLEAR_ERROR_TOUT, self.axis_id)
            return 0
        return CW_FAULT_RESET if self._clearing % 2 else 0

    # ---- 5. feedback and faults -----------------------------------------------------

    def _feedback(self) -> None:
        d = self.drive
        pa = d.position_actual
        delta = pa - self._pa
        if delta:
            self._fb_counts += ((delta + 0x80000000) & 0xFFFFFFFF) - 0x80000000
            self._pa = pa
            self.pos_fb_raw = self._fb_counts / self.cpu
            self.pos_fb = self.pos_fb_raw - self.pos_offset
        self._vel_fb = d.velocity_actual / self.cpu
        state = d.state
        if d.statusword & SW_FAULT:
            self.fault_status |= st.FS_DRIVE_FAULT
            if not self.error_stop:
                self._fault_disable(st.DRIVE_FAULT, 0)
        else:
            if self.fault_status & st.FS_DRIVE_FAULT:
                self.fault_status &= ~st.FS_DRIVE_FAULT
                if self._clearing is not None:
                    self._clearing = None
                    self._clear_errors()
            if self.enabled and state is not State.OPERATION_ENABLED:
                self._fault_disable(st.DRIVE_ABNORMAL_DISABLE, 0)
        if self._enabling and state is State.OPERATION_ENABLED:
            self._enabling = False
            self.enabled = True
            self._source = PG
            self.pg.reset(self.pos_fb)
            self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
            self._in_pos_count = 0
        di = d.digital_inputs
        if di != self._di:
            self._hw_inputs(di)
        if self.enabled:
            self._enabled_checks()
        self._update_status()

    def _hw_inputs(self, di: int) -> None:
        """New digital inputs: the hardware limit bits of fault_status follow the switches.

        IgnoreHWL only suppresses the limit's fault reaction (`_enabled_checks`); the bits
        and IsHWLL/IsHWRL still show the switches (0x60FD), as the manual's homing examples
        rely on when they search a limit switch with IgnoreHWL set."""
        self._di = di
        fs = self.fault_status & ~(st.FS_HW_RIGHT | st.FS_HW_LEFT)
        if di & DI_POSITIVE_LIMIT:
            fs |= st.FS_HW_RIGHT
        if di & DI_NEGATIVE_LIMIT:
            fs |= st.FS_HW_LEFT
        self.fault_status = fs

    def _enabled_checks(self) -> None:
        """Hardware limit in the direction of motion: kill stop; position error: disable."""
        fs = self.fault_status
        if fs & (st.FS_HW_RIGHT | st.FS_HW_LEFT) and not self.error_stop and not self.ignore_hwl:
            v = self.ref_vel
            if fs & st.FS_HW_RIGHT and v > 0.0:
                self._limit_stop(st.HWRL, st.FS_HW_RIGHT)
            elif fs & st.FS_HW_LEFT and v < 0.0:
                self._limit_stop(st.HWLL, st.FS_HW_LEFT)
        err = self.ref_pos - self.pos_fb
        if (err > self.max_pos_err or -err > self.max_pos_err) and not self.ignore_pe:
            self._fault_disable(st.PERR, st.FS_POSITION_ERROR)

    def _update_status(self) -> None:
        if not self.enabled:
            self.moving = self.in_pos = False
            self._in_pos_count = 0
            return
        src = self._source
        if src == PG:
            # region I lasts while the generator outputs new positions: until the
            # first cycle that repeats the last one (the velocity is then 0)
            moving = (not self.pg.is_done or self.ref_vel != 0.0 or bool(self._queue)
                      or self._deferred is not None)  # fmt: skip
        elif src == TORQUE:
            moving = self._torque_pm != 0
        elif src == EXT:  # a provider may say when its reference rests (gear, gantry)
            moving = self._ext.moving(self) if hasattr(self._ext, "moving") else True
        else:
            moving = True
        if moving:
            self.moving = True
            self.in_pos = False
            self._in_pos_count = 0
            return
        if self.moving:  # region I ends
            self.moving = False
            self.stopping = False
            self._end_cycle = end = max(self._cycle - 1, self._cmd_cycle)
            self.move_time_ms = (end - self._cmd_cycle) * self.dt * 1000.0
        err = self.ref_pos - self.pos_fb
        if -self.inpos_radius <= err <= self.inpos_radius:
            self._in_pos_count += 1
            if not self.in_pos and self._in_pos_count > self._debounce_cycles:
                self.in_pos = True
                if self._end_cycle >= 0:
                    self.settling_time_ms = (self._cycle - self._end_cycle) * self.dt * 1000.0
                    self._end_cycle = -1
        else:
            self._in_pos_count = 0
            self.in_pos = False

    # ---- fault reactions (table 5.1.1.4) --------------------------------------------

    def _limit_stop(self, code: int, bit: int) -> None:
        """Hardware or software limit: stop at the kill deceleration, error stop until Reset."""
        self.fault_status |= bit | st.FS_ERROR_STOP
        self.error_stop = True
        self.last_error = st.axis_error(code, self.axis_id)
        self._queue.clear()
        self.stopping = True
        if self._source == PG:
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

    def _start_ramp(self, v_0: float, decel: float) -> None:
        """Brake the reference from velocity v_0 to rest at `decel` (PVT and torque stops)."""
        if self.op_mode not in (MODE_CSP, MODE_CSV):
            self.op_mode = self.drive.mode = MODE_CSP
            self._torque_pm = 0
        self._source = RAMP
        self._ramp_v = v_0
        self._ramp_d = decel

    # ---- resting --------------------------------------------------------------------

    def _idle_candidate(self) -> bool:
        if self.moving or self._enabling or self._clearing is not None:
            return False
        if self.enabled:
            return self.in_pos and self._source == PG and not self._queue
        return True

    def _snapshot(self) -> tuple:
        d = self.drive
        m = d.mechanics
        return (d.statusword, d.position_actual, d.velocity_actual, d.torque_actual,
                d.digital_inputs, m.position, m.velocity, d.state, d._settled is d.state,
                self.fault_status, self.ref_pos, self.pos_fb)  # fmt: skip

    def _wake_key(self) -> tuple:
        d = self.drive
        # the drive has no public "quiescent" query: its fault latch is read directly
        return (d.controlword, d.mode, d.target_position, d.target_velocity, d.target_torque,
                d.tp_function, d.sensors.external, d._fault, self._wake_count)  # fmt: skip

    def _watch_rest(self) -> None:
        snap = self._snapshot()
        if snap == self._last_snap and snap[8]:
            self._still += 1
            if self._still >= self._rest_after:
                self._rest = True
                self._rest_key = self._wake_key()
        else:
            self._still = 0
            self._last_snap = snap

    @property
    def resting(self) -> bool:
        """True while the axis is a fixed point and skips its cycles."""
        return self._rest

    def wake(self) -> None:
        """Leave rest (every command calls this)."""
        self._wake_count += 1
        self._fast_ok = None
        self._rest = False
        self._still = 0

    @property
    def home_switch(self) -> bool:
        """The home switch input (0x60FD bit 2)."""
        return bool(self.drive.digital_inputs & DI_HOME_SWITCH)
