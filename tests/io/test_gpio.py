"""The controller's digital I/O (manual 9.1, 9.2, 9.4): numbering from 1, inversion,
bits, the E-stop input, and who sees it (HMPL, scope, host API)."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.io.gpio import ESTOP_INPUT, N_GPI, N_GPO, DigitalIO
from motionvm.io.system import IOSystem
from motionvm.sim.controller import Controller
from motionvm.sim.scope_sources import registry_for


def run(source: str, machine=None) -> list[str]:
    sim = (
        Simulation.from_source(source, machine=machine)
        if machine
        else Simulation.from_source(source)
    )
    sim.run(until=5.0)
    assert not sim.faults, sim.faults
    return sim.messages


def test_eight_inputs_and_outputs_numbered_from_one():
    io = DigitalIO()
    assert (io.n_inputs, io.n_outputs) == (N_GPI, N_GPO) == (8, 8)
    io.set_input(1, True)
    io.set_input(8, 5)
    io.set_output(3, 1)
    assert (io.input(1), io.input(2), io.input(8), io.output(3)) == (1, 0, 1, 1)
    assert io.input_bits == 1 | 1 << 7 and io.output_bits == 1 << 2
    io.set_input(1, False)
    assert io.input_bits == 1 << 7


@pytest.mark.parametrize("n", [0, 9])
def test_a_missing_bit_is_an_index_error(n):
    io = DigitalIO()
    with pytest.raises(IndexError, match=r"input .* does not exist \(1..8\)"):
        io.set_input(n, 1)
    with pytest.raises(IndexError, match=r"output .* does not exist \(1..8\)"):
        io.output(n)


def test_the_controller_owns_its_io():
    ctl = Controller()
    assert isinstance(ctl.io, IOSystem) and isinstance(ctl.io.gpio, DigitalIO)
    reg = registry_for(ctl)  # GPIO channels without any program
    ctl.io.gpio.set_output(6, 1)
    assert reg.resolve("gpo6").getter() == 1 and reg.resolve("himc_gpo_bits").getter() == 32


def test_hmpl_macros_use_the_manuals_numbers():
    sim = Simulation.from_source(
        "void main() { Till(HIMC_GPI(4)); HIMC_GPO(1) = HIMC_GPI(4) && !HIMC_GPI(6); }"
    )
    sim.step(3)
    assert sim.output(1) == 0
    sim.set_input(4, True)
    sim.run()
    assert sim.output(1) == 1 and sim.controller.io.gpio.outputs[0] == 1
    assert sim.read("himc_gpi_bits") == 1 << 3 and sim.read("gpi4") == 1


def test_hmpl_index_out_of_range_is_a_runtime_error():
    sim = Simulation.from_source("void main() { HIMC_GPO(9) = 1; }")
    sim.run()
    assert "HIMC_GPO(9): index out of range (1..8)" in sim.faults[0]


def test_set_toggle_and_all_outputs():
    out = run(
        """void main() {
            Print("%d", SetGPO(3, 1)); Print("%d %d", GetGPO(3), GetAllGPO());
            ToggleGPO(3); ToggleGPO(2); Print("%d", GetAllGPO());
            SetAllGPO(0xff); Print("%d", GetAllGPO());
            SetAllGPO(0x106); Print("%d %d", GetAllGPO(), GetGPO(1));
        }"""
    )
    assert out == ["0", "1 4", "2", "255", "6 0"]


def test_the_manuals_bit_examples():
    """9.4.3/9.4.4: inputs 1 and 4 on -> 9; outputs 2 and 3 on -> 6; likewise inverts."""
    sim = Simulation.from_source(
        """void main() {
            SetGPO(2, 1); SetGPO(3, 1); SetGPIInvert(1, 1); SetGPIInvert(4, 1);
            SetGPOInvert(2, 1); SetGPOInvert(3, 1);
            Print("%d %d %d %d", GetAllGPI(), GetAllGPO(), GetAllGPIInvertSt(), GetAllGPOInvertSt());
        }"""
    )
    sim.run()
    assert sim.messages == ["9 6 9 6"]


def test_bad_numbers_fail_with_minus_one_and_the_system_error():
    out = run(
        """void main() {
            Print("%d %d %d %d", SetGPO(0, 1), SetGPO(9, 1), ToggleGPO(-1), SetGPIInvert(9, 1));
            Print("%d %d %d", SetGPOInvert(9, 1), BindEMO(9), GetGPI(9));
            Print("%x", GetSystemLastErr());
        }"""
    )
    assert out == ["-1 -1 -1 -1", "-1 -1 0", "138f"]


def test_input_inversion_acts_on_what_programs_read():
    sim = Simulation.from_source(
        'void main() { SetGPIInvert(2, 1); Print("%d", GetGPI(2)); Till(!GetGPI(2)); Print("off"); }'
    )
    sim.step(2)
    assert sim.messages == ["1"]
    sim.set_input("gpi2", 1)
    sim.run()
    assert sim.messages == ["1", "off"]


def test_output_inversion_acts_on_the_pin():
    io = DigitalIO()
    io.set_output(3, 1)
    io.set_output_invert(3, 1)
    assert io.output(3) == 1 and io.output_pin(3) == 0
    io.set_output_invert(3, 0)
    assert io.output_pin(3) == 1


def test_more_inputs_from_the_machine_file(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text("axes = 1\n[io]\ninputs = 16\noutputs = 12\n")
    out = run('void main() { SetGPO(12, 1); Print("%d %d", GetAllGPO(), SetGPO(13, 1)); }', str(m))
    assert out == ["2048 -1"]


def test_estop_input_disables_every_axis_and_stops_every_task():
    sim = Simulation.from_source(
        """void worker() { while (1) Sleep(1); }
        void main() { Enable(0); Enable(1); Sleep(20); TaskStart(1, worker);
                      while (1) Sleep(1); }""".replace("TaskStart(1, worker)", "")
    )
    sim.step(30)
    assert sim.axis(0).enabled and sim.axis(1).enabled
    sim.set_input(ESTOP_INPUT, 1)
    assert not sim.axis(0).enabled and not sim.axis(1).enabled
    result = sim.run(until=1.0)
    assert result.finished
    assert any("E-stop input 8" in line and "0x00000064" in line for line in sim.faults)


def test_bind_emo_moves_or_removes_the_estop_input():
    sim = Simulation.from_source(
        'void main() { BindEMO(0); Enable(0); Sleep(20); Print("on"); Sleep(10); Print("%d", IsEnabled(0)); }'
    )
    sim.step(25)
    sim.set_input(8, 1)
    sim.run()
    assert sim.messages == ["on", "1"]
    sim = Simulation.from_source("void main() { BindEMO(3); Enable(0); while (1) Sleep(1); }")
    sim.step(20)
    sim.set_input(8, 1)
    assert sim.axis(0).enabled
    sim.set_input(3, 1)
    assert not sim.axis(0).enabled
    assert sim.run(until=1.0).finished


def test_a_task_inverting_the_estop_input_stops_itself():
    sim = Simulation.from_source('void main() { SetGPIInvert(8, 1); Print("never"); }')
    sim.run()
    assert sim.messages == [] and "E-stop input 8" in sim.faults[0]
