"""A simulated CiA 402 servo drive behind an object dictionary, stepped once per cycle.

The master (the controller) writes the RxPDO objects (controlword 0x6040, modes of
operation 0x6060, target position/velocity/torque) with `write`, calls `step(dt)` once
per bus cycle, and reads the TxPDO objects (statusword 0x6041, actual values, digital
inputs) with `read`. Objects are plain attributes too, for the cyclic master.

Power drive state machine (CiA 402 figure "state machine", transitions 0-16):

    Not ready to switch on --(boot_cycles)--> Switch on disabled --shutdown--> Ready to
    switch on --switch on (switch_on_cycles)--> Switched on --enable operation
    (enable_cycles)--> Operation enabled --quick stop--> Quick stop active; any fault
    --> Fault reaction active --(stopped)--> Fault --fault reset rising edge--> Switch
    on disabled. Disable voltage, shutdown and disable operation go back as specified.

A transition with a delay happens when its command has been present for that many
consecutive steps (a real drive closes its main contactor, releases the brake ...).
Modes: 8 CSP, 9 CSV, 10 CST; 6 (homing) is accepted and holds the position, the homing
itself being the master's job. Quick stop and the fault reaction ramp the speed down at
0x6085 [counts/s^2]; an encoder loss disables at once. Positions are int32 counts that
wrap; the drive unwraps the target so a move through the wrap point is continuous.
"""

from __future__ import annotations

import math

from motionvm.drives import drive_objects
from motionvm.drives import mechanics as mech_models
from motionvm.drives import objects as od
from motionvm.drives.objects import Command, State, decode_command, wrap_i32
from motionvm.drives.sensors import Sensors

_SETTLED = (  # states left only by a new command
    State.SWITCH_ON_DISABLED, State.READY_TO_SWITCH_ON, State.SWITCHED_ON, State.OPERATION_ENABLED
)  # fmt: skip
_CYCLIC_MODES = (od.MODE_CSP, od.MODE_CSV, od.MODE_CST)
_SW_BASE = {
    s.value: s.value
    | (0 if s is State.NOT_READY_TO_SWITCH_ON else od.SW_VOLTAGE_ENABLED | od.SW_REMOTE)
    for s in State
}
_OFF = (Command.DISABLE_VOLTAGE, Command.QUICK_STOP)
# an enum member read from its class costs a lookup through the metaclass each time
_OPERATION_ENABLED = State.OPERATION_ENABLED
_QUICK_STOP_ACTIVE = State.QUICK_STOP_ACTIVE
_SW_OPERATION_ENABLED = _SW_BASE[State.OPERATION_ENABLED.value]
_SW_CYCLIC = _SW_OPERATION_ENABLED | od.SW_FOLLOWS_TARGET
# under local control: Operation enabled, the controlword not processed (no remote bit)
_SW_LOCAL = _SW_OPERATION_ENABLED & ~od.SW_REMOTE
_CSP = od.MODE_CSP
_ERR_FOLLOWING = od.ERR_FOLLOWING
_CW_ENABLE = 0x0F
"""The controlword of Operation enabled (enable operation)."""
_INT32 = 2.0**31 - 2.0
"""Counts [counts] beyond which the int32 target or position could wrap."""

# `_round(x)` is round(x) of a float: its method in pure Python (no built-in's lookup);
# the compiled build's cia402.pxd defines it as C's rint (the same integer, no Python
# object), a name an assignment here cannot make (Cython refuses to assign a name the
# .pxd declares), so the module's namespace gets it.
globals()["_round"] = float.__round__
_TWO_31, _MASK_32 = 0x80000000, 0xFFFFFFFF
"""An int32 wraps as ((n + _TWO_31) & _MASK_32) - _TWO_31 (C long longs when compiled,
where the literals would be Python ints)."""


class Cia402Drive:
    """One servo drive: object dictionary, power state machine, modes, mechanics, sensors."""

    __slots__ = (  # the object dictionary and the drive's state, all set up in __init__
        "_controlword_prev", "_csp_ready", "_demand", "_encoder", "_encoder_lost", "_fault",
        "_fe_checked", "_fe_window", "_following_error", "_forced", "_limit_lazy",
        "_max_torque", "_mode_prev", "_motor_position_prev", "_on_change", "_per_mille_per_nm",
        "_position_demand",
        "_ramp_vel", "_settled", "_stopped", "_target_prev", "_timer", "_torque_actual",
        "_torque_quiet_neg_nm", "_torque_quiet_nm", "_velocity_actual", "boot_cycles",
        "controlword", "device_type", "digital_inputs", "digital_output_mask",
        "digital_outputs", "enable_cycles", "error_code", "local_demand", "mechanics",
        "mode", "mode_display", "objects", "position_actual", "pt_sample_rate",
        "quick_stop_decel", "quick_stop_option", "rated_torque", "rated_torque_nm",
        "sensors", "state", "statusword_base", "supported_modes", "switch_on_cycles",
        "target_position", "target_torque", "target_velocity", "__weakref__"
    )  # fmt: skip

    KEYS = frozenset({
        "mechanics", "boot_cycles", "switch_on_cycles", "enable_cycles", "rated_torque",
        "max_torque", "quick_stop_decel", "quick_stop_option", "following_error_window",
        "position", "negative_limit", "positive_limit", "home_low", "home_high",
        "index_spacing", "index_offset", "rxpdo", "txpdo", "pt_sample_rate",
    })  # fmt: skip

    def __init__(
        self,
        mechanics=None,
        sensors: Sensors | None = None,
        *,
        boot_cycles: int = 2,
        switch_on_cycles: int = 2,
        enable_cycles: int = 4,
        rated_torque: float = 1.0,
        max_torque: int = 3000,
        quick_stop_decel: int = 10_000_000,
        quick_stop_option: int = 2,
        following_error_window: int = 0xFFFFFFFF,
        position: float = 0.0,
        pdo: dict | None = None,
        pt_sample_rate: float = 16000.0,
    ):
        """Delays in steps; `rated_torque` [N*m]; `max_torque` [per mille of rated];
        `quick_stop_decel` [counts/s^2]; `position` the motor's start position [counts];
        `pdo` the `rxpdo`/`txpdo` mapping (drives/drive_objects.py); `pt_sample_rate`
        [Hz] how often the position trigger samples the position (manual 12.1.1)."""
        self.mechanics = mechanics or mech_models.IdealMechanics()
        self.sensors = sensors or Sensors()
        self.boot_cycles = boot_cycles
        self.switch_on_cycles = switch_on_cycles
        self.enable_cycles = enable_cycles
        self.rated_torque_nm = rated_torque
        self._per_mille_per_nm = 1000.0 / rated_torque
        # objects (attribute names as in objects.DICTIONARY)
        self.device_type = 0x00020192
        self.supported_modes = od.SUPPORTED_MODES_VALUE
        self.rated_torque = round(rated_torque * 1000.0)  # [mN*m]
        self.statusword = 0
        self.max_torque = max_torque
        self.quick_stop_decel = quick_stop_decel
        self.quick_stop_option = quick_stop_option
        self.following_error_window = following_error_window
        self.controlword = 0
        self.mode = 0
        self.mode_display = 0
        self.target_position = 0
        self.target_velocity = 0
        self.target_torque = 0
        self.error_code = od.ERR_NONE
        self.state = State.NOT_READY_TO_SWITCH_ON
        """The power drive state (what the statusword shows)."""
        self._controlword_prev = 0
        self._csp_ready = False
        """True if the last step was the common one (see `step`) and nothing since then
        (a fault, local control) keeps the next from being it too, under the same
        controlword and mode."""
        self._settled: State | None = None
        self._timer = 0
        self._fault: int | None = None
        self._on_change = None
        self._encoder_lost = False
        self._ramp_vel = 0.0
        self._stopped = False
        self._demand = 0.0
        """Position demand [counts], unwrapped (no int32 turn is ever added)."""
        self._target_prev = 0
        self._mode_prev = 0
        self.local_demand: float | None = None
        """The position demand [counts, unwrapped] of the drive's own firmware under local
        control (`follow_local_demand`); None while the master commands the drive."""
        self.mechanics.set_position(position)
        self._motor_position_prev = float(position)
        """Motor position [counts] at the end of the last cycle (for the sensors)."""
        self._encoder = round(position)
        """Encoder count, unwrapped."""
        self.position_actual = wrap_i32(self._encoder)
        self.position_demand = self.position_actual
        self.velocity_actual = 0
        self.torque_actual = 0
        self.following_error = 0
        self.digital_inputs = self.sensors.update(
            self._motor_position_prev, self._motor_position_prev
        )
        self.statusword = _SW_BASE[self.state._value_]
        self.digital_outputs = 0
        """0x60FE:1, the drive's physical outputs."""
        self.digital_output_mask = 0
        """0x60FE:2, which of them the master drives."""
        self.pt_sample_rate = pt_sample_rate
        self.objects = drive_objects.build(self, pdo)
        """The object dictionary: SDO and PDO access (drives/dictionary.py)."""
        self._forced = self.objects.forced  # the same dict: ForceWritePDO fills it

    @classmethod
    def create(cls, config: dict) -> Cia402Drive:
        """Build a drive from a config table; bad keys and values are named in the error."""
        cfg = mech_models.Config(config, "drive", cls.KEYS)
        mech_config = config.get("mechanics", {"model": "ideal"})
        mechanics = mech_models.create(mech_config)
        sensors = Sensors.from_config(cfg)
        option = cfg.integer("quick_stop_option", 2, 0)
        if option > 8:
            raise ValueError(f"drive: quick_stop_option = {option!r} is not in 0..8")
        return cls(
            mechanics,
            sensors,
            boot_cycles=cfg.integer("boot_cycles", 2, 1),
            switch_on_cycles=cfg.integer("switch_on_cycles", 2, 1),
            enable_cycles=cfg.integer("enable_cycles", 4, 1),
            rated_torque=cfg.number("rated_torque", 1.0),
            max_torque=cfg.integer("max_torque", 3000, 0),
            quick_stop_decel=cfg.integer("quick_stop_decel", 10_000_000, 1),
            quick_stop_option=option,
            following_error_window=cfg.integer("following_error_window", 0xFFFFFFFF, 0),
            position=cfg.number("position", 0.0, low=-(2.0**31), strict=False, high=2.0**31),
            pdo={k: config[k] for k in ("rxpdo", "txpdo") if k in config},
            pt_sample_rate=cfg.number("pt_sample_rate", 16000.0, high=1e9),
        )

    # ---- SDO-style access -----------------------------------------------------------

    def read(self, index: int, subindex: int = 0) -> int | str:
        """Value of object `index`:`subindex` (`objects`); SdoAbort if there is none."""
        return self.objects.read(index, subindex)

    def write(self, index: int, subindex: int, value: int) -> None:
        """Write object `index`:`subindex`; refused (SdoAbort) if read-only or out of range."""
        self.objects.write(index, subindex, value)

    # touch probe objects live in the sensors
    tp_function = property(lambda self: self.sensors.tp_function,
                           lambda self, v: setattr(self.sensors, "tp_function", v))  # fmt: skip
    tp_status = property(lambda self: self.sensors.tp_status)
    tp1_positive_edge = property(lambda self: self.sensors.latched[0])
    tp1_negative_edge = property(lambda self: self.sensors.latched[1])
    tp2_positive_edge = property(lambda self: self.sensors.latched[2])
    tp2_negative_edge = property(lambda self: self.sensors.latched[3])

    # Four TxPDO objects that follow, in Operation enabled, from the state the last step
    # left (the mechanics, the demand and the encoder count, which only a step changes):
    # they are computed when read, so the cycle does not round them unless someone reads
    # them. In every other state the step stores them.

    @property
    def velocity_actual(self) -> int:
        """0x606C [counts/s]."""
        if self.state is _OPERATION_ENABLED:
            return wrap_i32(round(self.mechanics.velocity))
        return self._velocity_actual

    @velocity_actual.setter
    def velocity_actual(self, value: int) -> None:
        self._velocity_actual = value

    @property
    def torque_actual(self) -> int:
        """0x6077 [per mille of the rated torque]."""
        if self.state is _OPERATION_ENABLED:
            t = round(self.mechanics.torque * self._per_mille_per_nm)
            return t if -32768 <= t <= 32767 else max(-32768, min(32767, t))
        return self._torque_actual

    @torque_actual.setter
    def torque_actual(self, value: int) -> None:
        self._torque_actual = value

    @property
    def position_demand(self) -> int:
        """0x6062 [counts]."""
        if self.state is _OPERATION_ENABLED:
            return wrap_i32(round(self._demand))
        return self._position_demand

    @position_demand.setter
    def position_demand(self, value: int) -> None:
        self._position_demand = value

    @property
    def following_error(self) -> int:
        """0x60F4 [counts]: demand minus actual position."""
        if self.state is _OPERATION_ENABLED:
            return wrap_i32(round(self._demand) - self._encoder)
        return self._following_error

    @following_error.setter
    def following_error(self, value: int) -> None:
        self._following_error = value

    @property
    def statusword(self) -> int:
        """0x6041. After a step that ended in Operation enabled, its internal limit bit
        (11) follows from the state that step left, as the four objects above: it is
        computed when read, from the motor's torque. `statusword_base` is the rest."""
        sw = self.statusword_base
        if self._limit_lazy:
            torque = self.mechanics.torque
            if (torque >= self._torque_quiet_nm or torque <= self._torque_quiet_neg_nm) and abs(
                self.torque_actual
            ) >= self._max_torque:
                sw |= od.SW_INTERNAL_LIMIT
        return sw

    @statusword.setter
    def statusword(self, value: int) -> None:
        """The whole statusword, internal limit bit included."""
        self.statusword_base = value
        self._limit_lazy = False

    @property
    def following_error_window(self) -> int:
        """0x6065 [counts]: a CSP following error beyond it faults the drive (0x8611)."""
        return self._fe_window

    @following_error_window.setter
    def following_error_window(self, value: int) -> None:
        self._fe_window = value
        # a window of 2**31 or more exceeds any int32 error: no check
        self._fe_checked = value < 0x80000000

    @property
    def max_torque(self) -> int:
        """0x6072 [per mille of the rated torque]: the internal limit bit's threshold."""
        return self._max_torque

    @max_torque.setter
    def max_torque(self, value: int) -> None:
        if self._limit_lazy and value != self._max_torque:
            # the statusword keeps the internal limit bit of the last step's limit
            self.statusword = self.statusword
            self._csp_ready = False  # the next step goes through `_prepare`
        self._max_torque = value
        # below this torque [N*m] the rounded torque actual stays under the limit: a
        # margin far above the rounding of torque * per mille per N*m
        if value <= 0:
            self._torque_quiet_nm = math.inf
        else:
            self._torque_quiet_nm = (value - 1) / self._per_mille_per_nm * (1.0 - 1e-9)
        self._torque_quiet_neg_nm = -self._torque_quiet_nm

    @property
    def settled(self) -> bool:
        """True if the last controlword has done all it does in this state (no delay
        runs): repeating it leaves the state as it is, unless a fault is raised."""
        return self._settled is self.state

    @property
    def pending_fault(self) -> int | None:
        """The error code of a fault raised and not yet reset, or None."""
        return self._fault

    # ---- faults for tests -----------------------------------------------------------

    def inject_fault(self, code: int = od.ERR_GENERIC) -> None:
        """Raise a drive fault with error code `code`: fault reaction, then Fault."""
        self._raise_fault(code)
        if self._on_change is not None:
            self._on_change()

    def _raise_fault(self, code: int) -> None:
        if self._fault is None:
            self._fault = code
            self._csp_ready = False  # the next step runs the state machine

    @property
    def on_change(self):
        """Called (no arguments) when something other than a step changes what the drive
        will do: a write of its object dictionary (SDO, PDO, forcing), a fault injected,
        its sensors' external inputs, touch probe function or switches written. The master's
        cyclic writes of the controlword and the targets do not call it. The owner sets
        it (the motion kernel: the axis wakes from rest)."""
        return self._on_change

    @on_change.setter
    def on_change(self, fn) -> None:
        self._on_change = self.objects.on_write = self.sensors.on_change = fn

    def encoder_loss(self) -> None:
        """Lose the encoder: the actual position freezes and the drive faults (0x7305)."""
        self._encoder_lost = True
        self.inject_fault(od.ERR_ENCODER)

    def encoder_restore(self) -> None:
        """Reconnect the encoder; a fault reset can then clear the fault."""
        self._encoder_lost = False

    # ---- local control: a program on the drive commands the motor ----------------------

    def follow_local_demand(self, counts: float | None) -> None:
        """Local control: from the next `step` on the motor follows `counts` [counts,
        unwrapped], a demand generated on the drive itself (a program running on it), as
        in CSP: reached linearly over the step. Call it again with every new demand.

        Under local control the drive shows Operation enabled without the statusword's
        remote bit (9, CiA 402: the controlword is not processed) and ignores the master's
        controlword and targets; position_demand (0x6062) is the local demand. None hands
        the drive back to the master, in Switch on disabled.
        """
        self._csp_ready = False  # the next step goes through `_prepare`
        if counts is None:
            if self.local_demand is not None:
                self.local_demand = None
                self.state = State.SWITCH_ON_DISABLED
                self._settled = None
                self._demand = self.mechanics.position
                self.statusword = self._feedback_off(self.state, self._encoder)
            return
        if self.local_demand is None:
            self.state = _OPERATION_ENABLED
            self._settled = None
        self.local_demand = float(counts)

    # ---- the cycle ------------------------------------------------------------------

    def step(self, dt: float) -> None:
        """Advance one bus cycle of `dt` [s]: state machine, motion, feedback objects.

        The common cycle, Operation enabled in CSP under a settled controlword that is
        repeated, is known from one flag (`_csp_ready`, set by the cycle before) and two
        comparisons; its motion is the demand following the target's change. Every other
        cycle goes through `_prepare` (state machine, local control, the other modes).
        Two checks are skipped where their outcome is known: the sensors while the
        motor stays in their quiet interval, the following error where its window
        exceeds any int32 error; in Operation enabled the internal limit bit is left to
        `statusword` (computed when read). Under local control (`follow_local_demand`)
        the motor follows the drive's own demand as in CSP and the master's controlword
        and targets are not processed."""
        if self._forced:  # ForceWritePDO: forced outputs win over the master's
            self.objects.apply_forced()
        if self._csp_ready and self.controlword == self._controlword_prev and self.mode == _CSP:
            sw = None
            state = _OPERATION_ENABLED
        else:
            sw = self._prepare(dt)
            state = self.state
            self._limit_lazy = True  # if the step ends in Operation enabled (see `statusword`)
        if sw is None:  # CSP in Operation enabled: the demand follows the target
            target = self.target_position
            change = target - self._target_prev
            if change > 0x7FFFFFFF or change < -0x80000000:  # beyond int32: the target wrapped
                change = ((change + _TWO_31) & _MASK_32) - _TWO_31
            self._demand = demand = self._demand + change
            self._target_prev = target
            x = self.mechanics.step_position(demand, dt)
            sw = _SW_CYCLIC
        else:
            x = self.mechanics.position
        # feedback
        if self._encoder_lost:
            enc = self._encoder
        else:
            self._encoder = enc = _round(x)  # noqa: F821
            if enc > 0x7FFFFFFF or enc < -0x80000000:  # beyond int32: the counter wraps
                self.position_actual = ((enc + _TWO_31) & _MASK_32) - _TWO_31
            else:
                self.position_actual = enc
        s = self.sensors
        # the sensors' last update ended at _motor_position_prev (the drive is their
        # only caller), so that position lies in their quiet interval if it is not empty
        if s.quiet_low < x < s.quiet_high:
            self.digital_inputs = s.quiet_inputs
        elif s.has_switches or s._tp_function or s.tp_status:
            self.digital_inputs = s.update(self._motor_position_prev, x)
        else:
            self.digital_inputs = s._external
        self._motor_position_prev = x
        if state is not _OPERATION_ENABLED:
            self.statusword = self._feedback_off(state, enc)
            return
        if self._fe_checked and self.mode == _CSP and self.local_demand is None:
            fe = _round(self._demand) - enc  # noqa: F821
            fe = ((fe + _TWO_31) & _MASK_32) - _TWO_31
            if abs(fe) > self._fe_window:
                self._raise_fault(_ERR_FOLLOWING)  # no fault was pending in this state
                sw |= od.SW_FOLLOWING_ERROR
        self.statusword_base = sw  # `statusword` adds the internal limit bit

    # ---- closed-form advance (time skipping: motion/axis_coast.py) -------------------

    def steady(self) -> bool:
        """True if every cycle from now on is the common one of `step` (Operation enabled
        in CSP under a settled controlword that is repeated) with nothing a closed-form
        advance leaves out: no fault, no local control, no lost encoder, no forced
        outputs, no following-error check, no touch probe, and an ideal motor whose
        demands are whole counts (`IdealMechanics.holds_whole_counts`)."""
        m = self.mechanics
        if type(m) is not mech_models.IdealMechanics:
            return False
        if (self.state is not _OPERATION_ENABLED or self.mode != _CSP or self._mode_prev != _CSP
                or self.controlword != _CW_ENABLE or self._controlword_prev != _CW_ENABLE
                or self._settled is not self.state or self._fault is not None
                or self.local_demand is not None or self._encoder_lost or self._forced
                or self._fe_checked):  # fmt: skip
            return False
        s = self.sensors
        if s._tp_function or s.tp_status:
            return False
        return m.holds_whole_counts(self._demand)

    def demand_for(self, target: int) -> float:
        """The demand [counts] a steady cycle makes of `target` [counts], the next
        cycle's target: the demand follows the target's change (no wrap: `clear_of`)."""
        return self._demand + (target - self._target_prev)

    def demand_shift(self) -> float:
        """The demand minus the target [counts]: how far the motor's counts lie from the
        target's (steady: the same every cycle, as the demand follows the target's
        changes)."""
        return self._demand - self._target_prev

    def clear_of(self, t_lo: float, t_hi: float) -> bool:
        """True if targets within [t_lo, t_hi] [counts] (steady, up to their rounding)
        wrap no int32 object and move the motor into no limit switch."""
        shift = self._demand - self._target_prev
        x_lo, x_hi = t_lo + shift - 2.0, t_hi + shift + 2.0
        if not (-_INT32 < x_lo and x_hi < _INT32):
            return False  # the int32 target and position would wrap
        x = self.mechanics.position
        return self.sensors.clear_of_limits(x_lo if x_lo < x else x, x_hi if x_hi > x else x)

    def land(self, target: int, demand: float, demand_vel: float, line: list | None,
             x_1: float, x: float, v_1: float, dt: float) -> None:  # fmt: skip
        """The drive after a steady advance, as `step` leaves it: the target [counts] of
        its last cycle, the demand [counts] it made of it (velocity `demand_vel`
        [counts/s]), the motor's last cycle from x_1 to x (`IdealMechanics.land`, with
        its delay line `line`), and the feedback of that position."""
        self.target_position = target
        self._target_prev = target
        self._demand = demand
        self.mechanics.land(demand, demand_vel, line, x_1, x, v_1, dt)
        self._encoder = enc = _round(x)  # noqa: F821
        self.position_actual = enc  # (steady: no int32 wrap, `clear_of`)
        self.digital_inputs = self.sensors.update(x_1, x)
        self._motor_position_prev = x
        self.statusword_base = _SW_CYCLIC
        self._limit_lazy = True  # `statusword` adds the internal limit bit

    def _prepare(self, dt: float) -> int | None:
        """The part of a cycle other than the common one (see `step`) before the feedback:
        the state machine, local control, the motion of the other modes and states.
        Returns the statusword's mode bits, or None for CSP in Operation enabled, whose
        motion `step` makes. Sets `_csp_ready` for the next cycle: True if it is the
        common one unless the controlword or the mode change."""
        state = self.state
        mode = self.mode
        if self.local_demand is not None:  # the drive's own firmware commands the motor
            self._csp_ready = False
            self._demand = demand = self.local_demand
            self.mechanics.step_position(demand, dt)
            self.mode_display = mode
            self._settled = state  # only a new demand moves the motor again
            return _SW_LOCAL
        if (self.controlword != self._controlword_prev or state is not self._settled
                or self._fault is not None):  # fmt: skip
            state = self._power_state_machine(state)
        if state is _OPERATION_ENABLED and mode == _CSP:
            if self._mode_prev != _CSP:
                self._take_target()
                self._mode_prev = self.mode_display = _CSP
            # a later fault, local control or state change clears the flag at once
            self._csp_ready = state is self._settled and self._fault is None
            return None
        self._csp_ready = False
        self._move(state, dt)
        return _SW_CYCLIC if mode in _CYCLIC_MODES else _SW_OPERATION_ENABLED

    def _feedback_off(self, state: State, enc: int) -> int:
        """The feedback objects outside Operation enabled; returns the statusword."""
        m = self.mechanics
        if self._encoder_lost:
            self._velocity_actual = 0
        else:
            vel = round(m.velocity)
            self._velocity_actual = ((vel + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        torque = round(m.torque * self._per_mille_per_nm)
        self._torque_actual = (
            torque if -32768 <= torque <= 32767 else max(-32768, min(32767, torque))
        )
        self._position_demand = ((enc + 0x80000000) & 0xFFFFFFFF) - 0x80000000
        self._following_error = 0
        sw = _SW_BASE[state._value_]  # keyed by value: an enum member hashes slowly
        if state is _QUICK_STOP_ACTIVE and self._stopped:
            sw |= od.SW_TARGET_REACHED
        return sw

    def _power_state_machine(self, state: State) -> State:
        """One step of the power state machine from `state` under the controlword."""
        cw = self.controlword
        reset_edge = bool(cw & 0x80) and not self._controlword_prev & 0x80
        self._controlword_prev = cw
        before = state
        if self._fault is not None and state not in (
            State.FAULT_REACTION_ACTIVE, State.FAULT, State.NOT_READY_TO_SWITCH_ON
        ):  # fmt: skip
            self.error_code = self._fault
            state = self._enter_ramp(State.FAULT_REACTION_ACTIVE)
        elif state is State.NOT_READY_TO_SWITCH_ON:
            self._timer += 1
            if self._timer >= self.boot_cycles:
                state = State.SWITCH_ON_DISABLED
                self._timer = 0
        elif state is State.FAULT:
            if reset_edge and not self._encoder_lost:
                self._fault = None
                self.error_code = od.ERR_NONE
                state = State.SWITCH_ON_DISABLED
        elif state is not State.FAULT_REACTION_ACTIVE:
            state = self._transition(state, decode_command(cw))
        self.state = state
        # a command that changed nothing and waits for nothing will not act again
        settled = state is before and self._timer == 0 and state in _SETTLED
        self._settled = state if settled else None
        return state

    def _transition(self, state: State, cmd: Command | None) -> State:
        waiting = False
        if state is State.SWITCH_ON_DISABLED:
            if cmd is Command.SHUTDOWN:
                state = State.READY_TO_SWITCH_ON
        elif state is State.READY_TO_SWITCH_ON:
            if cmd in (Command.SWITCH_ON, Command.ENABLE_OPERATION):
                waiting = True
                if self._wait(self.switch_on_cycles):
                    state = State.SWITCHED_ON
            elif cmd in _OFF:
                state = State.SWITCH_ON_DISABLED
        elif state is State.SWITCHED_ON:
            if cmd is Command.ENABLE_OPERATION:
                waiting = True
                if self._wait(self.enable_cycles):
                    state = State.OPERATION_ENABLED
                    self._enter_operation()
            elif cmd is Command.SHUTDOWN:
                state = State.READY_TO_SWITCH_ON
            elif cmd in _OFF:
                state = State.SWITCH_ON_DISABLED
        elif state is State.OPERATION_ENABLED:
            if cmd is Command.SWITCH_ON:
                state = State.SWITCHED_ON
            elif cmd is Command.SHUTDOWN:
                state = State.READY_TO_SWITCH_ON
            elif cmd is Command.DISABLE_VOLTAGE:
                state = State.SWITCH_ON_DISABLED
            elif cmd is Command.QUICK_STOP:
                state = self._enter_ramp(State.QUICK_STOP_ACTIVE)
        elif state is State.QUICK_STOP_ACTIVE:
            if cmd is Command.DISABLE_VOLTAGE:
                state = State.SWITCH_ON_DISABLED
            elif cmd is Command.ENABLE_OPERATION and self.quick_stop_option >= 5:
                state = State.OPERATION_ENABLED
                self._enter_operation()
        if not waiting:
            self._timer = 0
        return state

    def _wait(self, cycles: int) -> bool:
        self._timer += 1
        if self._timer >= cycles:
            self._timer = 0
            return True
        return False

    def _enter_operation(self) -> None:
        """Start from the actual position; CSP takes over its target at the next step."""
        self._demand = self.mechanics.position
        self._mode_prev = -1

    def _take_target(self) -> None:
        """Unwrap 0x607A next to the actual position, so no wrap turn is added."""
        self._demand = float(self._encoder + wrap_i32(self.target_position - self.position_actual))
        self._target_prev = self.target_position

    def _enter_ramp(self, state: State) -> State:
        self._ramp_vel = self.mechanics.velocity
        self._demand = self.mechanics.position
        self._stopped = False
        if state is State.QUICK_STOP_ACTIVE and self.quick_stop_option == 0:
            return State.SWITCH_ON_DISABLED
        return state

    def _move(self, state: State, dt: float) -> None:
        """The motion of a cycle other than CSP in Operation enabled (see `step`)."""
        m = self.mechanics
        if state is State.OPERATION_ENABLED:
            mode = self.mode
            if mode == od.MODE_CSV:
                m.step_velocity(float(self.target_velocity), dt)
                self._demand = m.position
            elif mode == od.MODE_CST:
                limit = self.max_torque
                per_mille = max(-limit, min(limit, self.target_torque))
                m.step_torque(per_mille * self.rated_torque_nm / 1000.0, dt)
                self._demand = m.position
            else:  # no mode, or homing left to the master: hold
                if self._mode_prev in (od.MODE_CSV, od.MODE_CST):
                    self._demand = m.position
                m.step_position(self._demand, dt)
            self._mode_prev = mode
            self.mode_display = mode
        elif state in (State.QUICK_STOP_ACTIVE, State.FAULT_REACTION_ACTIVE):
            if state is State.FAULT_REACTION_ACTIVE and self._encoder_lost:
                self._stopped = True
            if not self._stopped:
                v_0 = self._ramp_vel
                dv = self.quick_stop_decel * dt
                v_1 = 0.0 if abs(v_0) <= dv else v_0 - math.copysign(dv, v_0)
                self._demand += 0.5 * (v_0 + v_1) * dt
                self._ramp_vel = v_1
                m.step_position(self._demand, dt)
                self._stopped = v_1 == 0.0
            elif state is State.QUICK_STOP_ACTIVE:
                m.step_position(self._demand, dt)
            else:
                m.step_free(dt)
            if self._stopped:
                if state is State.FAULT_REACTION_ACTIVE:
                    self.state = State.FAULT
                elif self.quick_stop_option < 5:
                    self.state = State.SWITCH_ON_DISABLED
            self.mode_display = self.mode
        else:
            m.step_free(dt)
            self._demand = m.position
            self.mode_display = self.mode
