"""The controller's digital inputs and outputs (manual 19.4 HIMC_GPI, 19.5 HIMC_GPO).

One `DigitalIO` per controller (`Controller.io`): N_GPIO inputs and N_GPIO outputs,
numbered from 0, each 0 or 1. Inputs are set from outside (the host API, a scenario,
the plant); outputs by the programs. A language reads and writes them through this
object, the scope records them, the host API sets and reads them. The two lists are
created once and only their elements change, so a reader may keep a reference to them.
"""

from __future__ import annotations

N_GPIO = 32
"""Inputs, and outputs, of the controller."""


class DigitalIO:
    """The controller's digital inputs and outputs, 0-based."""

    def __init__(self, n_inputs: int = N_GPIO, n_outputs: int = N_GPIO) -> None:
        self.inputs: list[int] = [0] * n_inputs
        """Input bits by number [0 or 1]."""
        self.outputs: list[int] = [0] * n_outputs
        """Output bits by number [0 or 1]."""

    @property
    def n_inputs(self) -> int:
        return len(self.inputs)

    @property
    def n_outputs(self) -> int:
        return len(self.outputs)

    @staticmethod
    def _index(bits: list[int], i: int, what: str) -> int:
        if not 0 <= i < len(bits):
            raise IndexError(f"{what} {i} does not exist (0..{len(bits) - 1})")
        return i

    def input(self, i: int) -> int:
        """Input `i` [0 or 1]; IndexError if there is no such input."""
        return self.inputs[self._index(self.inputs, i, "input")]

    def set_input(self, i: int, value: object) -> None:
        """Set input `i` to 1 if `value` is true, else 0."""
        self.inputs[self._index(self.inputs, i, "input")] = 1 if value else 0

    def output(self, i: int) -> int:
        """Output `i` [0 or 1]; IndexError if there is no such output."""
        return self.outputs[self._index(self.outputs, i, "output")]

    def set_output(self, i: int, value: object) -> None:
        """Set output `i` to 1 if `value` is true, else 0."""
        self.outputs[self._index(self.outputs, i, "output")] = 1 if value else 0

    @property
    def input_bits(self) -> int:
        """Every input as one integer, input i in bit i."""
        return _bits(self.inputs)

    @property
    def output_bits(self) -> int:
        """Every output as one integer, output i in bit i."""
        return _bits(self.outputs)


def _bits(values: list[int]) -> int:
    out = 0
    for i, b in enumerate(values):
        if b:
            out |= 1 << i
    return out
