"""The I/O slaves' CoE object dictionaries (CiA 401: 0x6000, 0x6200, 0x6401, 0x6411,
0x1008, 0x1018) reached by ReadSDO ... ReleasePDO with the slave ids of chapter 9."""

from __future__ import annotations

from motionvm.api import Simulation

MACHINE = """
axes = 2
[[slave]]
kind = "digital"
inputs = 12
outputs = 10
name = "stack light"
[[slave]]
kind = "analog"
ai = 2
ao = 2
[[slave]]
kind = "digital"
slots = [{inputs = 4}, {outputs = 4}]
[[wire]]
from = "slv2.do3"
to = "slv2.di1"
[[wire]]
from = "slv4.s2.do1"
to = "gpi1"
"""


def run(tmp_path, source: str, machine: str = MACHINE) -> list[str]:
    m = tmp_path / "m.toml"
    m.write_text(machine)
    sim = Simulation.from_source(source, machine=str(m))
    sim.run()
    return sim.messages


def test_slave_ids_agree_with_chapter_9(tmp_path):
    out = run(
        tmp_path,
        """void main() {
            Print("%d", GetSlaveNum());
            Print("%d", WriteSDO(2, 0x6200, 1, 1, 0x05));
            Print("%d %d %d %d", GetSlvGPO(2, 1), GetSlvGPO(2, 2), GetSlvGPO(2, 3),
                  GetSlvAllGPO(2));
            SetSlvGPO(2, 10, 1); SetSlvGPO(2, 1, 0);
            Print("%d %d", ReadSDO(2, 0x6200, 1, 1), ReadSDO(2, 0x6200, 2, 1));
            Sleep(5);
            Print("%d %d", GetSlvGPI(2, 1), ReadSDO(2, 0x6000, 1, 1));
            Print("%d %d", ReadPDO(2, 0x6000, 1), ReadPDO(2, 0x6200, 2));
        }""",
    )
    assert out == ["5", "0", "1 0 1 5", "4 2", "1 1", "1 2"]


def test_identity_name_and_counts(tmp_path):
    out = run(
        tmp_path,
        """void main() {
            Data_t d;
            Print("%d %d %d", ReadSDO(2, 0x1018, 0, 1), ReadSDO(2, 0x1018, 2, 4),
                  ReadSDO(3, 0x1018, 4, 4));
            Print("%d %d %d %d", ReadSDO(2, 0x6000, 0, 1), ReadSDO(2, 0x6200, 0, 1),
                  ReadSDO(3, 0x6401, 0, 1), ReadSDO(3, 0x6411, 0, 1));
            Print("%d 0x%X", ReadSDO(3, 0x6000, 0, 1), GetSystemLastErr());
            Print("%d 0x%X", ReadSDO(2, 0x6000, 3, 1), GetSystemLastErr());
            Print("%d 0x%X", ReadSDO(0, 0x6200, 1, 1), GetSystemLastErr());
            Print("%d 0x%X", ReadSDO(5, 0x1018, 1, 4), GetSystemLastErr());
        }""",
    )
    assert out == [
        "4 1025 3",
        "2 2 2 2",
        "-1 0x6020000",
        "-1 0x6090011",
        "-1 0x6020000",
        "-1 0x138F",
    ]


def test_device_name(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text(MACHINE)
    sim = Simulation.from_source("void main() { }", machine=str(m))
    motion = sim.controller.motion
    assert motion.slaves.get(2).sdo_read(0x1008, 0, 11) == b"stack light"
    assert motion.slaves.get(3).read(0x1008, 0) == "motionvm analog I/O"
    assert motion.slaves.get(4).read(0x1008, 0) == "motionvm digital I/O"
    assert [s.objects is motion.slaves.get(s.slave_id) for s in sim.controller.io.bus.slaves] == [
        True
    ] * 5


def test_output_bits_of_missing_channels_and_inputs_are_refused(tmp_path):
    out = run(
        tmp_path,
        """void main() {
            Print("%d 0x%X", WriteSDO(2, 0x6200, 2, 1, 0x04), GetSystemLastErr());
            Print("%d 0x%X", WriteSDO(2, 0x6000, 1, 1, 1), GetSystemLastErr());
            Print("%d 0x%X", WriteSDO(2, 0x6200, 1, 2, 1), GetSystemLastErr());
            Print("%d 0x%X", WritePDO(2, 0x6000, 1, 1), GetSystemLastErr());
            Print("%d", WritePDO(2, 0x6200, 2, 3));
            Print("%d %d", GetSlvGPO(2, 9), GetSlvGPO(2, 10));
        }""",
    )
    assert out == ["-1 0x6090030", "-1 0x6010002", "-1 0x6070010", "-1 0x6010002", "0", "1 1"]


def test_analog_words(tmp_path):
    out = run(
        tmp_path,
        """void main() {
            Print("%d", WriteSDO(3, 0x6411, 2, 2, -1));
            Print("%d", GetSlvAORaw(3, 2));
            SetSlvAORaw(3, 1, 40000);
            Print("%d %d", ReadSDO(3, 0x6411, 1, 2), ReadPDO(3, 0x6411, 1));
            Print("%d 0x%X", WriteSDO(3, 0x6401, 1, 2, 5), GetSystemLastErr());
            Print("%d", ReadSDO(3, 0x6401, 2, 2));
        }""",
    )
    assert out == ["0", "65535", f"{40000 - 65536} {40000 - 65536}", "-1 0x6010002", "0"]


def test_forced_output_is_what_the_wire_carries(tmp_path):
    out = run(
        tmp_path,
        """void main() {
            Print("%d", ForceWritePDO(2, 0x6200, 1, 0x04));
            SetSlvGPO(2, 3, 0);
            Sleep(5);
            Print("%d %d %d", GetSlvGPO(2, 3), GetSlvGPI(2, 1), ReadPDO(2, 0x6200, 1));
            Print("%d", ForceWritePDO(4, 0x6200, 1, 1));
            Sleep(5);
            Print("%d %d", GetSlvGPO(4 | HMPL_SLOT_2, 1), GetGPI(1));
            Print("%d", ReleasePDO(2, 0x6200, 1));
            SetSlvGPO(2, 3, 0);
            Sleep(5);
            Print("%d %d", GetSlvGPO(2, 3), GetSlvGPI(2, 1));
        }""",
    )
    assert out == ["0", "1 1 4", "0", "1 1", "0", "0 0"]


def test_lost_io_slave_refuses_object_access(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text(MACHINE)
    sim = Simulation.from_source(
        """void main() {
            Sleep(10);
            Print("%d 0x%X", ReadSDO(2, 0x1018, 1, 4), GetSystemLastErr());
            Print("%d", ReadSDO(3, 0x1018, 1, 4));
        }""",
        machine=str(m),
    )
    sim.controller.io.lose_slave(2)
    sim.run()
    assert sim.messages == ["-1 0x14B4", "0"]
