"""An axis (HIMC manual chapter 5): profile generator + CiA 402 drive + unit conversion.

Positions are in axis units [mm or deg]; the drive works in encoder counts
(`counts_per_unit`). Two coordinate systems differ by the position offset of SetPos:
the slave's (raw feedback, offset output) and the axis's (reference, pos_out, pos_fb):
    slave = axis + pos_offset (+ the compensation while it is active, axis_filters.py).
Commands are methods that raise `AxisCommandError(code, message)` when the manual's
rules refuse them; `code` is the low half of the axis error (table 18.1.2.1). An
accepted move makes `moving` true and `in_pos` false at once, in the calling cycle.
Decisions where the manual is silent are documented at each method.

A move is a value (`MoveAbsolute`, `MoveRelative`, `MoveVelocity`, `MovePvt`): the
command queue of buffer mode 1 and a move deferred by a zero velocity scale hold them,
and `_start` starts one. The parts of an axis: its profile generator `pg`, its `drive`
(with mechanics and sensors), the feedback counts unwrapped from the drive's int32
position actual, the reference source (profile, PVT, ramp, torque or a provider), the
command queue, and the status (moving, in position, resting).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from motionvm.drives.objects import MODE_CSP, MODE_CST
from motionvm.motion import axis_status as st
from motionvm.motion.axis_config import AxisConfig, build_drive
from motionvm.motion.axis_cycle import PG, PVT, TORQUE, AxisCycle
from motionvm.motion.axis_filters import AxisFilters
from motionvm.motion.axis_follow import AxisFollow
from motionvm.motion.axis_settings import AxisSettings
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.profile import ProfileGenerator
from motionvm.motion.pvt import PvtError, PvtTrajectory

QUEUE_SIZE = 32
"""Commands an axis buffers in buffer mode 1 (eERR_AXIS_CMD_QUEUE_FULL beyond)."""


# ---- moves, as the queue and a deferred start hold them ---------------------------------


@dataclass(frozen=True, slots=True)
class MoveAbsolute:
    """Move to `target` [mm] and stop there."""

    target: float


@dataclass(frozen=True, slots=True)
class MoveRelative:
    """Move by `distance` [mm] from the reference where the move starts (buffered)."""

    distance: float


@dataclass(frozen=True, slots=True)
class MoveVelocity:
    """Jog at `velocity` [mm/s]; the sign is the direction."""

    velocity: float


@dataclass(frozen=True, slots=True)
class MovePvt:
    """Follow `trajectory` (times [s] from the start of the move)."""

    trajectory: PvtTrajectory


Move = MoveAbsolute | MoveRelative | MoveVelocity | MovePvt


class Axis(AxisSettings, AxisCycle, AxisFollow):
    """One axis of the controller, stepped once per cycle by the motion kernel."""

    __slots__ = (  # with AxisCycle's (axis_cycle.py): nothing can be bolted on
        "buffer_mode", "config", "controlled_by", "extra_status", "filters", "move_vel_limit",
        "rotary", "vel_scale", "__weakref__",
    )  # fmt: skip

    def __init__(self, axis_id: int, config: AxisConfig, dt: float, drive=None):
        self.axis_id = axis_id
        self.config = config
        self.dt = dt
        self.drive = drive if drive is not None else build_drive(config)
        self.cpu = config.counts_per_unit
        """Encoder counts per axis unit [counts/mm or counts/deg]."""
        self.rotary = config.rotary
        self.kill_dec = config.kill_dec
        self._sw_left, self._sw_right = config.sw_left, config.sw_right
        self._ignore_swl = self._error_stop = False
        self._rollover = 0.0
        self._software_limits_changed()
        self.max_pos_err = config.max_pos_err
        self.inpos_radius = config.inpos_radius
        self._in_pos_debounce_cycles = round(config.inpos_debounce_ms / 1000.0 / dt)
        self._enable_timeout_cycles = math.ceil(config.enable_timeout_ms / 1000.0 / dt)
        self.pg = ProfileGenerator(dt, config.max_vel, config.max_acc, config.max_dec,
                                   config.smooth_time_ms / 1000.0, config.start_position)  # fmt: skip
        self.ignore_hwl = self.ignore_swl = self.ignore_pe = False
        self.vel_scale = 100.0
        self.rollover = 0.0
        self.op_mode = self.drive.mode = MODE_CSP
        self.buffer_mode = 0
        self.enabled = self._enabling = False
        self.error_stop = self.stopping = self.halted = False
        self.moving = self.in_pos = False
        self.fault_status = self.last_error = 0
        self.extra_status = 0
        self.move_vel_limit = math.inf
        """A move must stay below this velocity [mm/s or deg/s], else it is refused with
        eERR_AXIS_CMD_INVALID_VEL: a device that needs it sets it (an armed position
        trigger, manual 12.1.1); inf: no limit."""
        self.controlled_by: str | None = None
        """Who commands the axis instead of the controller's tasks (a PDL drive), or None."""
        """Bits that gear, group, gantry and homing set (3-9, 11, 12 of table 5.1.1.5)."""
        self._pos_offset = self._slave_offset = 0.0
        self.comp_pos = 0.0
        """[mm] The compensation sent to the drive this cycle (GetCompPos)."""
        self._comp_dependents: tuple[Axis, ...] = ()  # compensated axes that read this one
        self.filters = AxisFilters(self)
        """VSF, InShape and compensation (motion/axis_filters.py)."""
        self._cmd_path: AxisFilters | None = None  # `filters` while any of them is on
        self.move_time_ms = self.settling_time_ms = 0.0
        # the reference: its source (axis_cycle.PG ...) and what each source needs
        self._reference_source = PG
        self._provider = None  # the provider while following (axis_follow.py)
        self._command_queue: deque[Move] = deque()
        self._deferred_move: Move | None = None  # waits for a velocity scale above 0
        self._pvt_trajectory: PvtTrajectory | None = None
        self._pvt_cycle = 0  # cycles since the PVT move started
        self._ramp_vel = self._ramp_decel = 0.0  # [mm/s], [mm/s^2]
        self._torque_per_mille = 0  # torque command [per mille of the rated torque]
        # power: enable sequence and fault reset, counted in cycles
        self._fault_reset_cycles: int | None = None  # while a drive fault is reset
        self._enable_cycles = 0
        # status: the cycle count and the cycles a move started and ended
        self._in_pos_cycles = 0
        self._cycle = 0
        self._move_start_cycle = 0
        self._move_end_cycle = -1
        # feedback: the drive's int32 position_actual unwrapped into feedback counts
        self._position_actual = self.drive.position_actual
        self._feedback_counts = self._position_actual
        self._digital_inputs = -1  # the 0x60FD value last seen (-1: none yet)
        self._on_hw_limit = False  # a hardware limit bit is on in fault_status
        self.pos_fb_raw = self.pos_fb = self._feedback_counts / self.cpu
        self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
        # resting (axis_cycle.py)
        self.resting = False
        """True while the axis is a fixed point and skips its cycles (read only)."""
        self._last_snapshot: tuple = ()
        self._still_cycles = 0
        self._rest_after_cycles = getattr(self.drive.mechanics, "delay_cycles", 0) + 3

    # ---- checks ---------------------------------------------------------------------

    def _require_motion_ok(self, *, torque: bool = False) -> None:
        self.wake()
        # the slot behind `error_stop`: every move command passes here
        if self._error_stop:
            raise AxisCommandError(
                st.CMD_INVALID_ERROR_STATE, f"axis {self.axis_id} is in error stop (call Reset)"
            )
        if not self.enabled:
            raise AxisCommandError(st.CMD_INVALID_DISABLED, f"axis {self.axis_id} is not enabled")
        if self.stopping:
            raise AxisCommandError(st.CMD_INVALID_STOPPING, f"axis {self.axis_id} is stopping")
        ext = self.following
        if ext is not None and not getattr(ext, "accepts_moves", False):
            code = getattr(ext, "refusal_code", st.CMD_INVALID_IN_SYNC)
            raise AxisCommandError(code, f"axis {self.axis_id} follows {ext}")
        if (self.op_mode == MODE_CST) != torque:
            raise AxisCommandError(
                st.CMD_INVALID_CONTROL_MODE,
                f"axis {self.axis_id}: not valid in op mode {self.op_mode}",
            )

    def _require_still(self) -> None:
        self.wake()
        if self.moving:
            raise AxisCommandError(st.CMD_INVALID_MOVING, f"axis {self.axis_id} is moving")

    def _accepted(self) -> None:
        """A move was accepted: region I starts in this very cycle (figure 5.1.4)."""
        if not self.moving:
            self._move_start_cycle = self._cycle
        self.moving = True
        self.in_pos = False
        self._in_pos_cycles = 0
        self._move_end_cycle = -1

    def _buffered(self, move: Move) -> bool:
        """Queue `move` if buffer mode 1 and the axis moves; True if queued."""
        if self.buffer_mode == 1 and self.moving:
            if len(self._command_queue) >= QUEUE_SIZE:
                raise AxisCommandError(
                    st.CMD_QUEUE_FULL, f"axis {self.axis_id}: command queue full ({QUEUE_SIZE})"
                )
            self._command_queue.append(move)
            return True
        return False

    def _drop_motion(self) -> None:
        if self._cmd_path is not None:
            self._cmd_path.dropped()
        self._command_queue.clear()
        self._reference_source = PG
        self.pg.reset(self.pos_fb)
        self.ref_pos, self.ref_vel, self.ref_acc = self.pos_fb, 0.0, 0.0
        self._torque_per_mille = 0
        self.drive.target_torque = 0
        self._deferred_move = None
        if self.halted:
            self.halted = False
            self.pg.set_velocity_scale(self.vel_scale / 100.0)
        self.stopping = False
        self.moving = self.in_pos = False

    # ---- power (5.2.1-5.2.3) --------------------------------------------------------

    def enable(self) -> None:
        """Start the drive's enable sequence; `enabled` turns true when it is done."""
        self.wake()
        if self.error_stop:
            raise AxisCommandError(
                st.CMD_INVALID_ERROR_STATE, f"axis {self.axis_id} is in error stop (call Reset)"
            )
        if self.enabled or self._enabling:
            return
        self._enabling = True
        self._enable_cycles = 0

    def disable(self) -> None:
        """Power off at once; clears the path planning (5.2.2)."""
        self.wake()
        self._drop_motion()
        self.enabled = self._enabling = False

    def reset(self) -> None:
        """Leave error stop: clear the fault bits (5.2.3).

        A drive fault is reset first: the controlword's fault reset bit is pulsed until
        the drive leaves Fault (after its fault reaction); the axis stays in error stop
        until then, or fails with eERR_AXIS_DRIVE_CLEAR_ERROR_TOUT after the enable
        timeout (e.g. a lost encoder).
        """
        self.wake()
        if self.fault_status & st.FS_DRIVE_FAULT:
            if self._fault_reset_cycles is None:
                self._fault_reset_cycles = 0
            return
        self._clear_errors()

    def _clear_errors(self) -> None:
        self.error_stop = False
        self.fault_status &= ~(
            st.FS_ERROR_STOP | st.FS_POSITION_ERROR | st.FS_SW_LEFT | st.FS_SW_RIGHT
        )

    # ---- moves (5.2.4-5.2.11) -------------------------------------------------------

    def _wrap_target(self, pos: float) -> float:
        """With rollover, the target in the current turn reached the shortest way."""
        r = self.rollover
        base = self.pg.target if self.moving else self.ref_pos
        d = (pos % r) - (base % r)
        d = (d + 0.5 * r) % r - 0.5 * r
        return base + d

    def _check_target(self, pos: float) -> float:
        if not math.isfinite(pos):
            raise AxisCommandError(
                st.CMD_INVALID_POS, f"axis {self.axis_id}: target {pos!r} is not a number"
            )
        if self._rollover:  # (the slots behind the settings: no property calls)
            return self._wrap_target(pos)
        if not self._ignore_swl and not self._sw_left <= pos <= self._sw_right:
            raise AxisCommandError(
                st.CMD_INVALID_POS,
                f"axis {self.axis_id}: target {pos:g} is outside the "
                f"software limits {self.sw_left:g} .. {self.sw_right:g}",
            )
        return pos

    def _rel_target(self, base: float, dist: float) -> float:
        """The end of a move by `dist` from `base`: with rollover the full distance,
        however many turns (5.2.5, 5.3.40), not the shortest way to its angle."""
        if self.rollover:
            return base + dist
        return self._check_target(base + dist)

    def move_abs(self, pos: float) -> None:
        """Move to `pos` [mm]; while moving in buffer mode 0 the target changes on the fly."""
        self._require_motion_ok()
        target = self._check_target(pos)
        move = MoveAbsolute(target)
        if not self._buffered(move):
            self._start(move)

    def move_rel(self, dist: float) -> None:
        """Move `dist` [mm] from the current reference (buffered: from the previous end)."""
        self._require_motion_ok()
        if not math.isfinite(dist):
            raise AxisCommandError(
                st.CMD_INVALID_POS, f"axis {self.axis_id}: distance {dist!r} is not a number"
            )
        if self.buffer_mode == 1 and self.moving:
            self._buffered(MoveRelative(dist))
            return
        base = self.ref_pos if self.following is None else self.pg.output[0]
        if self._cmd_path is not None and self._cmd_path.pending:
            base = self._cmd_path.unfiltered_pos  # where the plan is, not the filter
        self._start(MoveAbsolute(self._rel_target(base, dist)))

    def move_vel(self, vel: float) -> None:
        """Jog at `vel` [mm/s] (sign = direction), capped at the maximum velocity."""
        self._require_motion_ok()
        if not math.isfinite(vel):
            raise AxisCommandError(
                st.CMD_INVALID_VEL, f"axis {self.axis_id}: velocity {vel!r} is not a number"
            )
        move = MoveVelocity(vel)
        if not self._buffered(move):
            self._start(move)

    def move_pvt(self, times_ms: list[float], pos: list[float], vel: list[float]) -> None:
        """PVT motion through up to 50 points; times [ms] from now, positions absolute.

        A first point at time 0 must be where the axis is; otherwise the current
        reference (at rest) is the implicit first point.
        """
        self._require_motion_ok()
        if not 1 <= len(times_ms) <= 50:
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"{len(times_ms)} PVT points: must be 1 to 50"
            )
        t = [x / 1000.0 for x in times_ms]
        p, v = list(pos), list(vel)
        if t[0] == 0.0:
            if abs(p[0] - self.ref_pos) > self.inpos_radius:
                raise AxisCommandError(
                    st.CMD_INVALID_POS,
                    f"axis {self.axis_id}: the first PVT point {p[0]:g} "
                    f"is not the axis position {self.ref_pos:g}",
                )
            p[0] = self.ref_pos
        else:
            t, p, v = [0.0] + t, [self.ref_pos] + p, [0.0] + v
        try:
            traj = PvtTrajectory(t, p, v)
        except PvtError as exc:
            raise AxisCommandError(st.PVT_INVALID_TIME, f"axis {self.axis_id}: {exc}") from None
        v_peak, a_peak = traj.peaks()
        if v_peak > self.config.vel_limit:
            raise AxisCommandError(
                st.PVT_VEL_LIMIT,
                f"axis {self.axis_id}: PVT velocity {v_peak:g} exceeds "
                f"the limit {self.config.vel_limit:g}",
            )
        if a_peak > self.config.acc_limit:
            raise AxisCommandError(
                st.PVT_ACC_LIMIT,
                f"axis {self.axis_id}: PVT acceleration {a_peak:g} "
                f"exceeds the limit {self.config.acc_limit:g}",
            )
        move = MovePvt(traj)
        if not self._buffered(move):
            self._start(move)

    def move_trq(self, torque: float) -> None:
        """Torque command [N*m] in op mode 10, clamped to the continuous (rated) torque."""
        self._require_motion_ok(torque=True)
        if not math.isfinite(torque):
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"axis {self.axis_id}: torque {torque!r}"
            )
        rated = self.drive.rated_torque_nm
        torque = max(-rated, min(rated, torque))
        self._torque_per_mille = round(torque / rated * 1000.0)
        self._reference_source = TORQUE
        if self._torque_per_mille:
            self._accepted()

    def _start(self, move: Move) -> None:
        """Start `move` now. A new move ends a Halt; at a velocity scale of 0 a move from
        rest waits (moving) until the scale is raised, as the generator would drop it."""
        if self.move_vel_limit != math.inf:
            self._check_move_velocity(move)
        self._accepted()
        self._deferred_move = None
        if self.halted:
            self.halted = False
            self.pg.set_velocity_scale(self.vel_scale / 100.0)
        is_pvt = type(move) is MovePvt
        if not is_pvt and self.pg.velocity_scale == 0.0 and self.pg.is_done:
            self._deferred_move = move
            return
        if is_pvt:
            self._reference_source = PVT
            self._pvt_trajectory = move.trajectory
            self._pvt_cycle = 0
            return
        if self.following is None:  # a gantry axis stays on its pair reference
            self._reference_source = PG
        if type(move) is MoveAbsolute:
            self.pg.move_to(move.target)
        elif type(move) is MoveRelative:
            self.pg.move_to(self._rel_target(self.ref_pos, move.distance))
        else:
            self.pg.move_velocity(move.velocity)

    def _check_move_velocity(self, move: Move) -> None:
        if type(move) is MovePvt:
            v = move.trajectory.peaks()[0]
        else:
            v = self.pg.v_max * self.vel_scale / 100.0
            if type(move) is MoveVelocity:
                v = min(v, abs(move.velocity) * self.vel_scale / 100.0)
        if v >= self.move_vel_limit:
            raise AxisCommandError(
                st.CMD_INVALID_VEL,
                f"axis {self.axis_id}: velocity {v:g} is not below {self.move_vel_limit:g} "
                "(position trigger interval x sampling frequency)",
            )

    def _start_next(self) -> None:
        while self._command_queue:
            move = self._command_queue.popleft()
            try:
                self._start(move)
                return
            except AxisCommandError as exc:  # e.g. a relative target beyond a limit
                self.last_error = st.axis_error(exc.code, self.axis_id)

    def stop(self, decel: float | None = None) -> None:
        """Stop at the maximum deceleration (or `decel`); clears the path planning."""
        self.wake()
        self._command_queue.clear()
        self._deferred_move = None
        if not self.enabled or not self.moving:
            return
        decel = self.pg.d_max if decel is None else decel
        self.stopping = True
        self.halted = False
        if self._reference_source == PG or getattr(self.following, "accepts_moves", False):
            self.pg.set_velocity_scale(self.vel_scale / 100.0)
            self.pg.stop(decel)
        elif self._reference_source == TORQUE:
            self._torque_per_mille = 0
            self._start_ramp(self.vel_fb, decel)
        else:
            self._start_ramp(self.ref_vel, decel)

    def halt(self) -> None:
        """Pause: the velocity goes to 0 and the move waits for Resume (still `moving`)."""
        self._require_motion_ok()
        if self._reference_source != PG:
            raise AxisCommandError(
                st.CMD_INVALID_STATE, f"axis {self.axis_id}: Halt works on profile moves only"
            )
        self.halted = True
        self.pg.set_velocity_scale(0.0)

    def resume(self) -> None:
        """Continue a halted move."""
        self._require_motion_ok()
        if not self.halted:
            raise AxisCommandError(st.CMD_INVALID_STATE, f"axis {self.axis_id} is not halted")
        self.halted = False
        self.pg.set_velocity_scale(self.vel_scale / 100.0)
