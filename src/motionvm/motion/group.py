"""Axis groups (HIMC manual chapter 8): membership, settings, state machine, the cycle.

An `AxisGroup` holds up to `MAX_AXES` axes in the order they were added ({X, Y, Z, A,
B, C}, Cartesian kinematics 8.1.3: joint i is pose coordinate i). While the group is
enabled its axes follow it (`Axis.follow`: the group is their reference provider) and
refuse single-axis moves with eERR_AXIS_CMD_INVALID_GROUPED; the motion kernel steps
every group between the bus and the axes, so an axis reads its group's command of the
same cycle. The path (queue, look-ahead, profile, smoothing) is the group's
`PathPlanner` (motion/group_plan.py); the segments come from motion/group_motion.py.

States (PLCopen part 4): DISABLED -> (EnableGroup) STANDBY <-> MOVING; StopGroup:
STOPPING until at rest, then STANDBY; an axis that leaves the group's reference (a drive
fault, a disable, a limit stop) puts the group in ERROR_STOP: the path brakes at the
deceleration, the group refuses motion until ResetGroup (which needs every axis enabled
and out of error stop). Group status bits are tables 8.1.1.4 (fault) and 8.1.1.5 (motion).

Decisions where the manual is silent:
- membership changes (AddAxisToGrp, RemoveAxisFromGrp) need a disabled group
  (eERR_CRD_CMD_INVALID_STATE); an axis belongs to one group at most
  (eERR_CRD_CMD_AXIS_DUPLICATED) and no gantry pair or gear
  (eERR_CRD_CMD_GRP_AXIS_INVALID); SetupGroup is UngrpAllAxes, AddAxisToGrp for each
  axis, EnableGroup;
- an axis of an enabled group (error stop included) is synchronous (table 5.1.1.5
  bit 3, IsSync): it follows the group's commands; in a disabled group it is grouped
  (bit 4) only. SetPos refuses an axis added to a group, enabled or not (5.3.19);
- DisableAll and EStop disable every group at once (2.7, 2.9), a moving one too: its
  path is dropped as its axes are disabled; it keeps its axes and is not in error stop;
- EnableGroup needs every axis enabled and at rest (eERR_CRD_CMD_GRP_AXIS_INVALID),
  at most 6 axes for Cartesian kinematics (eERR_CRD_CMD_INVALID_KIN_SETTING);
  DisableGroup and UngrpAllAxes of a moving group are refused
  (eERR_CRD_CMD_INVALID_MOVING): stop it first;
- the group never asks an axis for more than its own limits: a segment's feed is capped
  at each axis's maximum velocity and its acceleration at half each axis's maximum
  acceleration, per unit of path; arcs and corners passed at speed keep their
  centripetal and corner accelerations within the other half (motion/group_motion.py).
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.group_coords import CS_MCS, CoordSystems
from motionvm.motion.group_plan import BM_BUFF, PathPlanner

MAX_AXES = 9
CARTESIAN = 1
DISABLED, STANDBY, MOVING, STOPPING, ERROR_STOP = (
    "disabled", "standby", "moving", "stopping", "error_stop")  # fmt: skip

# group fault_status (table 8.1.1.4) and motion_status (table 8.1.1.5) bits
GFS_ERROR_STOP, GFS_AXIS_FAULT, GFS_SW_LIMIT = 1, 2, 4
GMS_ENABLED, GMS_MOVING, GMS_IN_POSITION, GMS_INPUT_SHAPE = 1, 2, 4, 8

# group error codes, low 16 bits (table 18.1.3.1)
CRD_UNKNOWN = 0x000A
CRD_INVALID_KIN_SETTING = 0x001E
CRD_AXIS_DUPLICATED = 0x0028
CRD_GRP_SIZE_EMPTY = 0x0032
CRD_GRP_SIZE_FULL = 0x003C
CRD_INVALID_MOVING = 0x0046
CRD_INVALID_DISABLED = 0x0050
CRD_INVALID_STATE = 0x006E
CRD_QUEUE_FULL = 0x0078
CRD_GRP_AXIS_INVALID = 0x0082
CRD_INVALID_QUEUE_SIZE = 0x0096
CRD_INVALID_POS = 0x00D2
CRD_INVALID_LIN_VEL = 0x00DC
CRD_INVALID_LIN_ACC = 0x00E6
CRD_INVALID_LIN_DEC = 0x00F0
CRD_INVALID_LIN_SM_TIME = 0x0104
CRD_INVALID_ANG_VEL = 0x0140
CRD_INVALID_ANG_ACC = 0x014A
CRD_INVALID_ANG_DEC = 0x0154
CRD_INVALID_ANG_SM_TIME = 0x0168
CRD_INVALID_VEL_SCALE = 0x0190
CRD_INVALID_TRANS_VEL = 0x019A
CRD_INVALID_TRANS_DIS = 0x01A4
CRD_INVALID_TRANS_DEV = 0x01A5
CRD_INVALID_TRANS_CURVE = 0x01A6
CRD_TRANS_MODE_UNKNOWN = 0x01B8
CRD_COORD_SYS_UNKNOWN = 0x01C2
CRD_BLEND_MODE_UNKNOWN = 0x01CC
CRD_LIN_INVALID_PARAM = 0x01FE
CRD_CIRC_INVALID_PARAM = 0x0262
CRD_COORD_INVALID_PARAM = 0x02E4
CRD_LOOKAHEAD_INVALID_PARAM = 0x02F8
CRD_AXIS_ABNORMALLY_DISABLED = 0x03F2
CRD_AXIS_SWL = 0x03FC


class GroupError(Exception):
    """A refused group command; `code` is the low half of the group error 0x82XXCCCC."""

    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


class Profile:
    """Velocity [unit/s], acceleration, deceleration [unit/s^2] and smoothing time [ms]."""

    __slots__ = ("acc", "dec", "sm_ms", "vel")

    def __init__(self, vel: float, acc: float, dec: float, sm_ms: float):
        self.vel, self.acc, self.dec, self.sm_ms = vel, acc, dec, sm_ms

    def values(self) -> tuple[float, float, float, float]:
        return self.vel, self.acc, self.dec, self.sm_ms


class GroupLink:
    """The reference provider the axes of an enabled group follow (`Axis.follow`)."""

    accepts_moves = False
    refusal_code = st.CMD_INVALID_GROUPED
    """What a grouped axis answers a single-axis move with (eERR_AXIS_CMD_INVALID_GROUPED)."""

    __slots__ = ("group",)

    def __init__(self, group: AxisGroup) -> None:
        self.group = group

    def __repr__(self) -> str:
        return repr(self.group)

    def reference(self, axis) -> tuple[float, float, float]:
        g = self.group
        return g.joint_ref[g._index[axis.axis_id]]

    def moving(self, axis) -> bool:
        return self.group.planner.active

    def holds_still(self, axis) -> bool:
        """True while the group's reference stands still: its axes may rest (the group
        wakes them when its path moves again, `AxisGroup.step`)."""
        return not self.group.planner.active


class AxisGroup:
    """One axis group (see the module docstring)."""

    def __init__(self, group_id: int, dt: float, kernel) -> None:
        self.group_id = group_id
        self.dt = dt
        self.kernel = kernel
        self.axes: list = []
        self.kin = CARTESIAN
        self.state = DISABLED
        self.fault_status = 0
        self.lin = Profile(100.0, 500.0, 500.0, 50.0)
        """Translation profile (SetGrpMotionProfile defaults of 8.3.6)."""
        self.ang = Profile(360.0, 1800.0, 1800.0, 50.0)
        """Rotation profile (SetGrpAngMotionProfile defaults of 8.3.7)."""
        self.vel_scale = 100.0
        self.buffer_mode = BM_BUFF
        self.trans_mode = 0
        self.trans_prm = [0.0, 0.0, 0.0, 0.0]
        """trans_vel [mm/s], trans_dis [mm], trans_dev [mm], trans_curv [1/mm]."""
        self.lookahead = [5000.0, 100.0, 0.0]
        """Corner acceleration [mm/s^2], arc acceleration [mm/s^2], chord error [mm] (8.1.4)."""
        self.queue_size = 512
        self.coord_sys = CS_MCS
        self.coords = CoordSystems()
        self.planner = PathPlanner(dt, [])
        self.joint_ref: list[tuple[float, float, float]] = []
        self._index: dict[int, int] = {}
        self.last_end: list[float] = []
        """End pose [MCS] of the last queued segment: where a relative move starts from."""
        self.jogging = False
        self.link = GroupLink(self)
        self.group_set: GroupSet | None = None
        """The set that steps this group (it sets this); told when the group is enabled
        or disabled, so a cycle visits the enabled groups only."""

    def __repr__(self) -> str:
        return f"axis group {self.group_id}"

    # ---- errors ---------------------------------------------------------------------

    @property
    def last_error(self) -> int:
        return self.kernel.group_last_error[self.group_id]

    @last_error.setter
    def last_error(self, value: int) -> None:
        self.kernel.group_last_error[self.group_id] = value

    def fail(self, code: int, message: str) -> GroupError:
        return GroupError(code, f"group {self.group_id}: {message}")

    # ---- membership -----------------------------------------------------------------

    @property
    def n(self) -> int:
        return len(self.axes)

    @property
    def enabled(self) -> bool:
        return self.state != DISABLED

    def _require_disabled(self) -> None:
        if self.state != DISABLED:
            raise self.fail(CRD_INVALID_STATE, "is enabled (call DisableGroup first)")

    def add_axis(self, axis, owner) -> None:
        """AddAxisToGrp; `owner` is the group `axis` is in already, or None."""
        self._require_disabled()
        if owner is self:
            raise self.fail(CRD_AXIS_DUPLICATED, f"axis {axis.axis_id} is in the group already")
        if owner is not None:
            raise self.fail(CRD_AXIS_DUPLICATED, f"axis {axis.axis_id} is in {owner}")
        if len(self.axes) >= MAX_AXES:
            raise self.fail(CRD_GRP_SIZE_FULL, f"has {MAX_AXES} axes, the most a group takes")
        if axis.following is not None or axis.extra_status & (st.MS_GANTRY | st.MS_GEAR):
            raise self.fail(CRD_GRP_AXIS_INVALID,
                            f"axis {axis.axis_id} is a gantry or gear axis")  # fmt: skip
        self.axes.append(axis)
        axis.extra_status |= st.MS_GROUP
        axis.wake()

    def remove_last(self) -> None:
        """RemoveAxisFromGrp: the axis added last leaves."""
        self._require_disabled()
        if not self.axes:
            raise self.fail(CRD_GRP_SIZE_EMPTY, "is empty")
        a = self.axes.pop()
        a.extra_status &= ~st.MS_GROUP
        a.wake()

    def ungroup(self) -> None:
        """UngrpAllAxes: disable the group and let every axis go."""
        if self.state != DISABLED:
            self.disable()
        while self.axes:
            self.remove_last()

    # ---- power ----------------------------------------------------------------------

    def enable(self) -> None:
        if self.state != DISABLED:
            return
        if not self.axes:
            raise self.fail(CRD_GRP_SIZE_EMPTY, "is empty")
        if self.kin == CARTESIAN and len(self.axes) > 6:
            raise self.fail(CRD_INVALID_KIN_SETTING,
                            f"Cartesian kinematics maps 6 axes, the group has {len(self.axes)}")  # fmt: skip
        for a in self.axes:
            if not a.enabled or a.error_stop:
                raise self.fail(CRD_GRP_AXIS_INVALID, f"axis {a.axis_id} is not enabled")
            if a.moving:
                raise self.fail(CRD_INVALID_MOVING, f"axis {a.axis_id} is moving")
        self._attach()
        self.state = STANDBY
        self.fault_status = 0
        self._set_sync(True)
        if self.group_set is not None:
            self.group_set.power_changed()

    def _set_sync(self, on: bool) -> None:
        """The axes' synchronous bit (table 5.1.1.5 bit 3, IsSync): set from EnableGroup
        to the group's disable, error stop included (the group is still enabled)."""
        for a in self.axes:
            if on:
                a.extra_status |= st.MS_SYNC
            else:
                a.extra_status &= ~st.MS_SYNC

    def _attach(self) -> None:
        self._index = {a.axis_id: i for i, a in enumerate(self.axes)}
        pose = [a.ref_pos for a in self.axes]
        self.planner = self._new_planner(pose)
        self.last_end = list(pose)
        self.joint_ref = [(p, 0.0, 0.0) for p in pose]
        self.jogging = False
        for a in self.axes:
            a.wake()
            a.follow(self.link)

    def _new_planner(self, pose) -> PathPlanner:
        old = self.planner
        p = PathPlanner(self.dt, pose)
        p.command_filter = f = old.command_filter
        if f is not None:  # a group input shaper starts at rest where the axes are
            f.reset(pose)
        p.set_scale(self.vel_scale / 100.0)
        p.set_smoothing(self.lin.sm_ms / 1000.0)
        return p

    def disable(self) -> None:
        if self.state == DISABLED:
            return
        if self.moving:
            raise self.fail(CRD_INVALID_MOVING, "is moving (call StopGroup first)")
        self._detach()
        self.state = DISABLED
        self._set_sync(False)
        if self.group_set is not None:
            self.group_set.power_changed()

    def power_off(self) -> None:
        """DisableAll, EStop (2.7, 2.9): disabled at once whatever it does; its path is
        dropped, as its axes are disabled at once too. Its fault status stays."""
        if self.state == DISABLED:
            return
        self.jogging = False
        self._detach()
        self.state = DISABLED
        self._set_sync(False)
        if self.group_set is not None:
            self.group_set.power_changed()

    def _detach(self) -> None:
        for a in self.axes:
            a.wake()
            if a.following is self.link:
                a.release()

    def reset(self) -> None:
        """ResetGroup: ERROR_STOP -> STANDBY once every axis is enabled and error free."""
        if self.state != ERROR_STOP:
            return
        if self.planner.active:
            raise self.fail(CRD_INVALID_MOVING, "is still braking")
        for a in self.axes:
            if not a.enabled or a.error_stop:
                raise self.fail(CRD_INVALID_STATE,
                                f"axis {a.axis_id} is disabled or in error stop (reset it first)")  # fmt: skip
        self._detach()
        self._attach()
        self.state = STANDBY
        self.fault_status = 0

    # ---- status ---------------------------------------------------------------------

    @property
    def moving(self) -> bool:
        """IsGrpMoving: the path generator still outputs new positions."""
        return self.state != DISABLED and self.planner.active

    @property
    def in_pos(self) -> bool:
        """IsGrpInPos: enabled, not moving, every axis in position."""
        return (self.state in (STANDBY, ERROR_STOP) and not self.planner.active
                and all(a.in_pos for a in self.axes))  # fmt: skip

    @property
    def error_stop(self) -> bool:
        """IsGrpErrorStop: an axis left the group's reference; ResetGroup clears it."""
        return self.state == ERROR_STOP

    @property
    def motion_status(self) -> int:
        s = 0
        if self.state != DISABLED:
            s |= GMS_ENABLED
        if self.moving:
            s |= GMS_MOVING
        if self.state != DISABLED and self.in_pos:
            s |= GMS_IN_POSITION
        if self.planner.command_filter is not None:
            s |= GMS_INPUT_SHAPE
        return s

    def require_motion(self) -> None:
        """Motion commands need an enabled group, not stopping, not in error stop."""
        if self.state == DISABLED:
            raise self.fail(CRD_INVALID_DISABLED, "is not enabled (call EnableGroup)")
        if self.state == ERROR_STOP:
            raise self.fail(CRD_INVALID_STATE, "is in error stop (call ResetGroup)")
        if self.state == STOPPING:
            raise self.fail(CRD_INVALID_STATE, "is stopping")

    @property
    def cmd_num(self) -> int:
        """GetGrpCmdNum: the segments queued behind the one being run."""
        return max(0, len(self.planner.queue) - 1)

    # ---- stop, halt -----------------------------------------------------------------

    def stop(self) -> None:
        """StopGroup: brake along the path at the deceleration; the queue is cleared."""
        if self.state == DISABLED:
            raise self.fail(CRD_INVALID_DISABLED, "is not enabled")
        self.jogging = False
        if self.planner.active:
            self.planner.stop()
            if self.state != ERROR_STOP:
                self.state = STOPPING
        else:
            self.planner.queue.clear()
        self.last_end = None  # taken from where the path comes to rest

    def halt(self) -> None:
        self.require_motion()
        self.planner.halt()

    def resume(self) -> None:
        self.require_motion()
        if not self.planner.halted:
            raise self.fail(CRD_INVALID_STATE, "is not halted")
        self.planner.resume()

    def set_vel_scale(self, percent: float) -> None:
        self.vel_scale = percent
        self.planner.set_scale(percent / 100.0)

    # ---- the cycle ------------------------------------------------------------------

    def _check_axes(self) -> None:
        for a in self.axes:
            if a.following is not self.link:
                self._error(a)
                return

    def _error(self, axis) -> None:
        fs = GFS_ERROR_STOP
        if axis.fault_status & (st.FS_SW_LEFT | st.FS_SW_RIGHT):
            fs |= GFS_SW_LIMIT
            code = CRD_AXIS_SWL
        else:
            fs |= GFS_AXIS_FAULT
            code = CRD_AXIS_ABNORMALLY_DISABLED
        self.fault_status |= fs
        self.last_error = st.group_error(code, self.group_id)
        self.state = ERROR_STOP
        self.jogging = False
        if self.planner.active:
            self.planner.stop()
        self.last_end = None

    def step(self) -> None:
        """The group's part of a cycle, before its axes step."""
        if self.state == DISABLED:
            return
        if self.state != ERROR_STOP:
            self._check_axes()
        planner = self.planner
        if not planner.active:
            if self.state in (MOVING, STOPPING):
                self.state = STANDBY
            return
        for a in self.axes:  # (a resting axis steps again from this cycle on)
            if a.resting:
                a.wake()
        out = planner.step()
        vel, acc = planner.out_vel, planner.out_acc
        self.joint_ref = list(zip(out, vel, acc))
        if self.state == STANDBY:
            self.state = MOVING
        if not planner.active and self.state in (MOVING, STOPPING):
            self.state = STANDBY
        if self.last_end is None and planner.mode == "idle":
            self.last_end = list(planner.raw)

    # ---- poses ----------------------------------------------------------------------

    def pose_cmd(self) -> list[float]:
        """carte_pose_cmd [MCS]: the commanded pose of the last cycle."""
        return list(self.planner.out)

    def pose_fb(self) -> list[float]:
        """carte_pose_fb [MCS]: the axes' feedback through the kinematics."""
        return [a.pos_fb for a in self.axes]

    def end_pose(self) -> list[float]:
        """Where the next segment starts [MCS]: the end of the last queued one."""
        if self.last_end is None:
            return list(self.planner.raw)
        return list(self.last_end)


_ARRAYS = {
    "carte_pose_cmd": lambda g: g.planner.out,
    "carte_vel_cmd": lambda g: g.planner.out_vel,
    "carte_pose_fb": lambda g: g.pose_fb(),
    "joint_pos_cmd": lambda g: [a.ref_pos for a in g.axes],
    "joint_vel_cmd": lambda g: [a.ref_vel for a in g.axes],
    "joint_acc_cmd": lambda g: [a.ref_acc for a in g.axes],
    "joint_pos_fb": lambda g: [a.pos_fb for a in g.axes],
    "carte_pose_err": lambda g: [c - f for c, f in zip(g.planner.out, g.pose_fb())],
}
_SCALARS = {
    "grp_pg_pos": lambda g: g.planner.path_pos,
    "grp_pg_vel": lambda g: g.planner.v,
    "grp_pg_acc": lambda g: g.planner.acc,
    "grp_lin_vel": lambda g: g.lin.vel,
    "grp_lin_acc": lambda g: g.lin.acc,
    "grp_lin_dec": lambda g: g.lin.dec,
    "grp_lin_sf": lambda g: g.lin.sm_ms,
    "grp_ang_vel": lambda g: g.ang.vel,
    "grp_ang_acc": lambda g: g.ang.acc,
    "grp_ang_dec": lambda g: g.ang.dec,
    "grp_ang_sf": lambda g: g.ang.sm_ms,
    "grp_fault_status": lambda g: g.fault_status,
    "grp_motion_status": lambda g: g.motion_status,
}
ARRAY_VARIABLES = tuple(_ARRAYS)
"""Group variables of 8.1.1 that are arrays: [X Y Z A B C] or one value per axis."""
SCALAR_VARIABLES = tuple(_SCALARS)
CARTESIAN_ARRAYS = frozenset({"carte_pose_cmd", "carte_vel_cmd", "carte_pose_fb", "carte_pose_err"})


def group_variable(g: AxisGroup, name: str, index: int | None = None) -> float:
    """Group variable `name` of manual 8.1.1 (element `index` of an array; 0 beyond the
    group's axes, so a Cartesian array always has 6 elements)."""
    if name in _SCALARS:
        return float(_SCALARS[name](g))
    values = _ARRAYS[name](g)
    return float(values[index]) if index is not None and index < len(values) else 0.0


class GroupSet:
    """Every axis group of one motion kernel (`MotionKernel.groups`), by group id."""

    def __init__(self, kernel, n_groups: int, dt: float) -> None:
        self.kernel = kernel
        self.groups = [AxisGroup(g, dt, kernel) for g in range(n_groups)]
        self.enabled: list[AxisGroup] = []
        """The enabled groups, by group id (`power_changed` keeps it)."""
        for g in self.groups:
            g.group_set = self

    def power_changed(self) -> None:
        """A group was enabled or disabled (only `enable` and `disable` cross DISABLED)."""
        self.enabled = [g for g in self.groups if g.state != DISABLED]

    def __getitem__(self, group_id: int) -> AxisGroup:
        return self.groups[group_id]

    def __len__(self) -> int:
        return len(self.groups)

    def __iter__(self):
        return iter(self.groups)

    def get(self, group_id: int) -> AxisGroup | None:
        return self.groups[group_id] if 0 <= group_id < len(self.groups) else None

    def group_of(self, axis_id: int) -> AxisGroup | None:
        for g in self.groups:
            for a in g.axes:
                if a.axis_id == axis_id:
                    return g
        return None

    def step(self) -> None:
        for g in self.enabled:
            g.step()

    def busy(self) -> bool:
        return any(g.moving for g in self.groups)

    def power_off(self) -> None:
        """Disable every group at once (DisableAll, EStop)."""
        for g in self.enabled:
            g.power_off()

    def stop_all(self) -> set[int]:
        """StopGroup of every moving enabled group; the ids of the enabled groups' axes."""
        ids: set[int] = set()
        for g in self.groups:
            if g.state != DISABLED:
                if g.moving:
                    g.stop()
                ids.update(a.axis_id for a in g.axes)
        return ids
