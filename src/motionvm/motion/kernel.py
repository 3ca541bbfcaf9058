"""The motion kernel: every axis of the machine, what feeds their references, the
simulated EtherCAT bus, last errors.

It owns, besides the axes, the machine's reference providers and per-axis devices: the
electronic gears (`gears`, motion/gear.py), the gantry pairs (`gantries`,
motion/gantry.py), one homing state (`homing[axis_id]`, motion/homing.py) and one touch
probe (`probes[axis_id]`, motion/touchprobe.py) per axis. The controller calls it twice
per cycle:

1. `begin_cycle`, before the tasks: the gantry pairs' enable sequences and engagement,
   so that the tasks of a cycle see a pair settled;
2. `step`, after the tasks: the bus, then every axis in `step_order`. An axis that
   follows a provider (a gear, a gantry pair, a homing run: `Axis.follow`) pulls its
   reference from it as it steps, so the order of the axes is the order of the
   providers: gear masters step before their slaves. Providers that plan for several
   axes at once (axis groups) take their place between the bus and the axes.

The bus master's state (GetECATSt: 1 Init, 2 Pre-Operation, 4 Safe-Operation,
8 Operation) is Operation from power-on; ScanNetwork takes it down to Init and back up
one state per cycle, and the drives cannot be enabled until it is back in Operation. Slave i is axis i's drive.
The axis groups (`groups`, motion/group.py, N_GROUPS of them) step between the bus and
the axes; their last errors live here too (`group_last_error`).
"""

from __future__ import annotations

from motionvm.drives.dictionary import SlaveDirectory
from motionvm.motion import axis_coast, config_axis, config_group, group_coast
from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import AxisConfig
from motionvm.motion.axis_cycle import axes_busy, step_axes, step_axes_alone
from motionvm.motion.config_vars import ConfigVarTable
from motionvm.motion.deferred import Deferrals
from motionvm.motion.gantry import GantrySet
from motionvm.motion.gear import GearBox
from motionvm.motion.group import GroupSet
from motionvm.motion.homing import AxisHoming
from motionvm.motion.inshape import InShapeSettings
from motionvm.motion.touchprobe import TouchProbe
from motionvm.runtime.waits import Waiting

ECAT_INIT, ECAT_PREOP, ECAT_SAFEOP, ECAT_OP = 1, 2, 4, 8
N_GROUPS = 16


class MotionKernel:
    """All axes of one controller, their reference providers and the bus they sit on."""

    def __init__(self, configs: list[AxisConfig], dt: float):
        self.dt = dt
        self.axes = [Axis(i, c, dt) for i, c in enumerate(configs)]
        self.step_order = list(self.axes)
        """The order the axes step in: by id, gear masters first (motion/gear.py)."""
        self.gears = GearBox(self)
        """The electronic gears (manual chapter 6); it keeps `step_order` masters first."""
        self.gantries = GantrySet(self.gears)
        """The gantry pairs (manual chapter 7), stepped in `begin_cycle`."""
        self.homing = [AxisHoming(a) for a in self.axes]
        """The homing state of each axis (manual chapter 20), by axis id."""
        self.probes = [TouchProbe(a) for a in self.axes]
        """The touch probe of each axis (manual chapter 13), by axis id."""
        self.slaves = SlaveDirectory(a.drive.objects for a in self.axes)
        """The object dictionaries of the bus's slaves: the drives, then I/O modules."""
        for a in self.axes:  # a write to a drive from outside wakes its axis from rest
            a.drive.on_change = a.wake
        self.config_vars = ConfigVarTable()
        """Controller variables by HCV id (manual 17.1.1): the axes' are registered here."""
        config_axis.register(self.config_vars, self)
        self.ecat_state = ECAT_OP
        """Master state of the bus [1, 2, 4, 8]."""
        self.system_last_error = 0
        self.group_last_error = [0] * N_GROUPS
        self.group_inshape = [InShapeSettings() for _ in range(N_GROUPS)]
        """Each group's InShape settings (SetGrpInShape, EnableGrpInShape: chapter 15)."""
        self.groups = GroupSet(self, N_GROUPS, dt)
        """The axis groups (manual chapter 8), stepped before the axes."""
        config_group.register(self.config_vars, self)
        self.estopped = False
        """True after EStop: IsSystemError answers 1."""
        self._bus_steps: list[int] = []
        # I/O slaves: the I/O layer (io/system.py) puts them on the bus after the drives
        self.extra_slaves = 0
        """I/O slaves on the bus after the drives: slaves n_axes .. n_slaves - 1."""
        self.lost_slaves: set[int] = set()
        """Slaves that left the bus (a fault): they report Init (1) for good."""
        self._coast_memo: dict = {}
        """What `coast_horizon` found of each axis that `coast` can reuse (axis_coast.py)."""
        self.deferring = False
        """Set by the controller for each cycle in which nothing but the status flags
        may read a moving axis: `step` then defers what it can (motion/deferred.py)."""
        self.deferred = Deferrals()
        """The axes whose cycles `step` deferred (`catch_up` brings them up to date)."""
        self.reads: list | None = None
        """While a task runs (and time skipping records them): the status flags the task
        read, as (object, attribute, value); None: nothing is recorded (runtime/kernel.py,
        `Kernel.recorder`)."""

    @property
    def n_slaves(self) -> int:
        """Every slave of the bus: the drives, then the I/O slaves."""
        return len(self.axes) + self.extra_slaves

    @property
    def n_axes(self) -> int:
        return len(self.axes)

    def axis(self, axis_id: int) -> Axis | None:
        """Axis `axis_id` (up to date: `catch_up`), or None if there is no such axis."""
        if 0 <= axis_id < len(self.axes):
            a = self.axes[axis_id]
            if self.deferred.lagging and a in self.deferred.lagging:
                self.deferred.catch_up(a)
            return a
        return None

    def catch_up(self) -> None:
        """Bring every axis whose cycles `step` deferred up to date (motion/deferred.py):
        before anything but the status flags of an axis is read or changed."""
        if self.deferred.lagging:
            self.deferred.catch_up_all()

    # ---- the cycle ------------------------------------------------------------------

    def begin_cycle(self) -> None:
        """Before the tasks of a cycle: the gantry pairs' enable sequences and engagement."""
        if self.gantries.pairs:
            self.gantries.step()

    def step(self) -> None:
        """The motion phase of one cycle: the bus, then every axis in `step_order`."""
        if self._bus_steps:
            self.ecat_state = self._bus_steps.pop(0)
        if self.deferring and self._through_deferrals():
            self.deferred.step(self.step_order)  # (motion/deferred.py)
            return
        groups = self.groups
        if groups.enabled:  # most cycles no group is enabled: no call
            groups.step()
        if self.deferred.lagging:
            self.deferred.catch_up_all()
        step_axes(self.step_order)

    def _through_deferrals(self) -> bool:
        """While `deferring`: True if a motion phase now goes through the deferrals
        (`step`): no group enabled, no bus starting, no gantry pair, no gear."""
        return not (self.groups.enabled or self._bus_steps or self.gantries.pairs
                    or self.gears.gears)  # fmt: skip

    def busy(self) -> bool:
        """True while an axis moves, enables, settles or stops, or the bus starts up.

        An axis jogging at a constant velocity it has reached (`Axis.cruising`) counts as
        settled: nothing about it changes until it is commanded again.
        """
        if self._bus_steps or self.groups_moving():
            return True
        if self.deferred.lagging:
            if self.deferred.one_busy():
                return True
            self.catch_up()  # (`cruising` reads more than the status flags)
        return axes_busy(self.axes)

    def step_alone(self, n: int, until_idle: bool) -> int:
        """Up to `n` cycles of this kernel alone (`begin_cycle`, `step`): cycles in which
        nothing else of the controller has work (the controller's `_motion_alone`).
        Stops after the first cycle that leaves the kernel at rest (`at_rest`) or, with
        `until_idle`, not busy (`busy`): the run loop decides something there. Returns
        the cycles run. Axes alone (no group enabled, no bus starting, no gantry pair,
        nothing deferred) run in one loop (`step_axes_alone`, in C when compiled)."""
        if not (self.groups.enabled or self._bus_steps or self.gantries.pairs
                or self.deferring or self.deferred.lagging):  # fmt: skip
            return step_axes_alone(self.step_order, self.axes, n, until_idle)
        # deferring as `step` does: the phases with nothing to do are only counted
        deferrals = self.deferred if self.deferring and self._through_deferrals() else None
        k = 0
        while k < n:
            if deferrals is not None:
                idle = deferrals.pass_idle(self.step_order, n - k)
                if idle:
                    k += idle
                    continue
            self.begin_cycle()
            self.step()
            k += 1
            if self.at_rest() or (until_idle and not self.busy()):
                return k
        return n

    def groups_moving(self) -> bool:
        """`groups.busy()`: a group moves (only an enabled group's planner is asked)."""
        for g in self.groups.enabled:
            if g.moving:
                return True
        return False

    def still_running(self) -> list[Waiting]:
        """A `Waiting` for every axis that keeps the run busy (`busy`)."""
        self.catch_up()
        out = [Waiting(f"axis group {g.group_id}", why="moving") for g in self.groups if g.moving]
        for a in self.axes:
            if a.moving and not a.cruising:
                out.append(Waiting(f"axis {a.axis_id}", why="moving"))
            elif a._enabling:
                out.append(Waiting(f"axis {a.axis_id}", why="enabling"))
            elif a.enabled and not a.in_pos and not a.cruising:
                out.append(Waiting(f"axis {a.axis_id}", why="settling into position"))
        return out

    def at_rest(self) -> bool:
        """True if no axis needs stepping: the controller may then jump ahead in time."""
        if self._bus_steps or self.groups_moving():
            return False
        for a in self.axes:
            if not a.resting:
                return False
        return True

    # ---- time skipping (motion/axis_coast.py) ----------------------------------------

    def steps_alone(self) -> bool:
        """True if a cycle of this kernel alone (`begin_cycle`, `step`), with no task and
        no client run, is the whole of the cycle for it: no gear, no gantry pair, no bus
        starting up (each of those is stepped with the tasks)."""
        return not (self._bus_steps or self.gantries.pairs or self.gears.gears)

    def coast_horizon(self, wanted: int, watched=None, watches=()) -> int:
        """How many cycles (at most `wanted`) every axis can be advanced in closed form
        from now: 0 if one must be stepped. Gears, gantry pairs and a starting bus are
        stepped; a moving axis group as far as motion/group_coast.py allows. The advance
        ends with the first status change of an axis, unless `watched` (not None) holds
        the axes whose `moving` flag someone reads: the others may end region I inside
        it and stop where they come into position (motion/axis_coast.py); and at the
        first cycle after which a position that a task waits for may be reached
        (`watches`: `PositionWatch`es, each false now)."""
        self.catch_up()
        if not self.steps_alone():
            return 0 if not self.at_rest() else wanted
        k = wanted
        memo = self._coast_memo
        memo.clear()
        grouped = None
        for g in self.groups.enabled:
            if g.moving:
                k = group_coast.coast_room(g, k)
                if not k:
                    return 0
                if grouped is None:
                    grouped = [g]
                else:
                    grouped.append(g)
        if grouped is not None:  # (the limits only once no group's path ends the advance)
            for g in grouped:
                if not group_coast.clear(g):
                    return 0
            grouped = {a for g in grouped for a in g.axes}
        for a in self.axes:
            if not a.resting and (grouped is None or a not in grouped):
                k = axis_coast.coast_cycles(a, k, watched is not None and a not in watched, memo)
                if not k:
                    return 0
        for w in watches:
            k = w.cycles(k)
            if not k:
                return 0
        return k

    def coast(self, k: int) -> None:
        """Advance every axis by `k` cycles (k <= `coast_horizon(k, ...)`), as k `step`s
        would. With a moving group, fewer cycles than its closed form takes are stepped."""
        self.catch_up()
        grouped = None
        for g in self.groups.enabled:
            if g.moving:
                if k < group_coast.min_cycles(g):
                    self._coast_memo.clear()
                    for _ in range(k):
                        self.step()
                    return
                if grouped is None:
                    grouped = []
                grouped.append(g)
        if grouped is not None:
            inside = set()
            for g in grouped:
                group_coast.coast(g, k)
                inside.update(g.axes)
        memo = self._coast_memo
        for a in self.step_order:
            if not a.resting and (grouped is None or a not in inside):
                axis_coast.coast(a, k, memo)
        memo.clear()

    def status_signature(self) -> tuple:
        """What a task's wait on an axis or group event tests (IsInPos, IsMoving,
        IsEnabled, IsHomed, IsHoming, IsErrorStop, IsGrp*): equal signatures, equal
        answers."""
        axes = tuple([(a.moving, a.in_pos, a.enabled, a._enabling, a._error_stop, a.extra_status)
                      for a in self.axes])  # fmt: skip
        if not self.groups.enabled:
            return axes
        # and what IsGrpEnabled, IsGrpMoving, IsGrpInPos, IsGrpErrorStop test besides
        return axes, tuple([(g.group_id, g.state, g.moving) for g in self.groups.enabled])

    # ---- bus and system (manual 2.5-2.10, 2.15) -------------------------------------

    def slave_state(self, slave_id: int) -> int:
        """State of slave `slave_id` (0 if there is no such slave)."""
        if not 0 <= slave_id < self.n_slaves:
            return 0
        if slave_id in self.lost_slaves:
            return ECAT_INIT
        return self.ecat_state

    def scan_network(self) -> int:
        """Rescan: the bus goes Init -> Pre-Op -> Safe-Op -> Op, one state per cycle.

        Refused (eERR_AXIS_CMD_INVALID_ENABLED of the first enabled axis) while an axis
        is enabled, as a rescan would cut the drives off.
        """
        for a in self.axes:
            if a.enabled or a._enabling:
                return st.axis_error(st.CMD_INVALID_ENABLED, a.axis_id)
        self.ecat_state = ECAT_INIT
        self._bus_steps = [ECAT_PREOP, ECAT_SAFEOP, ECAT_OP]
        return 0

    def lose_drive(self, axis_id: int) -> None:
        """The drive of `axis_id` left the bus: the axis faults as on a drive fault
        (disabled, error stop), with eERR_AXIS_DRIVE_FAULT as its last error."""
        a = self.axes[axis_id]
        a.drive_lost()

    def disable_all(self) -> None:
        """DisableAll (2.7): disable every axis and every axis group."""
        self.groups.power_off()
        for a in self.axes:
            a.disable()

    def stop_all(self) -> None:
        """Stop every axis at its kill deceleration; the axes stay enabled. The axes of an
        enabled group stop with it, along its path (StopGroup)."""
        in_groups = self.groups.stop_all()
        for a in self.axes:
            if a.axis_id not in in_groups:
                a.stop(a.kill_dec)

    def estop(self) -> None:
        """Emergency stop: disable every axis and group; the system reports an error."""
        self.disable_all()
        self.estopped = True
        self.system_last_error = st.SYS_EMERGENCY_STOP
