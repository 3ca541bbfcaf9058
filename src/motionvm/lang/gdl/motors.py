"""GDL motors as machine axes: DC$MOTOR$AXIS, STEPPER$MOTOR and STP$MOTOR$AXIS.

Mapping (`assign_axes`): a motor named in the machine file (`gdl = "NAME"` in an
[[axis]] table) is that axis; the other motor objects of an application, in declaration
order (files as given, then textual order), take the machine's free axes 0, 1, 2, ...
(axes whose drive runs no PDL program and that no other motor took); an application
with more motors than free axes does not run (`GdlMachineError`). A motor's axis is
owned by it: HMPL motion commands to it are refused, as for a PDL drive's axis. AXIS$NUMBER of a DC$MOTOR$AXIS stays the object's own number in
GDL; it does not pick the axis.

Configuration at the start of the run, through the axis's public API:
- units: a position of the object [units] is a position of the axis [mm or deg] 1:1.
  The RTS reads the axis's reference position (`ref_pos`, the profile generator's
  output) and velocity (`ref_vel`), so the machine's counts_per_unit and its drive's
  mechanics change no value a program sees;
- limits: velocity MAX$SPEED [units/s], acceleration and deceleration ACCELERATION
  [units/s^2] (a HOME$SEARCH faster than MAX$SPEED raises the velocity limit for it);
  the machine's software limits and limit switches are ignored: GDL checks MOVE$TO
  against the object's LOWER/UPPER$TRAVEL$LIMIT itself, and a jog runs freely;
- power: the axis is enabled at once, whatever CONSTANT$STATUS says; its drive's CiA 402
  enable sequence takes a few cycles, and a motion operator given before the drive is
  enabled starts in the first cycle it is.

Semantics:
- CONSTANT$STATUS is the object's permission to move: DISABLED refuses motion operators
  and stops the motor at once where its reference is (no ramp; the drive stays enabled
  and holds that position); ENABLED permits them again at once.
- RUN$AT$SPEED v: `move_vel(v)` (v = 0 ramps down as STOP); MOVE$TO p: `move_abs(p +
  offset)` (offset: set by homing); STOP: `stop(ACCELERATION)`. The axis refuses new
  moves while it stops: a motion operator given then starts once it stands still, and
  OPERATING$CONDITION stays RUNNING in between.
- HOME$SEARCH: `move_vel(-HOME$SPEED)` until the home input is ON, then the motor stops
  at once and that position becomes POSITION 0 (`offset`), HOMED = ON.
- Each cycle after the motion step: SPEED = round(ref_vel), POSITION = round(ref_pos -
  offset); OPERATING$CONDITION = STOPPED in the cycle the reference arrives on its
  target or stop position (SPEED 0 from then on).
- An axis that leaves Operation Enabled on its own (a drive fault, a position error)
  sets DIAGN$STATUS = FAULT and OPERATING$CONDITION = STOPPED.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from motionvm.lang.gdl.app import App, ObjectInfo
from motionvm.lang.gdl.check_proc import dynamic_limit
from motionvm.lang.gdl.devices import MOTOR_TYPES, Device, GdlFault, RtsView
from motionvm.motion.axis_status import AxisCommandError
from motionvm.sim.machine import GdlMotorSpec

if TYPE_CHECKING:
    from motionvm.motion.axis import Axis

MOVE, JOG, STOP = "move", "jog", "stop"
"""What a motor was last commanded to do (None: it stands still)."""


class GdlMachineError(Exception):
    """The machine cannot run the application (too few axes); exit code 3. The message
    is the whole line: `FILE:LINE:COL: error: ...` at the machine file's `gdl` key or
    the motor's declaration."""


def assign_axes(
    app: App, axes: Sequence[Axis], named: Sequence[GdlMotorSpec] = ()
) -> dict[str, Axis]:
    """The machine axis of each motor object, by object key.

    Motors the machine file names (`gdl = "NAME"` in an [[axis]] table) are those axes;
    the others take, in declaration order, the axes nobody owns yet (no PDL program on
    the drive, no other motor). Each motor's axis is marked as owned by it, so HMPL
    motion commands to it are refused. Raises GdlMachineError for a name that is not a
    motor of the application and when the machine has too few free axes.
    """
    motors = [o for o in app.objects.values() if o.type.name in MOTOR_TYPES]
    by_key = {o.key: o for o in motors}
    out: dict[str, Axis] = {}
    for spec in named:
        obj = by_key.get(spec.name.casefold())
        if obj is None:
            known = ", ".join(o.name for o in motors) or "none"
            raise GdlMachineError(
                f"{spec.where}: error: [[axis]] {spec.axis}: gdl = '{spec.name}' is not a motor "
                f"object of the application (its motors: {known})"
            )
        out[obj.key] = axes[spec.axis]
    taken = {id(a) for a in out.values()}
    free = iter(a for a in axes if id(a) not in taken and a.controlled_by is None)
    for obj in motors:
        if obj.key in out:
            continue
        axis = next(free, None)
        if axis is None:
            owned = sum(1 for a in axes if a.controlled_by is not None)
            needed = owned + len(motors)
            raise GdlMachineError(
                f"{obj.pos}: error: motor {obj.name} has no machine axis: the "
                f"machine's {len(axes)} axes are all taken (by PDL drives or other motors); "
                f"the application declares {len(motors)} motors (give a machine file with "
                f"{needed} [[axis]] tables)"
            )
        out[obj.key] = axis
    for key, axis in out.items():
        axis.controlled_by = f"GDL motor {by_key[key].name}"
    return out


class _Hold:
    """A reference provider that holds the axis where its reference is."""

    def reference(self, axis: Axis) -> tuple[float, float, float]:
        return axis.ref_pos, 0.0, 0.0


_HOLD = _Hold()


def halt_at_once(axis: Axis) -> None:
    """Stop `axis` at once on its reference position and keep it enabled and ready.

    `Axis` has no public stop without a ramp; `release()` hands an axis back to its
    profile generator at rest on its current reference (motion/axis_follow.py), which
    is exactly that. Replace by a quick-stop method of `Axis` if one comes.
    """
    axis.follow(_HOLD)
    axis.release()


class MotorDevice(Device):
    """A GDL motor object on its machine axis (see the module docstring)."""

    def __init__(self, obj: ObjectInfo, axis: Axis) -> None:
        super().__init__(obj)
        self.axis = axis
        self.offset = 0.0
        """Axis position of POSITION 0 [units], set by homing."""
        self.homing = False
        self.home: ObjectInfo | None = None
        self.mode: str | None = None
        """MOVE, JOG or STOP while commanded; None once it stands still."""
        self.target = 0.0
        """Axis position [units] a MOVE ends on."""
        self.v_cmd = 0.0
        """Commanded jog velocity [units/s]."""
        self.pending: tuple[str, float] | None = None
        """A command waiting for the axis (enabling, or stopping after STOP)."""
        self.position = axis.ref_pos
        """Axis position [units] at the last update (encoders and home inputs read it)."""
        self.velocity = 0.0
        """Axis velocity [units/s] at the last update, 0 from the cycle of arrival."""

    def _param(self, name: str, default: int) -> float:
        return float(self.obj.params.get(name, default))  # type: ignore[arg-type]

    @property
    def v_max(self) -> float:
        return self._param("MAX$SPEED", 3000)

    @property
    def a_max(self) -> float:
        return self._param("ACCELERATION", 30000)

    def start(self, rts: RtsView) -> None:
        self.home = next(
            (
                o
                for o in rts.app.objects.values()
                if o.type.name == "STP$MOTOR$AXIS$HOME$INPUT"
                and o.params.get("STPMOTOR$NAME") == self.obj.key
            ),
            None,
        )
        ax = self.axis
        ax.set_ignore("swl", 1)
        ax.set_ignore("hwl", 1)
        ax.set_vel(self.v_max)
        ax.set_acc(self.a_max)
        ax.set_dec(self.a_max)
        ax.enable()
        if self.obj.type.state("POSITION") is not None:
            rts.init_value(self.obj, "POSITION", 0, round(self.position))

    # ------------------------------------------------------------ operators

    def _require_ready(self, rts: RtsView, op: str) -> None:
        if rts.read(self.obj, "CONSTANT$STATUS", 0) != "ENABLED":
            raise GdlFault(
                f"{op} OF {self.obj.name}: the motor is DISABLED (assign "
                f"CONSTANT$STATUS OF {self.obj.name} = ENABLED first)"
            )
        if rts.read(self.obj, "DIAGN$STATUS", 0) == "FAULT":
            raise GdlFault(f"{op} OF {self.obj.name}: DIAGN$STATUS is FAULT")

    def _check_limit(self, op: str, name: str, value: int, limit: str) -> None:
        dyn = dynamic_limit(self.obj, limit)
        if dyn is not None and not dyn[0] <= value <= dyn[1]:
            raise GdlFault(
                f"argument {name} of {op} = {value} is outside {dyn[2]} "
                f"{dyn[0]}..{dyn[1]} of {self.obj.name}"
            )

    def call(self, rts: RtsView, op: str, args: list[int], element: int) -> None:
        if op == "STOP":
            self.homing = False
            self._stop()
            return
        self._require_ready(rts, op)
        if op == "RUN$AT$SPEED":
            self._check_limit(op, "speed", args[0], "max_speed")
            self.homing = False
            if args[0] == 0:
                self._stop()
            else:
                self._command(JOG, float(args[0]))
        elif op == "MOVE$TO":
            self._check_limit(op, "position", args[0], "travel")
            self.homing = False
            target = args[0] + self.offset
            if self.mode is not None or self.axis.ref_pos != target:  # else: already there
                self._command(MOVE, target)
        elif op == "HOME$SEARCH":
            if self.home is None:
                raise GdlFault(
                    f"HOME$SEARCH OF {self.obj.name}: no STP$MOTOR$AXIS$HOME$INPUT names this axis"
                )
            self.homing = True
            rts.write(self.obj, "HOMED", 0, False, rts.origin())
            self._command(JOG, -self._param("HOME$SPEED", 100))
        else:
            super().call(rts, op, args, element)
        if self.busy:
            rts.write(self.obj, "OPERATING$CONDITION", 0, "RUNNING", rts.origin())

    def _stop(self) -> None:
        """Ramp down at ACCELERATION; a command still waiting is dropped."""
        self.pending = None
        if self.mode is None:
            return
        if self.axis.moving:
            self.axis.stop(self.a_max)
            self.mode = STOP
        else:  # a command that never started
            self.mode = None

    def _command(self, kind: str, arg: float) -> None:
        """Start a MOVE to `arg` [units] or a JOG at `arg` [units/s], or let it wait."""
        if kind == MOVE:
            self.target = arg
        else:
            self.v_cmd = arg
        ax = self.axis
        if ax.error_stop:
            raise GdlFault(
                f"{self.obj.name}: machine axis {ax.axis_id} is in error stop "
                f"(last error {ax.last_error:#x})"
            )
        if not ax.enabled or ax.stopping:
            if not ax.enabled:
                ax.enable()  # nothing if it is enabling already
            if self.mode is None:
                self.mode = kind
            self.pending = (kind, arg)
            return
        self.pending = None
        self.mode = kind
        self._start(kind, arg)

    def _start(self, kind: str, arg: float) -> None:
        ax = self.axis
        v_lim = self.v_max if kind == MOVE else max(self.v_max, abs(arg))
        try:
            if ax.variable("max_vel") != v_lim:
                ax.set_vel(v_lim)
            if kind == MOVE:
                ax.move_abs(arg)
            else:
                ax.move_vel(arg)
        except AxisCommandError as exc:
            raise GdlFault(f"{self.obj.name}: machine axis {ax.axis_id}: {exc}") from None

    def on_write(self, rts: RtsView, keyword: str, element: int, value: object) -> None:
        if keyword == "CONSTANT$STATUS" and value == "DISABLED":
            self.homing = False
            self.pending = None
            if self.mode is not None and self.axis.enabled:
                halt_at_once(self.axis)
            self.mode = None
            self.velocity = 0.0
            rts.write(self.obj, "SPEED", 0, 0, rts.origin())
            rts.write(self.obj, "OPERATING$CONDITION", 0, "STOPPED", rts.origin())

    # ------------------------------------------------------------ the cycle

    def update(self, rts: RtsView) -> None:
        ax = self.axis
        if self.pending is not None and ax.enabled and not ax.stopping:
            kind, arg = self.pending
            self.pending = None
            self.mode = kind
            try:
                self._start(kind, arg)
            except GdlFault:
                self._fault(rts)
                return
        if self.mode is None:
            return
        if not ax.enabled:
            if self.pending is None or ax.error_stop:
                self._fault(rts)
            return
        p = ax.ref_pos
        if self.mode == MOVE and self.pending is None:
            done = p == self.target
        elif self.mode == STOP:
            done = p == ax.variable("pg_pos_cmd")
        else:
            done = False
        self.position = p
        self.velocity = 0.0 if done else ax.ref_vel
        if self.homing and self.home is not None:
            rts.device(self.home).update(rts)
            if rts.read(self.home, "STATUS", 0):
                halt_at_once(ax)
                self.homing = False
                self.mode = None
                self.velocity = 0.0
                self.offset = p
                rts.write(self.obj, "HOMED", 0, True, "update")
        rts.write(self.obj, "SPEED", 0, round(self.velocity), "update")
        if self.obj.type.state("POSITION") is not None:
            rts.write(self.obj, "POSITION", 0, round(p - self.offset), "update")
        if done:
            self.mode = None if self.pending is None else self.pending[0]
        if self.mode is None:
            rts.write(self.obj, "OPERATING$CONDITION", 0, "STOPPED", "update")

    def _fault(self, rts: RtsView) -> None:
        """The axis left Operation Enabled on its own: the motor is stopped and faulty."""
        self.mode = None
        self.pending = None
        self.homing = False
        self.position = self.axis.ref_pos
        self.velocity = 0.0
        rts.write(self.obj, "SPEED", 0, 0, "update")
        rts.write(self.obj, "DIAGN$STATUS", 0, "FAULT", "update")
        rts.write(self.obj, "OPERATING$CONDITION", 0, "STOPPED", "update")

    @property
    def busy(self) -> bool:
        return self.mode is not None

    @property
    def transient(self) -> bool:
        if self.mode is None:
            return False
        if self.mode != JOG or self.pending is not None or self.homing:
            return True
        return not self.axis.cruising
