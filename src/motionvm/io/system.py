"""The controller's I/O system: its GPIO, the EtherCAT slaves, the plant wiring and
sensors, AO bindings, the E-stop input; a cycle client of the controller.

`IOSystem(config, motion, cycle_time)` builds, from the machine's `IOConfig`:
- `gpio`, the controller's `DigitalIO` (io/gpio.py);
- `bus`, every slave (io/slaves.py): the axes' drives, then the I/O slaves; it tells
  the motion kernel how many I/O slaves follow the drives (`extra_slaves`), so that
  GetSlaveNum and GetSlvECATSt count them;
- the wires and sensors (io/wiring.py);
- each I/O slave's CoE object dictionary (io/slave_objects.py), added to the motion
  kernel's `slaves` after the drives' (ReadSDO ... ReleasePDO use the same slave ids);
  `end_cycle` applies the forced PDO values after the cycle's writes.

Each cycle (runtime/clients.py): `begin_cycle` delivers the wires' due changes and
updates the sensors (the inputs are latched before the tasks run); `end_cycle` updates
the analog outputs bound to controller variables (manual 10.4) and samples the wires'
outputs. Idle I/O costs nothing per cycle: with no wire, sensor, binding or I/O slave
the controller calls neither (`has_work`; `rebind` tells it when the bindings change).
`next_event` is the earliest pending wire change; the run goes on (`busy`) while a
change is on its way through a wire.

Channels by name (`channel(name)`: the scope, a scenario, the host API):
`gpiN`, `gpoN`, `slvS.diK`, `slvS.doK`, `slvS.aiK`, `slvS.aoK` (`slvS.sM.diK`: slot M),
`slvS.state` (EtherCAT state). Inputs are written at the pin, outputs as a program
writes them; a digital channel takes what `bit_of` reads as 0 or 1. The E-stop (rising edge of the bound input) disables every axis
(`MotionKernel.estop`) and calls the handlers given to `on_estop` (a language run
side stops its tasks).
A lost slave (`lose_slave`) leaves Operation for good: it reports Init, its outputs
drop to 0 at the pins, its inputs keep their last value, and a drive's axis faults.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable

from motionvm.io.analog import (
    AXIS_SHIFT,
    AXIS_VARIABLES,
    raw_of_word,
    value_of_word,
    word_of_raw,
    word_of_typed_raw,
    word_of_value,
)
from motionvm.io.config import DEFAULT_IO, Endpoint, IOConfig, parse_endpoint
from motionvm.io.gpio import DigitalIO, call_estop_handlers
from motionvm.io.slave_objects import build as build_slave_objects
from motionvm.io.slaves import DRIVE, Module, Slave, SlaveBus
from motionvm.io.wiring import Sensor, Wire, delay_cycles
from motionvm.runtime.clients import PassiveClient


def bit_of(value: object) -> int:
    """A digital channel's value [0 or 1] as a scenario or the host gives it: a boolean,
    ON or OFF (any case), or a finite number (0 is 0, any other 1). ValueError for
    anything else: the text '0' or 'off' is not read by its truth (it would be 1)."""
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, str) and value.upper() in ("ON", "OFF"):
        return 1 if value.upper() == "ON" else 0
    if isinstance(value, int | float) and math.isfinite(value):
        return 1 if value else 0
    raise ValueError(f"a digital value is 0 or 1, true/false or ON/OFF, not {value!r}")


class IOSystem(PassiveClient):
    """The machine's I/O (see the module docstring)."""

    def __init__(self, config: IOConfig | None, motion, cycle_time: float) -> None:
        config = config or DEFAULT_IO
        self.config = config
        self.motion = motion
        self.cycle_time = cycle_time
        self.gpio = DigitalIO(config.n_inputs, config.n_outputs)
        self.gpio.estop_input = config.estop_input
        self.gpio.on_estop(self._estop)
        slaves = [
            Slave(i, DRIVE, [Module.create(config.drive_inputs, config.drive_outputs)], axis=i)
            for i in range(motion.n_axes)
        ]
        for spec in config.slaves:
            modules = [Module.create(*counts, bits=spec.bits) for counts in spec.modules]
            slaves.append(Slave(len(slaves), spec.kind, modules, spec.name))
        self.bus = SlaveBus(slaves)
        self._digital_modules = [m for s in slaves for m in s.modules if m.inputs or m.outputs]
        """The modules with digital channels (`digital_signature`; the bus is fixed)."""
        motion.extra_slaves = len(config.slaves)
        self.slave_objects = self._attach_objects()
        """The I/O slaves' object dictionaries (io/slave_objects.py), in bus order."""
        self._estop_handlers: list = []
        """Called with the input number after an E-stop input disabled the axes."""
        self.var_readers: list[Callable[[int], float | None]] = [self._axis_variable]
        """Readers of controller variables by id for AO bindings (10.4): the first that
        does not return None wins."""
        self._acc_prev: dict[int, tuple[float, float]] = {}
        self.wires = [self._wire(w) for w in config.wires]
        self.sensors = [
            Sensor(motion.axes[s.axis], s.lo, s.hi, s.invert, self._writer(s.target))
            for s in config.sensors
        ]
        self.bound: list[tuple[Module, int]] = []
        """Analog outputs bound to a controller variable, updated each cycle."""
        self.cycle = 0

    # ---- cycle ------------------------------------------------------------------------

    @property
    def observes_motion(self) -> bool:
        """Sensors and analog outputs bound to axis variables read the axes each cycle
        (wires carry outputs, which only tasks change)."""
        return bool(self.sensors or self.bound)

    def digital_signature(self) -> tuple:
        """The digital channels of every slave (inputs, then outputs, module by module):
        what a task's wait on GetSlvGPI/GetSlvGPO reads (equal signatures, equal answers)."""
        return tuple([(*m.inputs, -1, *m.outputs) for m in self._digital_modules])

    def has_work(self, hook: str) -> bool:
        """Whether `hook` has anything to do (runtime/clients.py): `begin_cycle` with a
        wire or a sensor, `end_cycle` with a bound output, an I/O slave (its forced PDOs)
        or a wire. Only the bindings change after the start (`rebind`)."""
        if hook == "begin_cycle":
            return bool(self.wires or self.sensors)
        return bool(self.bound or self.slave_objects or self.wires)

    def begin_cycle(self) -> None:
        if self.wires:
            cycle = self.motion_cycle()
            for w in self.wires:
                if w.pending:
                    w.deliver(cycle)
        for s in self.sensors:
            s.update()

    def end_cycle(self) -> None:
        for module, k in self.bound:
            self._update_binding(module, k)
        for objects in self.slave_objects:
            if objects.forced:  # ForceWritePDO wins over this cycle's writes
                objects.apply_forced()
        if self.wires:
            cycle = self.motion_cycle()
            for w in self.wires:
                w.sample(cycle)

    def busy(self) -> bool:
        """True while a change is on its way through a delayed wire."""
        for w in self.wires:
            if w.pending:
                return True
        return False

    def still_running(self) -> list:
        from motionvm.runtime.waits import Waiting

        return [
            Waiting(f"wire {spec.source.text} -> {spec.target.text}", why="a change on its way")
            for w, spec in zip(self.wires, self.config.wires)
            if w.pending
        ]

    def next_event(self) -> int | None:
        cycle = self.motion_cycle()
        wake = None
        for w in self.wires:
            due = w.next_due(cycle)
            if due is not None and (wake is None or due < wake):
                wake = due
        for s in self.sensors:
            if s.changed():
                return cycle
        return wake

    def motion_cycle(self) -> int:
        """The controller's current cycle (the clock is attached by the controller)."""
        return self.clock.cycle if self.clock is not None else 0

    clock = None
    """The controller's clock (`runtime.clock.Clock`), set by the controller."""

    def _attach_objects(self) -> list:
        """Give every slave its object dictionary: a drive its own, an I/O slave one of
        io/slave_objects.py, registered after the drives so its SDO slave id is its
        slave id."""
        out = []
        for slave in self.bus.slaves:
            if slave.axis is not None:
                slave.objects = self.motion.slaves.get(slave.slave_id)
                continue
            objects = build_slave_objects(slave)
            if self.motion.slaves.add(objects) != slave.slave_id:
                raise RuntimeError(f"slave {slave.slave_id}: its objects got another id")
            slave.objects = objects
            out.append(objects)
        return out

    # ---- E-stop and faults ----------------------------------------------------------

    def _estop(self, n: int) -> None:
        self.estop(n)

    def estop(self, n: int = 0) -> None:
        """The E-stop (from input `n`, 0: another source): disable every axis, then tell
        the handlers (`on_estop`)."""
        self.motion.estop()
        call_estop_handlers(self._estop_handlers, n)

    def on_estop(self, handler: Callable[[int], None]) -> None:
        """Call the bound method `handler(n)` (held weakly) after an E-stop input n
        disabled the axes: a language's run side stops its tasks."""
        self._estop_handlers.append(weakref.WeakMethod(handler))  # type: ignore[arg-type]

    def lose_slave(self, slave_id: int) -> None:
        """Slave `slave_id` leaves the bus (see the module docstring)."""
        slave = self.bus.get(slave_id)
        if slave is None or not slave.online:
            return
        slave.online = False
        self.motion.lost_slaves.add(slave_id)
        if slave.axis is not None:
            self.motion.lose_drive(slave.axis)

    # ---- channels by name -----------------------------------------------------------

    def endpoint_module(self, ep: Endpoint) -> tuple[Slave, Module] | None:
        slave = self.bus.get(ep.slave if ep.slave is not None else -1)
        if slave is None:
            return None
        module = slave.module(ep.slot)
        return None if module is None else (slave, module)

    def _reader(self, ep: Endpoint) -> Callable[[], int]:
        """The pin level of a digital output endpoint; the raw value of an analog one, as
        GetSlvAORaw reads it (two's complement on an HMPL_DAC_SIGNED channel)."""
        gpio = self.gpio
        if ep.kind == "gpo":
            return lambda: gpio.output_pin(ep.channel)
        slave, module = self.endpoint_module(ep)  # type: ignore[misc]
        i = ep.channel - 1
        if ep.kind == "do":
            outputs = module.outputs
            return lambda: outputs[i] if slave.online else 0
        words, types, bits = module.ao, module.ao_type, module.bits
        return lambda: raw_of_word(words[i], bits, types[i]) if slave.online else 0

    def _writer(self, ep: Endpoint) -> Callable[[int], None]:
        """Drive the pin of a digital input endpoint; the word of an analog one from a raw
        value, clamped to the raw values the input's type holds."""
        gpio = self.gpio
        if ep.kind == "gpi":
            n = ep.channel
            return lambda v: gpio.set_input(n, v)
        slave, module = self.endpoint_module(ep)  # type: ignore[misc]
        i = ep.channel - 1
        if ep.kind == "di":
            values = module.inputs

            def write_di(v: int) -> None:
                if slave.online:
                    values[i] = 1 if v else 0

            return write_di
        words, types, bits = module.ai, module.ai_type, module.bits

        def write_ai(v: int) -> None:  # a raw value, as GetSlvAIRaw is to read it
            if slave.online:
                words[i] = word_of_typed_raw(int(v), bits, types[i])

        return write_ai

    def _wire(self, spec) -> Wire:
        return Wire(
            self._reader(spec.source),
            self._writer(spec.target),
            delay_cycles(spec.delay_ms, self.cycle_time),
            spec.source.is_analog,
            spec.gain,
            spec.offset,
        )

    def channel(
        self, name: str
    ) -> tuple[Callable[[], float], Callable[[object], None] | None] | None:
        """(read, write) of a channel name, or None if it names no channel of this machine;
        `write` is None for a read-only channel (`slvS.state`)."""
        if name.startswith("slv") and name.endswith(".state"):
            try:
                sid = int(name[3:-6])
            except ValueError:
                return None
            if self.bus.get(sid) is None:
                return None
            return (lambda: self.motion.slave_state(sid)), None
        ep = parse_endpoint(name)
        if ep is None:
            return None
        gpio = self.gpio
        if ep.kind == "gpi":
            if not gpio.has_input(ep.channel):
                return None
            return (lambda: gpio.input(ep.channel)), (
                lambda v: gpio.set_input(ep.channel, bit_of(v))
            )
        if ep.kind == "gpo":
            if not gpio.has_output(ep.channel):
                return None
            return (lambda: gpio.output(ep.channel)), (
                lambda v: gpio.set_output(ep.channel, bit_of(v))
            )
        found = self.endpoint_module(ep)
        if found is None:
            return None
        slave, module = found
        values = {"di": module.inputs, "do": module.outputs, "ai": module.ai, "ao": module.ao}[
            ep.kind
        ]
        i = ep.channel - 1
        if not 0 <= i < len(values):
            return None
        if ep.kind in ("di", "do"):

            def set_bit(v: object) -> None:
                values[i] = bit_of(v)

            return (lambda: values[i]), set_bit
        bits = module.bits

        def set_word(v: object) -> None:
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise ValueError(f"{name} takes a raw value (an integer), not {v!r}")
            values[i] = word_of_raw(int(round(v)), bits)

        return (lambda: values[i]), set_word

    def channel_names(self) -> list[str]:
        out = [f"gpi{n}" for n in range(1, self.gpio.n_inputs + 1)]
        out += [f"gpo{n}" for n in range(1, self.gpio.n_outputs + 1)]
        for slave in self.bus.slaves:
            out.append(f"slv{slave.slave_id}.state")
            for m, module in enumerate(slave.modules, 1):
                pre = f"slv{slave.slave_id}." + (f"s{m}." if len(slave.modules) > 1 else "")
                for kind, values in (("di", module.inputs), ("do", module.outputs),
                                     ("ai", module.ai), ("ao", module.ao)):  # fmt: skip
                    out += [f"{pre}{kind}{k}" for k in range(1, len(values) + 1)]
        return out

    # ---- AO bindings (manual 10.4) --------------------------------------------------

    def rebind(self) -> None:
        """Recompute the list of bound outputs after SetSlvAOMonitor/SetSlvAOParam."""
        self.bound = [
            (module, k)
            for slave in self.bus.slaves
            for module in slave.modules
            for k, b in enumerate(module.ao_bind)
            if b.enabled and b.var_id >= 0
        ]
        self.work_changed()

    def read_variable(self, var_id: int) -> float | None:
        for reader in self.var_readers:
            value = reader(var_id)
            if value is not None:
                return value
        return None

    def _update_binding(self, module: Module, k: int) -> None:
        b = module.ao_bind[k]
        value = self.read_variable(b.var_id)
        if value is None:
            return
        module.ao[k] = word_of_value(value * b.scale + b.offset, module.bits, module.ao_type[k])

    def _axis_variable(self, var_id: int) -> float | None:
        """HMPL_AXIS_n | HMPL_REF_POS ... HMPL_CUR_FB (io/analog.py AXIS_VARIABLES)."""
        axis_id, var = divmod(var_id, 1 << AXIS_SHIFT)
        name = AXIS_VARIABLES.get(var)
        axis = self.motion.axis(axis_id)
        if name is None or axis is None:
            return None
        if name == "acc_fb":  # the change of the velocity feedback over the last cycle
            vel = axis.variable("vel_fb")
            cycle = self.motion_cycle()
            last = self._acc_prev.get(axis_id)
            self._acc_prev[axis_id] = (cycle, vel)
            if last is None or last[0] != cycle - 1:
                return 0.0
            return (vel - last[1]) / self.cycle_time
        return float(axis.variable(name))

    def converted(self, module: Module, k: int, output: bool) -> float:
        words, types = (module.ao, module.ao_type) if output else (module.ai, module.ai_type)
        return value_of_word(words[k], module.bits, types[k])
