"""The controller's digital inputs and outputs (manual chapter 9.1, 9.2, 9.4; 19.4
HIMC_GPI, 19.5 HIMC_GPO) and the E-stop input.

One `DigitalIO` per controller: 8 inputs and 8 outputs by default (the machine file's
`[io]` table may give more), numbered from 1 as the manual numbers them: `GetGPI(4)`
is the 4th input, `gpi4` its name, bit 3 of `himc_gpi_bits`/`GetAllGPI` its state.

Levels:
- an input has a *pin* level (what the plant, a wire, a sensor or a scenario drives)
  and an *inversion* (SetGPIInvert); what a program reads (`GetGPI`, `HIMC_GPI`,
  `GetAllGPI`, `himc_gpi_bits`, the `gpiN` channel) is pin XOR inversion;
- an output has a *state* (what a program wrote: `SetGPO`, `HIMC_GPO(n) = 1`; what
  `GetGPO`, `GetAllGPO`, `himc_gpo_bits`, `gpoN` show) and an inversion
  (SetGPOInvert); the pin level, which a wire carries, is state XOR inversion.

`inputs` (what programs read) and `outputs` (the states) are lists indexed from 0
(input N at `inputs[N - 1]`) that are created once and only change element by element,
so a reader may keep a reference to them.

E-stop: the bound input (`estop_input`, default 8, 0 = none; BindEMO) triggers on a
rising edge of what programs read (so an inverted input makes a normally-closed E-stop
button work). Every handler is called at once with the input's
number (bound methods, held weakly: `on_estop`); the I/O system disables the axes, a language's run side stops its tasks.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable

N_GPI = 8
"""Inputs of the controller (manual 9.1)."""
N_GPO = 8
"""Outputs of the controller (manual 9.1)."""
ESTOP_INPUT = 8
"""The input bound to the E-stop at power-on (manual 9.1: I8)."""


class DigitalIO:
    """The controller's digital inputs and outputs, numbered from 1."""

    def __init__(self, n_inputs: int = N_GPI, n_outputs: int = N_GPO) -> None:
        self.inputs: list[int] = [0] * n_inputs
        """What programs read, by number - 1 [0 or 1]: pin XOR inversion."""
        self.input_pins: list[int] = [0] * n_inputs
        """Input pin levels, by number - 1 [0 or 1]."""
        self.input_invert: list[int] = [0] * n_inputs
        self.outputs: list[int] = [0] * n_outputs
        """Output states as programs wrote them, by number - 1 [0 or 1]."""
        self.output_invert: list[int] = [0] * n_outputs
        self.estop_input = ESTOP_INPUT if n_inputs >= ESTOP_INPUT else 0
        """The input number bound to the E-stop (0: none)."""
        self._estop_handlers: list[weakref.WeakMethod] = []
        """Called with the input number on a rising edge of the E-stop input (held
        weakly: a run side that goes away leaves no cycle behind)."""

    def on_estop(self, handler: Callable[[int], None]) -> None:
        """Call the bound method `handler(n)` on a rising edge of the E-stop input n."""
        self._estop_handlers.append(weakref.WeakMethod(handler))  # type: ignore[arg-type]

    @property
    def n_inputs(self) -> int:
        return len(self.inputs)

    @property
    def n_outputs(self) -> int:
        return len(self.outputs)

    def has_input(self, n: int) -> bool:
        return 1 <= n <= len(self.inputs)

    def has_output(self, n: int) -> bool:
        return 1 <= n <= len(self.outputs)

    @staticmethod
    def _index(count: int, n: int, what: str) -> int:
        if not 1 <= n <= count:
            raise IndexError(f"{what} {n} does not exist (1..{count})")
        return n - 1

    # ---- inputs ----------------------------------------------------------------------

    def input(self, n: int) -> int:
        """Input `n` as programs read it [0 or 1]; IndexError if there is no such input."""
        return self.inputs[self._index(len(self.inputs), n, "input")]

    def set_input(self, n: int, value: object) -> None:
        """Drive the pin of input `n` to 1 if `value` is true, else 0."""
        i = self._index(len(self.inputs), n, "input")
        self.input_pins[i] = 1 if value else 0
        self._refresh(i)

    def set_input_invert(self, n: int, invert: object) -> None:
        i = self._index(len(self.inputs), n, "input")
        self.input_invert[i] = 1 if invert else 0
        self._refresh(i)

    def _refresh(self, i: int) -> None:
        old = self.inputs[i]
        new = self.input_pins[i] ^ self.input_invert[i]
        if new == old:
            return
        self.inputs[i] = new
        if new and i + 1 == self.estop_input:
            call_estop_handlers(self._estop_handlers, i + 1)

    # ---- outputs ---------------------------------------------------------------------

    def output(self, n: int) -> int:
        """The state of output `n` [0 or 1]; IndexError if there is no such output."""
        return self.outputs[self._index(len(self.outputs), n, "output")]

    def set_output(self, n: int, value: object) -> None:
        """Set output `n` to 1 if `value` is true, else 0."""
        self.outputs[self._index(len(self.outputs), n, "output")] = 1 if value else 0

    def set_output_invert(self, n: int, invert: object) -> None:
        self.output_invert[self._index(len(self.outputs), n, "output")] = 1 if invert else 0

    def output_pin(self, n: int) -> int:
        """The pin level of output `n`: its state XOR its inversion."""
        i = self._index(len(self.outputs), n, "output")
        return self.outputs[i] ^ self.output_invert[i]

    # ---- all at once -----------------------------------------------------------------

    @property
    def input_bits(self) -> int:
        """Every input as programs read it, input N in bit N - 1 (`himc_gpi_bits`)."""
        return bits_of(self.inputs)

    @property
    def output_bits(self) -> int:
        """Every output state, output N in bit N - 1 (`himc_gpo_bits`)."""
        return bits_of(self.outputs)

    @property
    def input_invert_bits(self) -> int:
        return bits_of(self.input_invert)

    @property
    def output_invert_bits(self) -> int:
        return bits_of(self.output_invert)

    def set_output_bits(self, value: int) -> None:
        """Output N takes bit N - 1 of `value` (SetAllGPO)."""
        outs = self.outputs
        for i in range(len(outs)):
            outs[i] = (value >> i) & 1


def call_estop_handlers(handlers: list[weakref.WeakMethod], n: int) -> None:
    """Call every handler still alive with input number `n`."""
    for ref in list(handlers):
        handler = ref()
        if handler is not None:
            handler(n)


def bits_of(values: list[int]) -> int:
    """`values[i]` in bit i, as a C int (a 32nd bit set makes it negative)."""
    out = 0
    for i, b in enumerate(values):
        if b:
            out |= 1 << i
    out &= 0xFFFFFFFF
    return out - (1 << 32) if out & 0x80000000 else out
