"""Scope channels of the controller's I/O system: every input, output, analog word and
slave state (io/system.py `IOSystem.channel`).

- `gpi3`, `gpo5`: a controller input as programs read it, an output's state [bool];
  `himc_gpi_bits`, `himc_gpo_bits`: all of them as one integer (input N in bit N - 1);
- `slvS.diK`, `slvS.doK` [bool], `slvS.aiK`, `slvS.aoK` [raw: the channel's word] of an
  I/O slave (`slvS.sM.diK`: slot M of a slave with slots), and `slvS.aiK.value`,
  `slvS.aoK.value`, the word converted by the channel's type (table 10.1.1) [raw];
- `slvS.state`: the slave's EtherCAT state (1 Init ... 8 Operation) [raw].
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from motionvm.io.system import IOSystem
from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, ChannelSource, ScopeError


class IoSource(ChannelSource):
    """The channels of one `IOSystem`."""

    def __init__(self, io: IOSystem) -> None:
        self.io = io

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        io = self.io
        gpio = io.gpio
        if name == "himc_gpi_bits":
            return (lambda: gpio.input_bits), RAW_UNIT
        if name == "himc_gpo_bits":
            return (lambda: gpio.output_bits), RAW_UNIT
        if name.endswith(".value") and (".ai" in name or ".ao" in name):
            return self._converted(name[: -len(".value")], name)
        found = io.channel(name)
        if found is None:
            return self._missing(name)
        read, _ = found
        bit = name.startswith(("gpi", "gpo")) or ".d" in name
        return read, BIT_UNIT if bit else RAW_UNIT

    def _converted(self, base: str, name: str):
        from motionvm.io.config import parse_endpoint

        ep = parse_endpoint(base)
        found = self.io.endpoint_module(ep) if ep is not None and ep.slave is not None else None
        if found is None or not 1 <= ep.channel <= len(
            found[1].ao if ep.kind == "ao" else found[1].ai
        ):
            return self._missing(name)
        module, k, out = found[1], ep.channel - 1, ep.kind == "ao"
        return (lambda: self.io.converted(module, k, out)), RAW_UNIT

    def _missing(self, name: str):
        if name.startswith(("gpi", "gpo")) and name[3:].isdigit():
            gpio = self.io.gpio
            n = gpio.n_inputs if name.startswith("gpi") else gpio.n_outputs
            raise ScopeError(
                f"scope channel '{name}': the controller has {name[:3]}1..{name[:3]}{n}"
            )
        if name.startswith("slv"):
            raise ScopeError(
                f"scope channel '{name}': no such slave channel on this machine "
                f"(slaves 0..{len(self.io.bus) - 1}; channels slvS.diK, slvS.doK, slvS.aiK, "
                "slvS.aoK from K = 1, slvS.state)"
            )
        return None

    def channel_names(self) -> Iterable[str]:
        yield "himc_gpi_bits"
        yield "himc_gpo_bits"
        for name in self.io.channel_names():
            yield name
            if ".ai" in name or ".ao" in name:
                yield f"{name}.value"
