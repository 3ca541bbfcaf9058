"""EtherCAT I/O slaves (manual 2.5-2.10 and 9.3, 9.5): bus order, slot addressing, the
slave GPIO functions and their errors, the manual's examples 2 and 3 of 9.1.2."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation

MACHINE = """
axes = 1
[[slave]]
kind = "digital"
inputs = 4
outputs = 4
[[slave]]
kind = "digital"
slots = [{inputs = 2}, {outputs = 4}]
[[slave]]
kind = "analog"
ai = 1
"""


def sim_of(tmp_path, source: str, machine: str = MACHINE) -> Simulation:
    m = tmp_path / "m.toml"
    m.write_text(machine)
    return Simulation.from_source(source, machine=str(m))


def test_drives_first_then_io_slaves_in_file_order(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            Print("%d %d %d %d %d", GetSlaveNum(), GetSlvECATSt(0), GetSlvECATSt(1),
                  GetSlvECATSt(3), GetSlvECATSt(4));
            Print("%d", ScanNetwork()); Sleep(1); Print("%d", GetSlvECATSt(2));
            Sleep(5); Print("%d", GetSlvECATSt(2));
        }""",
    )
    sim.run()
    assert sim.messages == ["4 8 8 8 0", "0", "2", "8"]
    assert [s.kind for s in sim.controller.io.bus.slaves] == [
        "drive",
        "digital",
        "digital",
        "analog",
    ]


def test_set_toggle_get_and_all(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            Print("%d %d", SetSlvGPO(1, 2, 1), GetSlvGPO(1, 2));
            ToggleSlvGPO(1, 2); ToggleSlvGPO(1, 3); Print("%d", GetSlvAllGPO(1));
            SetSlvAllGPO(1, 0x6); Print("%d %d", GetSlvAllGPO(1), GetSlvGPO(1, 3));
            Sleep(5); Print("%d %d", GetSlvGPI(1, 1), GetSlvAllGPI(1));
        }""",
    )
    sim.step(1)
    sim.set_input("slv1.di1", 1)
    sim.set_input("slv1.di4", 1)
    sim.run()
    assert sim.messages == ["0 1", "4", "6 1", "1 9"]
    assert sim.output("slv1.do2") == 1 and sim.read("slv1.do3") == 1


def test_slots(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            Print("%d", SetSlvGPO(2 | HMPL_SLOT_2, 3, 1));
            Print("%d %d", GetSlvAllGPO(2 | HMPL_SLOT_2), GetSlvGPO(2 | HMPL_SLOT_2, 3));
            Print("%d %d", SetSlvGPO(2, 1, 1), SetSlvGPO(2 | HMPL_SLOT_3, 1, 1));
            Sleep(5); Print("%d", GetSlvGPI(2 | HMPL_SLOT_1, 2));
        }""",
    )
    sim.set_input("slv2.s1.di2", 1)
    sim.run()
    # slot 1 has no outputs; there is no slot 3
    assert sim.messages == ["0", "4 1", "-1 -1", "1"]


def test_bad_slaves_and_channels_fail(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            Print("%d %d %d", SetSlvGPO(0, 1, 1), SetSlvGPO(9, 1, 1), SetSlvGPO(1, 5, 1));
            Print("%d %d %d", ToggleSlvGPO(3, 1), SetSlvAllGPO(-1, 1), GetSlvGPI(1, 0));
            Print("%d %d %x", GetSlvAllGPI(7), GetSlvGPO(1, 9), GetSystemLastErr());
        }""",
    )
    sim.run()
    assert sim.messages == ["-1 -1 -1", "-1 -1 0", "0 0 138f"]


def test_manual_example_2_falling_edge_toggles(tmp_path):
    """9.1.2 example 2: a falling edge on input 3 of slave 1 toggles its output 2 and
    sets every controller output."""
    sim = sim_of(
        tmp_path,
        """void main() {
            int last_state = 0;
            while (1) {
                int in = GetSlvGPI(1, 3);
                if ( (in ^ last_state) && !in) {
                    ToggleSlvGPO(1, 2);
                    SetAllGPO(0xff);
                }
                last_state = in;
            }
        }""",
    )
    sim.step(5)
    sim.set_input("slv1.di3", 1)
    sim.step(5)
    assert sim.output("slv1.do2") == 0 and sim.read("himc_gpo_bits") == 0
    sim.set_input("slv1.di3", 0)
    sim.step(5)
    assert sim.output("slv1.do2") == 1 and sim.read("himc_gpo_bits") == 255


def test_manual_example_3_slot_toggle(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            int last_state = 0;
            while (1) {
                SetSlvGPO(2 | HMPL_SLOT_2, 3);
                Sleep(1000);
                ToggleSlvGPO(2 | HMPL_SLOT_2, 3);
            }
        }""".replace("SetSlvGPO(2 | HMPL_SLOT_2, 3)", "SetSlvGPO(2 | HMPL_SLOT_2, 3, 1)"),
    )
    sim.run(until=0.5)
    assert sim.output("slv2.s2.do3") == 1
    sim.run(until=1.5)
    # as printed, the loop sets the output again right after toggling it
    assert sim.output("slv2.s2.do3") == 1 and not sim.faults


def test_manual_example_1_rising_edge_disables_every_axis(tmp_path):
    sim = sim_of(
        tmp_path,
        """void main() {
            int last_state = 0;
            Enable(0);
            while (1) {
                int in = GetGPI(4);
                if ( (in ^ last_state) & in) {
                    DisableAll();
                    SetGPO(3, 1);
                }
                last_state = in;
            }
        }""",
    )
    sim.step(20)
    assert sim.axis(0).enabled and sim.output(3) == 0
    sim.set_input(4, 1)
    sim.step(3)
    assert not sim.axis(0).enabled and sim.output(3) == 1


def test_the_host_sets_inputs_and_reads_outputs_by_name(tmp_path):
    sim = sim_of(tmp_path, "void main() { SetSlvGPO(1, 4, 1); SetGPO(2, 1); Sleep(1); }")
    sim.run()
    assert (sim.output("slv1.do4"), sim.output("gpo2"), sim.output(2)) == (1, 1, 1)
    sim.set_input("slv3.ai1", 40000)
    assert sim.read("slv3.ai1") == 40000
    for bad in ("gpo2", "slv1.do1", "slv1.di9", "nothing"):
        with pytest.raises(KeyError):
            sim.set_input(bad, 1)
    with pytest.raises(KeyError):
        sim.output("slv7.do1")
    with pytest.raises(IndexError):
        sim.set_input(9, 1)


def test_drives_have_the_general_purpose_channels_the_machine_gives_them(tmp_path):
    machine = 'axes = 2\n[io]\ndrive_inputs = 4\ndrive_outputs = 2\n[[wire]]\nfrom = "slv1.do2"\nto = "slv0.di3"\n'
    sim = sim_of(
        tmp_path,
        """void main() {
            Print("%d %d", SetSlvGPO(1, 2, 1), SetSlvGPO(1, 3, 1));
            Sleep(2);
            Print("%d %d %d", GetSlvGPI(0, 3), GetSlvAllGPI(0), GetSlvAllGPO(1));
        }""",
        machine,
    )
    sim.run()
    assert sim.messages == ["0 -1", "1 4 2"]
    assert sim.read("slv0.di3") == 1


def test_without_drive_channels_a_drive_has_none(tmp_path):
    sim = sim_of(tmp_path, 'void main() { Print("%d %d", SetSlvGPO(0, 1, 1), GetSlvGPI(0, 1)); }')
    sim.run()
    assert sim.messages == ["-1 0"]
