"""Gantry pairs (HIMC manual chapter 7): two axes driven from one linear + yaw pair reference.

A gantry pair turns a right-hand axis (RHS) and a left-hand axis (LHS) into an
imaginary linear axis and a yaw axis (manual 7.1):

    pos_linear = (pos_rhs + pos_lhs) / 2,     pos_yaw = (pos_rhs - pos_lhs) / 2
    pos_rhs = pos_linear + pos_yaw,           pos_lhs = pos_linear - pos_yaw

(`from_axes`, `to_axes`; positions [mm or deg], the same for velocities and
accelerations). Commands to the RHS axis move the linear axis, commands to the LHS axis
the yaw axis: the RHS axis's profile generator plans the linear reference, the LHS's
the yaw reference, and a `Gantry` (the reference provider both axes follow,
motion/axis_follow.py) turns the pair reference into the two motor references each cycle.
`linear_fb` and `yaw_fb` are the feedbacks of 7.1.

Enable sequence (manual 7.1.1): EnableGantryPair needs both axes disabled; then
enabling either axis enables the other (`GantrySet.step`, once per cycle); when both
are enabled the pair engages at the present feedback (no jump: linear and yaw are
computed from it). Disabling either axis, or a fault that disables it, disables both.
A stop of either axis (Stop, a limit) stops the other too; once both rest the pair
re-engages where it stands (a Stop of the RHS axis stops the linear axis, of the LHS
the yaw axis, once the axis keeps a gantry axis on its provider for a stop).
DisableGantryPair needs both axes disabled.

Decisions where the manual is silent: pair ids are the lowest free numbers from 0;
DisableGantryPair of an axis in no pair does nothing and succeeds (the manual's example
calls it to clear a pair that may not exist); a gear master or slave cannot join a pair
(eERR_AXIS_CMD_INVALID_IN_SYNC), nor an axis of another pair
(eERR_AXIS_CMD_INVALID_GANTRY_MODE). Both axes carry the Gantry bit (5) of table 5.1.1.5
from EnableGantryPair to DisableGantryPair.
"""

from __future__ import annotations

import math

from motionvm.motion import axis_status as st
from motionvm.motion.gear import CMD_INVALID_GANTRY_MODE, GearBox, SyncError

OFF, ENABLING, ON, STOPPING = "off", "enabling", "on", "stopping"


def to_axes(linear: float, yaw: float) -> tuple[float, float]:
    """(rhs, lhs) of a linear and a yaw value (positions, velocities or accelerations)."""
    return linear + yaw, linear - yaw


def from_axes(rhs: float, lhs: float) -> tuple[float, float]:
    """(linear, yaw) of the RHS and LHS values (manual 7.1)."""
    return (rhs + lhs) / 2.0, (rhs - lhs) / 2.0


class Gantry:
    """One gantry pair; the reference provider of both of its axes while engaged."""

    accepts_moves = True
    """Profile commands on either axis drive its generator, the linear or yaw reference.

    Until the axis keeps a following axis on its provider for a command, a command takes
    the axis to its own generator for one cycle and `step` takes it back."""

    def __init__(self, pair_id: int, rhs, lhs):
        self.pair_id = pair_id
        self.rhs = rhs
        self.lhs = lhs
        self.state = OFF
        self.linear_ref = (0.0, 0.0, 0.0)
        """Linear axis (position [mm], velocity [mm/s], acceleration [mm/s^2]) of the cycle."""
        self.yaw_ref = (0.0, 0.0, 0.0)
        """Yaw axis reference, as `linear_ref`."""
        self._served: set[int] = set()
        self._wait = 0  # cycles left for the partner to come up
        self._first = rhs  # the axis the user enabled
        self._brake: dict[int, list[float]] = {}  # axis id -> [velocity, deceleration]

    def __repr__(self) -> str:
        return f"gantry pair {self.pair_id} (rhs {self.rhs.axis_id}, lhs {self.lhs.axis_id})"

    @property
    def axes(self) -> tuple:
        return self.rhs, self.lhs

    @property
    def linear_fb(self) -> float:
        """Position feedback of the linear axis [mm]."""
        return from_axes(self.rhs.pos_fb, self.lhs.pos_fb)[0]

    @property
    def yaw_fb(self) -> float:
        """Position feedback of the yaw axis [mm]."""
        return from_axes(self.rhs.pos_fb, self.lhs.pos_fb)[1]

    @property
    def engaged(self) -> bool:
        return self.state == ON

    # ---- once per cycle, before the tasks -------------------------------------------

    def step(self) -> None:
        """Enable sequence, engagement, and keeping both axes in the pair."""
        r, l = self.rhs, self.lhs
        if self.state == OFF:
            if r.enabled != l.enabled:
                self._enable_partner(l if r.enabled else r)
            elif r.enabled:
                self._engage()
        elif self.state == ENABLING:
            if r.enabled and l.enabled:
                self._engage()
            elif not self._first.enabled:  # disabled while the partner comes up
                self._power_off()
            else:
                self._wait -= 1
                if self._wait < 0:  # the partner did not come up (enable timeout)
                    self._power_off()
        elif not (r.enabled and l.enabled):
            self._power_off()
        elif self.state == ON:
            for a, b in ((r, l), (l, r)):
                if a.following is not self:
                    if a.stopping:  # a stop ramp of its own (a limit): the other brakes too
                        self.state = STOPPING
                        if b.following is self:
                            decel = b.kill_dec if a.error_stop else b.pg.d_max
                            self._brake[b.axis_id] = [b.ref_vel, decel]
                    else:  # a command took the axis to its own generator: take it back
                        a.follow(self)
        elif self.state == STOPPING and self._at_rest(r) and self._at_rest(l):
            self._engage()

    def _at_rest(self, axis) -> bool:
        if axis.following is self:
            return self._brake.get(axis.axis_id, (0.0,))[0] == 0.0
        return not axis.moving

    def _enable_partner(self, other) -> None:
        try:
            other.enable()
        except st.AxisCommandError:  # in error stop: the pair cannot run on one axis
            self._power_off()
            return
        self.state = ENABLING
        self._first = self.lhs if other is self.rhs else self.rhs
        self._wait = round(other.config.enable_timeout_ms / 1000.0 / other.dt) + 2

    def _power_off(self) -> None:
        for a in self.axes:
            a.disable()
        self.state = OFF

    def _engage(self) -> None:
        r, l = self.rhs, self.lhs
        lin, yaw = from_axes(r.ref_pos, l.ref_pos)
        r.pg.reset(lin)
        l.pg.reset(yaw)
        self.linear_ref = (lin, 0.0, 0.0)
        self.yaw_ref = (yaw, 0.0, 0.0)
        self._served.clear()
        self._brake.clear()
        r.follow(self)
        l.follow(self)
        self.state = ON

    # ---- the provider ---------------------------------------------------------------

    def moving(self, axis) -> bool:
        """Either axis moves while the linear or the yaw generator runs (or it brakes)."""
        if self.state == STOPPING:
            return self._brake.get(axis.axis_id, (0.0,))[0] != 0.0
        return not (
            self.rhs.pg.is_done
            and self.lhs.pg.is_done
            and self.linear_ref[1] == 0.0
            and self.yaw_ref[1] == 0.0
        )

    def reference(self, axis) -> tuple[float, float, float]:
        """The motor reference of `axis` (rhs or lhs) for this cycle."""
        key = axis.axis_id
        if self.state == STOPPING:  # the partner stopped on its own: brake to rest
            v_0, decel = self._brake.get(key, (0.0, 0.0))
            dv = decel * axis.dt
            v_1 = 0.0 if abs(v_0) <= dv else v_0 - math.copysign(dv, v_0)
            if key in self._brake:
                self._brake[key][0] = v_1
            return axis.ref_pos + 0.5 * (v_0 + v_1) * axis.dt, v_1, (v_1 - v_0) / axis.dt
        if key in self._served or not self._served:  # the first call of a cycle
            self._served = {key}
            r, l = self.rhs, self.lhs
            self.linear_ref = r.pg.step() if r.following is self else r.pg.output
            self.yaw_ref = l.pg.step() if l.following is self else l.pg.output
        else:
            self._served.add(key)
        (p, v, a), (p_y, v_y, a_y) = self.linear_ref, self.yaw_ref
        if axis is self.rhs:
            return p + p_y, v + v_y, a + a_y
        return p - p_y, v - v_y, a - a_y


class GantrySet:
    """Every gantry pair of one motion kernel (`MotionKernel.gantries`): the commands of
    chapter 7 and their checks. `gears` is the same kernel's gear box: an axis is either
    geared or paired, never both."""

    def __init__(self, gears: GearBox):
        self.pairs: dict[int, Gantry] = {}
        """Pair id -> pair."""
        self._gears = gears
        gears.gantry_axes = self.axis_ids

    def axis_ids(self) -> frozenset:
        return frozenset(a.axis_id for g in self.pairs.values() for a in g.axes)

    def pair_of(self, axis_id: int) -> Gantry | None:
        for g in self.pairs.values():
            if axis_id in (g.rhs.axis_id, g.lhs.axis_id):
                return g
        return None

    def pair_id(self, axis_id: int) -> int:
        """GetGantryPairID: the pair's id, -1 if the axis is in no pair."""
        g = self.pair_of(axis_id)
        return -1 if g is None else g.pair_id

    def is_pair(self, id_1: int, id_2: int) -> bool:
        g = self.pair_of(id_1)
        return g is not None and id_1 != id_2 and id_2 in (g.rhs.axis_id, g.lhs.axis_id)

    def enable_pair(self, rhs, lhs) -> Gantry:
        """EnableGantryPair: pair two disabled axes."""
        if rhs is lhs:
            raise SyncError(
                st.CMD_INVALID_PARAMETER,
                rhs.axis_id,
                f"axis {rhs.axis_id} cannot be paired with itself",
            )
        for a in (rhs, lhs):
            if self.pair_of(a.axis_id) is not None:
                raise SyncError(
                    CMD_INVALID_GANTRY_MODE,
                    a.axis_id,
                    f"axis {a.axis_id} is already in {self.pair_of(a.axis_id)}",
                )
            if self._gears.coupled(a.axis_id):
                raise SyncError(
                    st.CMD_INVALID_IN_SYNC,
                    a.axis_id,
                    f"axis {a.axis_id} is coupled by an electronic gear",
                )
            if a.enabled or a.moving:
                raise SyncError(
                    st.CMD_INVALID_ENABLED,
                    a.axis_id,
                    f"axis {a.axis_id} is enabled (EnableGantryPair needs both axes disabled)",
                )
        pair_id = next(i for i in range(len(self.pairs) + 1) if i not in self.pairs)
        g = self.pairs[pair_id] = Gantry(pair_id, rhs, lhs)
        for a in (rhs, lhs):
            a.extra_status = a.extra_status | st.MS_GANTRY
            a.wake()
        return g

    def disable_pair(self, axis) -> None:
        """DisableGantryPair: separate the pair of `axis` (both axes disabled)."""
        g = self.pair_of(axis.axis_id)
        if g is None:
            return
        for a in g.axes:
            if a.enabled:
                raise SyncError(
                    st.CMD_INVALID_ENABLED,
                    a.axis_id,
                    f"axis {a.axis_id} is enabled (DisableGantryPair needs both axes disabled)",
                )
        del self.pairs[g.pair_id]
        for a in g.axes:
            a.extra_status = a.extra_status & ~st.MS_GANTRY
            a.wake()

    def step(self) -> None:
        """Once per cycle, before the tasks run (`MotionKernel.begin_cycle`)."""
        for g in self.pairs.values():
            g.step()
