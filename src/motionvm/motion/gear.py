"""Electronic gear (HIMC manual chapter 6): slave axes following a master's command times a ratio.

EnableGear couples a slave to a master, GearIn engages it with a ratio, GearOut
disengages it, DisableGear uncouples. An engaged slave follows the master's position
command (`master_pos_gear` = the master's ref_pos, table 6.1.1.1) relatively, so that
engaging never makes it jump:

    gear_cmd_pos = s_0 + gear_ratio * (master_pos_gear - m_0)      [mm or deg]

with (m_0, s_0) the two references at the moment the slave became synchronous. A `Gear`
is the slave's reference provider (`Axis.follow`, motion/axis_follow.py); a `GearBox`
holds every gear of one motion kernel (`MotionKernel.gears`) and checks the commands of
chapter 6.

Decisions where the manual is silent:
- A slave has one master; a master may have many slaves; an axis cannot be both (no
  chains: eERR_AXIS_CMD_INVALID_GEAR_MASTER / _IN_SYNC), nor a gantry axis.
- EnableGear needs both axes enabled (manual 6.2), GearIn too (6.4) and a slave that
  does not move on its own (eERR_AXIS_CMD_INVALID_MOVING). The ratio must be finite,
  non-zero and at most MAX_RATIO in size (eERR_AXIS_CMD_INVALID_GEAR_RATIO).
- GearIn with the master at rest engages at once (IsInGear is 1 on return). With the
  master moving, the effective ratio ramps linearly from its present value (0 when
  disengaged) to the new one in T = |delta ratio * v_master| / a_max(slave) [s]: the slave
  reaches the synchronous velocity at its maximum acceleration (for a master at constant
  velocity). IsInGear turns 1 when the ramp ends; a GearIn while engaged changes the
  ratio the same way.
- GearOut brakes the slave from its velocity to rest at its maximum deceleration and
  then hands it back to its profile generator; IsInGear is 0 at once. A disabled master
  gears its slaves out the same way. DisableGear of an engaged (or braking) slave fails
  with eERR_AXIS_CMD_INVALID_IN_SYNC: GearOut first.
- Status bits (table 5.1.1.5): a coupled slave has Synchronous (bit 3) and Gear (bit 8)
  from EnableGear to DisableGear.
- A slave that leaves its gear by itself (disabled, a fault, a limit stop ramp) is
  disengaged; it stays coupled.
- SetPos on a master (not synchronous itself: 5.3.19 refuses only a synchronous axis)
  moves nothing: its slaves keep their commands (`master_shifted`). SetPos on a
  coupled slave is refused (eERR_AXIS_CMD_INVALID_IN_SYNC).

Order within a cycle: a slave reads the master's reference when it steps. A master
that steps before its slave gives the command of the same cycle (`lag_cycles` 0); one
that steps after it, the command of the previous cycle (`lag_cycles` 1). A kernel that
steps its axes in id order couples same-cycle only masters with a lower id than their
slaves; a kernel with a `step_order` list gets it sorted masters first (`GearBox`).
"""

from __future__ import annotations

import math

from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import AxisCommandError

DISENGAGED, ENGAGING, ENGAGED, DISENGAGING = "disengaged", "engaging", "engaged", "disengaging"
MAX_RATIO = 1000.0
"""Largest |gear ratio| [-] GearIn accepts."""

SLAVE_BITS = st.MS_SYNC | st.MS_GEAR

# axis error codes of chapters 6 and 7, low 16 bits (table 18.1.2.1); the others are in
# axis_status
CMD_INVALID_GEAR_MASTER = 0x00AA
CMD_INVALID_GANTRY_MODE = 0x00DC
CMD_INVALID_MASTER_SLAVE_CONNECTION = 0x01C2
CMD_INVALID_GEAR_RATIO = 0x01D6
CMD_GEAR_DISABLED = 0x0FA0


class SyncError(AxisCommandError):
    """A refused gear or gantry command; the error belongs to axis `axis_id`."""

    def __init__(self, code: int, axis_id: int, message: str):
        super().__init__(code, message)
        self.axis_id = axis_id


class Gear:
    """One slave coupled to one master; the slave's reference provider while in gear."""

    accepts_moves = False
    """Profile commands on a slave in gear are to be refused (eERR_AXIS_CMD_INVALID_IN_SYNC);
    until the axis does so, a command takes the slave out of its gear."""

    def __init__(self, master, slave):
        self.master = master
        self.slave = slave
        self.ratio = 0.0
        """gear_ratio: the ratio of the last GearIn [-]."""
        self.state = DISENGAGED
        self.master_pos_gear = master.ref_pos
        """The master's command the slave used in its last cycle [mm or deg]."""
        self.gear_cmd_pos = slave.ref_pos
        """The slave's gear command of its last cycle [mm or deg]."""
        self._r = 0.0  # effective ratio [-]
        self._dr = 0.0  # ratio change per cycle while engaging [-]
        self._m_0 = self._s_0 = 0.0
        self._v = 0.0  # slave velocity [mm/s] while braking after GearOut

    def __repr__(self) -> str:
        return f"gear master {self.master.axis_id} -> slave {self.slave.axis_id}"

    def lag_cycles(self, order: list) -> int:
        """Cycles by which the slave sees the master's command late, axes stepped in `order`."""
        return 1 if order.index(self.master) > order.index(self.slave) else 0

    @property
    def in_gear(self) -> bool:
        """IsInGear: synchronous at the full ratio."""
        return self.active and self.state == ENGAGED

    @property
    def active(self) -> bool:
        """True while the slave takes its reference from this gear (engaging, engaged or
        braking after GearOut)."""
        if self.state != DISENGAGED and self.slave.following is not self:
            self.state = DISENGAGED  # disabled, a fault or a limit stop took it away
        return self.state != DISENGAGED

    # ---- commands -------------------------------------------------------------------

    def gear_in(self, ratio: float) -> None:
        """Engage at `ratio` (or change the ratio while engaged); see the module docstring."""
        slave, master = self.slave, self.master
        if not self.active:
            self._r = 0.0
            self._v = 0.0
            self.master_pos_gear = master.ref_pos
            self.gear_cmd_pos = slave.ref_pos
            slave.follow(self)
        self.ratio = ratio
        n = math.ceil(abs((ratio - self._r) * master.ref_vel) / slave.pg.a_max / slave.dt - 1e-9)
        if n <= 0:
            self._synchronised()
        else:
            self.state = ENGAGING
            self._dr = (ratio - self._r) / n

    def gear_out(self) -> None:
        """Disengage: brake to rest at the slave's maximum deceleration, then let go."""
        if not self.active or self.state == DISENGAGING:
            return
        self.state = DISENGAGING
        self._v = self.slave.ref_vel
        if self._v == 0.0:
            self._let_go()

    def master_shifted(self, shift: float) -> None:
        """The master's position reads `shift` [mm or deg] more (SetPos): the same
        motion, so the slave keeps its command."""
        self.master_pos_gear += shift
        self._m_0 += shift

    def _synchronised(self) -> None:
        self._r = self.ratio
        self._m_0 = self.master_pos_gear
        self._s_0 = self.gear_cmd_pos
        self.state = ENGAGED

    def _let_go(self) -> None:
        self.state = DISENGAGED
        self.slave.release()

    # ---- the provider ---------------------------------------------------------------

    def moving(self, slave) -> bool:
        """The slave moves while its gear command changes."""
        return self.state != ENGAGED or self.master.moving or self.slave.ref_vel != 0.0

    def reference(self, slave) -> tuple[float, float, float]:
        """The slave's (ref_pos [mm], ref_vel [mm/s], ref_acc [mm/s^2]) for this cycle."""
        dt = slave.dt
        p_prev, v_prev = self.gear_cmd_pos, slave.ref_vel
        if self.state == DISENGAGING or (self.state != DISENGAGED and not self.master.enabled):
            if self.state != DISENGAGING:
                self.state = DISENGAGING
                self._v = v_prev
            v_0 = self._v
            dv = slave.pg.d_max * dt
            v_1 = 0.0 if abs(v_0) <= dv else v_0 - math.copysign(dv, v_0)
            self._v = v_1
            p = p_prev + 0.5 * (v_0 + v_1) * dt
            if v_1 == 0.0:  # at rest: the profile generator holds the last command
                self._let_go()
                slave.pg.reset(p)
                self.gear_cmd_pos = p
                return p, 0.0, -v_prev / dt
        else:
            m = self.master.ref_pos
            if self.state == ENGAGING:
                r = self._r + self._dr
                if (r - self.ratio) * self._dr >= 0.0:
                    r = self.ratio
                self._r = r
                p = p_prev + r * (m - self.master_pos_gear)
                self.master_pos_gear, self.gear_cmd_pos = m, p
                if r == self.ratio:
                    self._synchronised()
            else:
                p = self._s_0 + self._r * (m - self._m_0)
            self.master_pos_gear = m
        self.gear_cmd_pos = p
        v = (p - p_prev) / dt
        return p, v, (v - v_prev) / dt


class GearBox:
    """Every gear of one motion kernel: the commands of chapter 6 and their checks.

    If the kernel has a `step_order` list (the order it steps its axes in), the box keeps
    it masters first, so that every slave sees its master's command of the same cycle.
    """

    def __init__(self, kernel):
        self.kernel = kernel
        self.gears: dict[int, Gear] = {}
        """Slave axis id -> its gear."""
        self.gantry_axes = lambda: frozenset()
        """Ids of the gantry axes (set by the gantry registry of the same kernel)."""

    # ---- queries --------------------------------------------------------------------

    def gear_of(self, slave_id: int) -> Gear | None:
        return self.gears.get(slave_id)

    def lag_cycles(self, slave_id: int) -> int:
        """0 if slave `slave_id` sees its master's command of the same cycle, 1 if late."""
        order = getattr(self.kernel, "step_order", None) or self.kernel.axes
        return self.gears[slave_id].lag_cycles(order)

    def _reorder(self) -> None:
        order = getattr(self.kernel, "step_order", None)
        if order is not None:
            masters = {g.master.axis_id for g in self.gears.values()}
            order[:] = sorted(self.kernel.axes, key=lambda a: (a.axis_id not in masters, a.axis_id))

    def is_slave(self, axis_id: int) -> bool:
        return axis_id in self.gears

    def is_master(self, axis_id: int) -> bool:
        return any(g.master.axis_id == axis_id for g in self.gears.values())

    def is_in_gear(self, axis_id: int) -> bool:
        g = self.gears.get(axis_id)
        return g is not None and g.in_gear

    def ratio(self, slave_id: int) -> float:
        g = self.gears.get(slave_id)
        return g.ratio if g is not None else 0.0

    def coupled(self, axis_id: int) -> bool:
        """True if the axis is a gear master or slave (a gantry may not take it)."""
        return self.is_slave(axis_id) or self.is_master(axis_id)

    # ---- commands -------------------------------------------------------------------

    def master_shifted(self, master, shift: float) -> None:
        """`master`'s position reads `shift` more (SetPos): its slaves stay in step."""
        if shift:
            for g in self.gears.values():
                if g.master is master:
                    g.master_shifted(shift)

    def _check_pair(self, master, slave) -> None:
        mid, sid = master.axis_id, slave.axis_id
        if mid == sid:
            raise SyncError(
                CMD_INVALID_MASTER_SLAVE_CONNECTION,
                sid,
                f"axis {sid} cannot be its own gear master",
            )
        for a in (master, slave):
            if a.axis_id in self.gantry_axes():
                raise SyncError(
                    CMD_INVALID_GANTRY_MODE, a.axis_id, f"axis {a.axis_id} is a gantry axis"
                )
            if not a.enabled:
                raise SyncError(
                    st.CMD_INVALID_DISABLED, a.axis_id, f"axis {a.axis_id} is not enabled"
                )

    def enable_gear(self, master, slave) -> None:
        """EnableGear: couple `slave` to `master` (both enabled)."""
        mid, sid = master.axis_id, slave.axis_id
        self._check_pair(master, slave)
        g = self.gears.get(sid)
        if g is not None:
            if g.master is master:
                return
            raise SyncError(
                st.CMD_INVALID_IN_SYNC,
                sid,
                f"axis {sid} is already the gear slave of axis {g.master.axis_id}",
            )
        if self.is_master(sid):
            raise SyncError(CMD_INVALID_GEAR_MASTER, sid, f"axis {sid} is a gear master")
        if mid in self.gears:
            raise SyncError(st.CMD_INVALID_IN_SYNC, mid, f"axis {mid} is a gear slave")
        self.gears[sid] = Gear(master, slave)
        slave.extra_status = slave.extra_status | SLAVE_BITS
        slave.wake()
        self._reorder()

    def _gear(self, slave) -> Gear:
        g = self.gears.get(slave.axis_id)
        if g is None:
            raise SyncError(
                CMD_GEAR_DISABLED,
                slave.axis_id,
                f"axis {slave.axis_id} is not a gear slave (call EnableGear)",
            )
        return g

    def gear_in(self, master, slave, ratio: float) -> None:
        """GearIn: engage `slave` at `ratio` to its master `master`."""
        g = self._gear(slave)
        if g.master is not master:
            raise SyncError(
                CMD_INVALID_MASTER_SLAVE_CONNECTION,
                slave.axis_id,
                f"axis {slave.axis_id} is coupled to master {g.master.axis_id}, "
                f"not {master.axis_id}",
            )
        self._check_pair(master, slave)
        if not (math.isfinite(ratio) and ratio != 0.0 and abs(ratio) <= MAX_RATIO):
            raise SyncError(
                CMD_INVALID_GEAR_RATIO,
                slave.axis_id,
                f"gear ratio {ratio!r} is not in -{MAX_RATIO:g} .. {MAX_RATIO:g} without 0",
            )
        if slave.error_stop:
            raise SyncError(
                st.CMD_INVALID_ERROR_STATE,
                slave.axis_id,
                f"axis {slave.axis_id} is in error stop (call Reset)",
            )
        if g.state == DISENGAGING or (not g.active and slave.moving):
            raise SyncError(st.CMD_INVALID_MOVING, slave.axis_id, f"axis {slave.axis_id} is moving")
        g.gear_in(ratio)

    def gear_out(self, slave) -> None:
        """GearOut: disengage `slave` (nothing to do if it is not engaged)."""
        self._gear(slave).gear_out()

    def disable_gear(self, slave) -> None:
        """DisableGear: uncouple a disengaged `slave` from its master."""
        g = self._gear(slave)
        if g.active:
            raise SyncError(
                st.CMD_INVALID_IN_SYNC,
                slave.axis_id,
                f"axis {slave.axis_id} is in gear (call GearOut first)",
            )
        del self.gears[slave.axis_id]
        slave.extra_status = slave.extra_status & ~SLAVE_BITS
        self._reorder()
