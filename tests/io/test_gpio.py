"""The controller's digital I/O: numbering, bits, and who sees it (HMPL, scope, host API)."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.io.gpio import N_GPIO, DigitalIO
from motionvm.sim.controller import Controller
from motionvm.sim.scope_sources import registry_for


def test_inputs_and_outputs_are_numbered_from_zero():
    io = DigitalIO()
    assert (io.n_inputs, io.n_outputs) == (N_GPIO, N_GPIO) == (32, 32)
    io.set_input(0, True)
    io.set_input(31, 5)
    io.set_output(3, 1)
    assert (io.input(0), io.input(1), io.input(31), io.output(3)) == (1, 0, 1, 1)
    assert io.input_bits == 1 | 1 << 31 and io.output_bits == 1 << 3
    io.set_input(0, False)
    assert io.input_bits == 1 << 31


@pytest.mark.parametrize("index", [-1, 32])
def test_a_missing_bit_is_an_index_error(index):
    io = DigitalIO()
    with pytest.raises(IndexError, match=r"input .* does not exist \(0..31\)"):
        io.set_input(index, 1)
    with pytest.raises(IndexError, match=r"output .* does not exist \(0..31\)"):
        io.output(index)


def test_the_controller_owns_its_io():
    ctl = Controller()
    assert isinstance(ctl.io, DigitalIO)
    reg = registry_for(ctl)  # GPIO channels without any program
    ctl.io.set_output(5, 1)
    assert reg.resolve("gpo5").getter() == 1 and reg.resolve("himc_gpo_bits").getter() == 32


def test_hmpl_reads_inputs_and_writes_outputs_of_the_controller():
    sim = Simulation.from_source(
        "void main() { Till(HIMC_GPI(4)); HIMC_GPO(1) = HIMC_GPI(4) && !HIMC_GPI(6); }"
    )
    sim.step(3)
    assert sim.output(1) == 0
    sim.set_input(4, True)
    sim.run()
    assert sim.output(1) == 1 and sim.controller.io.outputs[1] == 1
    assert sim.controller.io.input_bits == 1 << 4


def test_hmpl_index_out_of_range_is_a_runtime_error():
    sim = Simulation.from_source("void main() { HIMC_GPO(32) = 1; }")
    sim.run()
    assert "HIMC_GPO(32): index out of range (0..31)" in sim.faults[0]
