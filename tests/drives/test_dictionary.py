"""The object dictionary of a slave: SDO aborts, PDO mapping from the machine file,
forced PDO values, and the slave directory I/O modules register with."""

from __future__ import annotations

import pytest

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.dictionary import (
    ABORT_LENGTH,
    ABORT_NO_OBJECT,
    ABORT_NO_SUBINDEX,
    ABORT_NOT_MAPPABLE,
    ABORT_READ_ONLY,
    Obj,
    ObjectDictionary,
    SdoAbort,
    SlaveDirectory,
)
from motionvm.motion.axis_config import AxisConfig
from motionvm.motion.commands import MotionCommands
from motionvm.motion.kernel import MotionKernel
from motionvm.sim.machine import MachineFileError, load_machine

DT = 0.001


def _code(fn, *args) -> int:
    with pytest.raises(SdoAbort) as info:
        fn(*args)
    return info.value.code


def test_sdo_aborts_name_the_cia301_codes():
    d = Cia402Drive().objects
    assert _code(d.sdo_read, 0x1234, 0, 2) == ABORT_NO_OBJECT
    assert _code(d.sdo_read, 0x6041, 1, 2) == ABORT_NO_SUBINDEX
    assert _code(d.sdo_read, 0x6041, 0, 4) == ABORT_LENGTH
    assert _code(d.sdo_write, 0x6041, 0, 2, b"\x00\x00") == ABORT_READ_ONLY
    assert _code(d.sdo_read, 0x1008, 0, 65) == ABORT_LENGTH
    assert d.sdo_read(0x1008, 0, 8) == b"motionvm"
    assert d.sdo_read(0x1018, 0, 1) == b"\x04"


def test_default_mapping_is_the_cyclic_synchronous_one():
    d = Cia402Drive().objects
    assert (0x607A, 0) in d.rx and (0x60FF, 0) in d.rx and (0x6071, 0) in d.rx
    assert (0x6064, 0) in d.tx and (0x60FD, 0) in d.tx
    assert _code(d.pdo_read, 0x6065, 0) == ABORT_NOT_MAPPABLE
    assert _code(d.pdo_write, 0x6064, 0, 1) == ABORT_READ_ONLY


def test_forced_value_wins_over_the_master_until_released():
    drive = Cia402Drive()
    d = drive.objects
    d.force(0x6040, 0, 0x06)
    drive.controlword = 0x00  # the master writes its own value each cycle
    for _ in range(5):
        drive.step(DT)
    assert drive.controlword == 0x06  # shutdown took effect: Ready to switch on
    assert drive.statusword & 0x6F == 0x21
    d.release(0x6040, 0)
    drive.controlword = 0x00
    drive.step(DT)
    assert drive.controlword == 0x00 and drive.statusword & 0x4F == 0x40


def _machine(tmp_path, drive: str):
    p = tmp_path / "m.toml"
    p.write_text(f"[[axis]]\ndrive = {{ {drive} }}\n")
    return p


@pytest.mark.parametrize(
    ("drive", "message"),
    [
        ("rxpdo = [0x6040]", "rxpdo = [0x6040] lacks Target position (0x607A)"),
        ("txpdo = [0x6041, 0x6064, 0x1234]", "object 0x1234:0 does not exist"),
        ("rxpdo = [0x6040, 0x607A, 0x6041]", "Statusword (0x6041:0) is read-only"),
        ('rxpdo = [0x6040, 0x607A, "60FE/1"]', "entry '60FE/1' is not an object index"),
        ("txpdo = [0x6041, 0x6064, 0x1008]", "is a string: not mappable"),
        ("rxpdo = 7", "must be a list of objects"),
    ],
)
def test_bad_mapping_is_a_machine_file_error_naming_the_key(tmp_path, drive, message):
    with pytest.raises(MachineFileError) as info:
        load_machine(_machine(tmp_path, drive))
    text = str(info.value)
    assert "m.toml:2:11: error: [[axis]] 0: drive: " in text  # points at the key
    assert message in text


def test_slave_directory_takes_io_modules_after_the_drives():
    kernel = MotionKernel([AxisConfig(), AxisConfig()], DT)
    io = ObjectDictionary("an I/O module")
    inputs = [0b101]
    io.add(0x6000, 1, Obj("Digital inputs 1-8", "u8", lambda: inputs[0]))
    io.map_tx([(0x6000, 1)])
    assert kernel.slaves.add(io) == 2
    cmds = MotionCommands(kernel)
    assert cmds.ReadPDO(2, 0x6000, 1) == 5
    assert cmds.ReadSDO(2, 0x6000, 1, 1) == 5
    assert cmds.ReadSDO(3, 0x6000, 1, 1) == -1
    assert isinstance(SlaveDirectory().get(0), type(None))


def test_sdo_needs_a_bus_in_pre_operational_and_pdo_in_operational():
    kernel = MotionKernel([AxisConfig()], DT)
    cmds = MotionCommands(kernel)
    cmds.ScanNetwork()  # the bus goes down to Init, then up one state per cycle
    assert cmds.ReadSDO(0, 0x6041, 0, 2) == -1
    kernel.step()  # Pre-Operational
    assert cmds.ReadSDO(0, 0x6041, 0, 2) >= 0
    assert cmds.ReadPDO(0, 0x6041, 0) == -1
    kernel.step()
    kernel.step()  # Operational
    assert cmds.ReadPDO(0, 0x6041, 0) >= 0


def test_write_sdo_and_pdo_copy_the_low_bytes_of_the_value():
    kernel = MotionKernel([AxisConfig()], DT)
    cmds = MotionCommands(kernel)
    drive = kernel.axes[0].drive
    assert cmds.WriteSDO(0, 0x60FE, 2, 4, -1) == 0
    assert drive.digital_output_mask == 0xFFFFFFFF
    assert cmds.WritePDO(0, 0x60B8, 0, 0x12345) == 0
    assert drive.tp_function == 0x2345
    assert cmds.ReadSDO(0, 0x6064, 0, 4) == drive.position_actual
