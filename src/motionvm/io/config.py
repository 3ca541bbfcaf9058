"""The machine's I/O as the machine file describes it: `[io]`, `[[slave]]`, `[[wire]]`,
`[[sensor]]` tables -> an `IOConfig`, every bad key reported with its table and key.

```toml
[io]
inputs = 8            # controller inputs gpi1..gpi8 (default 8)
outputs = 8           # controller outputs gpo1..gpo8 (default 8)
estop_input = 8       # the input bound to the E-stop at power-on (0: none; BindEMO)
drive_inputs = 0      # general-purpose inputs and outputs of every drive slave
drive_outputs = 0     #   (GetSlvGPI(0, 1), slv0.di1; default none)

[[slave]]             # slave N (after the N drives), in file order
kind = "digital"      # inputs/outputs: channel counts; or slots = [{inputs = 8}, {outputs = 8}]
inputs = 16
outputs = 16

[[slave]]
kind = "analog"       # ai/ao: channel counts; bits: word width (default 16)
ai = 2
ao = 2
bits = 16

[[wire]]
from = "gpo3"         # an output: gpoN, slvS.doK, slvS.aoK (slvS.sM.doK: slot M)
to = "gpi4"           # an input: gpiN, slvS.diK, slvS.aiK
delay_ms = 5.0        # optional: the input follows this long after the output changes
gain = 1.0            # analog only: input raw = gain * output raw + offset
offset = 0.0

[[sensor]]
input = "gpi2"        # the input it drives
axis = 0
from = 10.0           # on while the axis's feedback position is in [from, to] (mm or deg)
to = 20.0
invert = false        # optional: off in the window, on outside it
```

`create_io(data, n_axes, report)` checks the tables of a parsed file; `report(array,
index, key, message)` receives each problem (`array` "" and `index` -1 for the `[io]`
table; key None: the table itself). Names are checked against the machine: the slave,
its kind, slot and channel must exist, `from` must be an output and `to` an input of
the same kind (digital or analog), and an input has at most one driver (a wire or a
sensor). Wires go from an output to an input and programs are the only way from an
input to an output, so wires can form no loop of zero delay.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field

from motionvm.io.gpio import ESTOP_INPUT, N_GPI, N_GPO
from motionvm.io.slaves import ANALOG, DIGITAL

MAX_CHANNELS = 1024
IO_KEYS = {"inputs", "outputs", "estop_input", "drive_inputs", "drive_outputs"}
SLAVE_KEYS = {
    DIGITAL: {"kind", "name", "inputs", "outputs", "slots"},
    ANALOG: {"kind", "name", "ai", "ao", "bits"},
}
SLOT_KEYS = {"inputs", "outputs"}
WIRE_KEYS = {"from", "to", "delay_ms", "gain", "offset"}
SENSOR_KEYS = {"input", "axis", "from", "to", "invert"}

_ENDPOINT = re.compile(r"(?:(gpi|gpo)(\d+)|slv(\d+)\.(?:s(\d+)\.)?(di|do|ai|ao)(\d+))")


@dataclass(frozen=True)
class SlaveSpec:
    """One `[[slave]]` table: an I/O slave's kind and its modules' channel counts."""

    kind: str
    modules: tuple[tuple[int, int, int, int], ...]
    """(inputs, outputs, ai, ao) per slot."""
    bits: int = 16
    name: str = ""


@dataclass(frozen=True)
class Endpoint:
    """A named channel: `gpi4` (kind "gpi", channel 4), `slv8.do2` (kind "do", slave 8,
    slot 1, channel 2), `slv9.ai1`."""

    kind: str
    channel: int
    slave: int | None = None
    slot: int = 1
    text: str = ""

    @property
    def is_output(self) -> bool:
        return self.kind in ("gpo", "do", "ao")

    @property
    def is_analog(self) -> bool:
        return self.kind in ("ai", "ao")


@dataclass(frozen=True)
class WireSpec:
    source: Endpoint
    target: Endpoint
    delay_ms: float = 0.0
    gain: float = 1.0
    offset: float = 0.0
    index: int = 0
    """Its place among the [[wire]] tables (for messages)."""


@dataclass(frozen=True)
class SensorSpec:
    target: Endpoint
    axis: int
    lo: float
    hi: float
    invert: bool = False
    index: int = 0
    """Its place among the [[sensor]] tables (for messages)."""


@dataclass(frozen=True)
class IOConfig:
    """The machine's I/O: controller GPIO counts, I/O slaves, wires and sensors."""

    n_inputs: int = N_GPI
    n_outputs: int = N_GPO
    estop_input: int = ESTOP_INPUT
    slaves: tuple[SlaveSpec, ...] = ()
    wires: tuple[WireSpec, ...] = ()
    sensors: tuple[SensorSpec, ...] = field(default_factory=tuple)
    drive_inputs: int = 0
    """General-purpose inputs of every drive slave (di1 ..)."""
    drive_outputs: int = 0
    """General-purpose outputs of every drive slave (do1 ..)."""


DEFAULT_IO = IOConfig()

Report = Callable[[str, int, str | None, str], None]


def parse_endpoint(text: str) -> Endpoint | None:
    """The endpoint a channel name names, or None if it is no channel name."""
    m = _ENDPOINT.fullmatch(text)
    if m is None:
        return None
    if m.group(1):
        return Endpoint(m.group(1), int(m.group(2)), text=text)
    slot = int(m.group(4)) if m.group(4) else 1
    return Endpoint(m.group(5), int(m.group(6)), int(m.group(3)), slot, text)


def _count(value: object, limit: int = MAX_CHANNELS) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= limit


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def create_io(data: dict, n_axes: int, report: Report) -> IOConfig:
    """The I/O of a parsed machine file (see the module docstring)."""
    io = data.get("io", {})
    n_in, n_out, estop = N_GPI, N_GPO, ESTOP_INPUT
    if not isinstance(io, dict):
        report("io", -1, None, "'io' must be a table: [io]")
    else:
        for key in sorted(set(io) - IO_KEYS):
            report(
                "", -1, key, f"unknown key '{key}' in [io] (known: {', '.join(sorted(IO_KEYS))})"
            )
        for key, default in (("inputs", N_GPI), ("outputs", N_GPO)):
            value = io.get(key, default)
            if not _count(value) or value < 1:
                report(
                    "", -1, key, f"{key} = {value!r}: must be an integer from 1 to {MAX_CHANNELS}"
                )
                value = default
            if key == "inputs":
                n_in = value
            else:
                n_out = value
        estop = io.get("estop_input", ESTOP_INPUT if n_in >= ESTOP_INPUT else 0)
        if not _count(estop) or estop > n_in:
            report(
                "",
                -1,
                "estop_input",
                f"estop_input = {estop!r}: must be an input number from 1 to {n_in}, or 0 (none)",
            )
            estop = 0
    d_in, d_out = 0, 0
    if isinstance(io, dict):
        for key in ("drive_inputs", "drive_outputs"):
            value = io.get(key, 0)
            if not _count(value):
                report(
                    "", -1, key, f"{key} = {value!r}: must be an integer from 0 to {MAX_CHANNELS}"
                )
                value = 0
            if key == "drive_inputs":
                d_in = value
            else:
                d_out = value
    slaves = tuple(_slaves(_tables(data, "slave", report), report))
    cfg = IOConfig(n_in, n_out, estop, slaves, drive_inputs=d_in, drive_outputs=d_out)
    wires = tuple(_wires(_tables(data, "wire", report), cfg, n_axes, report))
    sensors = tuple(_sensors(_tables(data, "sensor", report), cfg, n_axes, report))
    _single_driver(wires, sensors, report)
    return IOConfig(n_in, n_out, estop, slaves, wires, sensors, d_in, d_out)


def _tables(data: dict, name: str, report: Report) -> list[tuple[int, dict]]:
    tables = data.get(name, [])
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        report(name, -1, None, f"'{name}' must be written as [[{name}]] tables")
        return []
    return list(enumerate(tables))


def _slaves(tables: list[tuple[int, dict]], report: Report):
    for i, t in tables:
        kind = t.get("kind")
        if not isinstance(kind, str) or kind not in SLAVE_KEYS:
            report(
                "slave",
                i,
                "kind" if "kind" in t else None,
                f'[[slave]] {i}: kind = {kind!r}: must be "digital" or "analog"',
            )
            continue
        bad = False
        for key in sorted(set(t) - SLAVE_KEYS[kind]):
            report(
                "slave",
                i,
                key,
                f"[[slave]] {i}: unknown key '{key}' for a {kind} slave "
                f"(known: {', '.join(sorted(SLAVE_KEYS[kind]))})",
            )
            bad = True
        name = t.get("name", "")
        if not isinstance(name, str):
            report("slave", i, "name", f"[[slave]] {i}: name = {name!r}: must be a string")
            name = ""
        counts = {}
        for key in ("inputs", "outputs", "ai", "ao"):
            value = t.get(key, 0)
            if not _count(value):
                report(
                    "slave",
                    i,
                    key,
                    f"[[slave]] {i}: {key} = {value!r}: must be an integer from 0 to {MAX_CHANNELS}",
                )
                bad, value = True, 0
            counts[key] = value
        bits = t.get("bits", 16)
        if not _count(bits, 32) or bits < 2:
            report(
                "slave",
                i,
                "bits",
                f"[[slave]] {i}: bits = {bits!r}: must be an integer from 2 to 32",
            )
            bad, bits = True, 16
        modules = [(counts["inputs"], counts["outputs"], counts["ai"], counts["ao"])]
        slots = t.get("slots")
        if slots is not None:
            modules = _slots(i, slots, "inputs" in t or "outputs" in t, report)
            bad = bad or modules is None
        if not bad:
            yield SlaveSpec(kind, tuple(modules or ()), bits, name)


def _slots(i: int, slots: object, has_counts: bool, report: Report):
    from motionvm.io.slaves import N_SLOTS

    if (
        not isinstance(slots, list)
        or not 1 <= len(slots) <= N_SLOTS
        or not all(isinstance(s, dict) for s in slots)
    ):
        report(
            "slave",
            i,
            "slots",
            f"[[slave]] {i}: slots must be a list of 1 to {N_SLOTS} tables, e.g. [{{inputs = 8}}, {{outputs = 8}}]",
        )
        return None
    if has_counts:
        report(
            "slave",
            i,
            "slots",
            f"[[slave]] {i}: give inputs/outputs per slot or for the slave, not both",
        )
        return None
    out = []
    for n, s in enumerate(slots, 1):
        for key in sorted(set(s) - SLOT_KEYS):
            report(
                "slave",
                i,
                "slots",
                f"[[slave]] {i}: slot {n}: unknown key '{key}' (known: inputs, outputs)",
            )
            return None
        ins, outs = s.get("inputs", 0), s.get("outputs", 0)
        if not (_count(ins) and _count(outs)):
            report(
                "slave",
                i,
                "slots",
                f"[[slave]] {i}: slot {n}: inputs and outputs must be integers from 0 to {MAX_CHANNELS}",
            )
            return None
        out.append((ins, outs, 0, 0))
    return out


def endpoint_problem(ep: Endpoint, cfg: IOConfig, n_axes: int) -> str | None:
    """Why `ep` names no channel of the machine (None: it does)."""
    if ep.kind in ("gpi", "gpo"):
        count = cfg.n_inputs if ep.kind == "gpi" else cfg.n_outputs
        if not 1 <= ep.channel <= count:
            return f"the controller has {ep.kind}1..{ep.kind}{count}"
        return None
    assert ep.slave is not None
    n_slaves = n_axes + len(cfg.slaves)
    if ep.slave < n_axes:
        count = {"di": cfg.drive_inputs, "do": cfg.drive_outputs}.get(ep.kind, 0)
        if ep.slot == 1 and 1 <= ep.channel <= count:
            return None
        return (
            f"slave {ep.slave} is the drive of axis {ep.slave} ({ep.kind}: "
            f"[io] drive_inputs = {cfg.drive_inputs}, drive_outputs = {cfg.drive_outputs})"
        )
    if ep.slave >= n_slaves:
        return f"there is no slave {ep.slave} (slaves 0..{n_slaves - 1})"
    spec = cfg.slaves[ep.slave - n_axes]
    if ep.slot < 1 or ep.slot > len(spec.modules):
        return f"slave {ep.slave} has slots 1..{len(spec.modules)}"
    counts = dict(zip(("di", "do", "ai", "ao"), spec.modules[ep.slot - 1], strict=True))
    count = counts[ep.kind]
    if not 1 <= ep.channel <= count:
        what = f"slave {ep.slave}" + (f" slot {ep.slot}" if len(spec.modules) > 1 else "")
        return f"{what} ({spec.kind}) has no {ep.kind}{ep.channel}" + (
            f" ({ep.kind}1..{ep.kind}{count})" if count else ""
        )
    return None


def _endpoint(
    i: int, t: dict, key: str, array: str, cfg: IOConfig, n_axes: int, report: Report, output: bool
):
    text = t.get(key)
    want = (
        "an output (gpoN, slvS.doK, slvS.aoK)" if output else "an input (gpiN, slvS.diK, slvS.aiK)"
    )
    if text is None:
        report(array, i, None, f"[[{array}]] {i}: missing '{key}': {want}")
        return None
    ep = parse_endpoint(text) if isinstance(text, str) else None
    if ep is None:
        report(array, i, key, f"[[{array}]] {i}: {key} = {text!r}: must name {want}")
        return None
    if ep.is_output != output:
        report(
            array,
            i,
            key,
            f"[[{array}]] {i}: {key} = {text!r} is an {'input' if output else 'output'}; '{key}' takes {want}",
        )
        return None
    problem = endpoint_problem(ep, cfg, n_axes)
    if problem:
        report(array, i, key, f"[[{array}]] {i}: {key} = {text!r}: {problem}")
        return None
    return ep


def _unknown_keys(array: str, i: int, table: dict, known, report: Report) -> None:
    """Report each key of `[[array]]` number `i` that is not one of `known`."""
    for key in sorted(set(table) - known):
        report(
            array,
            i,
            key,
            f"[[{array}]] {i}: unknown key '{key}' (known: {', '.join(sorted(known))})",
        )


def _wires(tables, cfg: IOConfig, n_axes: int, report: Report):
    for i, t in tables:
        _unknown_keys("wire", i, t, WIRE_KEYS, report)
        src = _endpoint(i, t, "from", "wire", cfg, n_axes, report, True)
        dst = _endpoint(i, t, "to", "wire", cfg, n_axes, report, False)
        ok = src is not None and dst is not None
        if ok and src.is_analog != dst.is_analog:
            report(
                "wire",
                i,
                "to",
                f"[[wire]] {i}: {src.text} is {'analog' if src.is_analog else 'digital'} but {dst.text} is {'analog' if dst.is_analog else 'digital'}",
            )
            ok = False
        delay = t.get("delay_ms", 0.0)
        if not _number(delay) or delay < 0:
            report(
                "wire",
                i,
                "delay_ms",
                f"[[wire]] {i}: delay_ms = {delay!r}: must be a number of ms >= 0",
            )
            ok = False
        vals = {}
        for key, default in (("gain", 1.0), ("offset", 0.0)):
            value = t.get(key, default)
            if key in t and ok and not src.is_analog:
                report("wire", i, key, f"[[wire]] {i}: {key} applies to analog wires only")
                ok = False
            elif not _number(value):
                report("wire", i, key, f"[[wire]] {i}: {key} = {value!r}: must be a finite number")
                ok = False
            vals[key] = float(value) if _number(value) else default
        if ok:
            yield WireSpec(src, dst, float(delay), vals["gain"], vals["offset"], i)


def _sensors(tables, cfg: IOConfig, n_axes: int, report: Report):
    for i, t in tables:
        _unknown_keys("sensor", i, t, SENSOR_KEYS, report)
        ok = True
        dst = _endpoint(i, t, "input", "sensor", cfg, n_axes, report, False)
        if dst is not None and dst.is_analog:
            report(
                "sensor",
                i,
                "input",
                f"[[sensor]] {i}: input = {dst.text!r}: a sensor drives a digital input",
            )
            dst = None
        axis = t.get("axis")
        if not _count(axis, 1 << 30) or axis >= n_axes:
            report(
                "sensor",
                i,
                "axis" if "axis" in t else None,
                f"[[sensor]] {i}: axis = {axis!r}: must be an axis id from 0 to {n_axes - 1}",
            )
            ok = False
        bounds = []
        for key in ("from", "to"):
            value = t.get(key)
            if not _number(value):
                report(
                    "sensor",
                    i,
                    key if key in t else None,
                    f"[[sensor]] {i}: {key} = {value!r}: must be a position (mm or deg)",
                )
                ok = False
            bounds.append(value)
        if ok and bounds[0] > bounds[1]:
            report(
                "sensor",
                i,
                "to",
                f"[[sensor]] {i}: to = {bounds[1]!r} is below from = {bounds[0]!r}",
            )
            ok = False
        invert = t.get("invert", False)
        if not isinstance(invert, bool):
            report(
                "sensor", i, "invert", f"[[sensor]] {i}: invert = {invert!r}: must be true or false"
            )
            ok = False
        if ok and dst is not None:
            yield SensorSpec(dst, axis, float(bounds[0]), float(bounds[1]), invert, i)


def _single_driver(wires, sensors, report: Report) -> None:
    seen: dict[tuple, str] = {}
    for array, items in (("wire", wires), ("sensor", sensors)):
        for item in items:
            t = item.target
            key = (t.kind, t.slave, t.slot, t.channel)
            if key in seen:
                report(
                    array,
                    item.index,
                    "to" if array == "wire" else "input",
                    f"[[{array}]] {item.index}: {t.text} is already driven by {seen[key]}; "
                    "an input has one driver",
                )
            else:
                seen[key] = f"[[{array}]] {item.index}"
