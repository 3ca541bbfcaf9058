"""read/write by scope channel name: HMPL variables, controller I/O, axes, PDL drives, GDL states."""

from __future__ import annotations

import pytest
from api_programs import CELL_GDL, COUNTER, DRIVE_PDL, write

from motionvm.api import Simulation, WriteError
from motionvm.sim.variables import WRITABLE_AXIS


def test_hmpl_globals_system_variables_and_array_elements():
    sim = Simulation.from_source(COUNTER)
    sim.step(3)
    assert sim.read("count") == 3
    assert sim.read("speed") == 1.5
    assert sim.read("table[3]") == sim.read("table", 3) == 0
    assert sim.read("system_timeInMs") == 3 == round(sim.time * 1000)  # the clock now
    sim.write("count", 100)
    sim.write("table[3]", 7)
    sim.write("system_dtest0", 2.25)
    assert (sim.read("count"), sim.read("table[3]"), sim.read("system_dtest0")) == (100, 7, 2.25)
    sim.run()
    assert sim.messages == ["count 107 table[3] 7"]  # the program saw the writes


def test_an_hmpl_write_wraps_to_the_variables_width():
    sim = Simulation.from_source("char c; short s; void main() { }\n")
    sim.write("c", 200)
    sim.write("s", 70000)
    assert (sim.read("c"), sim.read("s")) == (-56, 4464)


def test_unknown_names_are_key_errors_with_a_did_you_mean():
    sim = Simulation.from_source(COUNTER)
    with pytest.raises(KeyError, match="did you mean count"):
        sim.read("cuont")
    with pytest.raises(KeyError, match="did you mean count"):
        sim.write("cuont", 1)
    with pytest.raises(KeyError, match="out of range"):
        sim.read("table[9]")
    with pytest.raises(KeyError, match="axis0.pos_fb"):
        sim.read("axis0.pos_fbb")


def test_controller_inputs_and_outputs():
    sim = Simulation.from_source(
        'void main() { Till(HIMC_GPI(3) == 1); HIMC_GPO(5) = 1; Print("on"); }\n'
    )
    sim.step(5)
    assert sim.read("gpo5") == 0 and sim.messages == []
    sim.write("gpi3", 1)
    assert sim.read("gpi3") == 1 and sim.read("himc_gpi_bits") == 4
    sim.run()
    assert sim.read("gpo5") == 1 and sim.messages == ["on"]
    sim.write("gpo5", 0)
    assert sim.output(5) == 0


def test_axis_variables_read_in_manual_units_and_write_through_set_functions():
    sim = Simulation.from_source("void main() { }\n")
    assert sim.read("axis0.max_vel") == 1000.0  # mm/s, the default machine's
    sim.write("axis0.max_vel", 250)
    sim.write("axis0.sm_factor", 20)
    sim.write("axis1.pos_fb", 12.5)
    assert sim.read("axis0.max_vel") == 250.0 and sim.axis(0).max_vel == 250.0
    assert sim.read("axis0.sm_factor") == 20.0
    assert sim.read("axis1.pos_fb") == 12.5 and sim.read("axis1.ref_pos") == 12.5
    assert set(WRITABLE_AXIS) <= set(sim.axis(0).__dataclass_fields__)


def test_a_read_only_axis_variable_says_which_ones_are_writable():
    sim = Simulation.from_source("void main() { }\n")
    with pytest.raises(WriteError, match=r"'axis0.vel_fb' is read-only.*max_vel \(SetVel\)"):
        sim.write("axis0.vel_fb", 1.0)


def test_a_refused_axis_write_carries_the_manuals_error_code():
    sim = Simulation.from_source("void main() { }\n")
    with pytest.raises(WriteError, match="eERR_AXIS_CMD_INVALID_SM_TIME") as exc:
        sim.write("axis2.sm_factor", -1)
    assert exc.value.code is not None and exc.value.code & 0xFFFFFFFF == 0x83020168
    assert sim.read("axis2.sm_factor") == 0.0  # unchanged


def test_pdl_drive_variables_through_the_drives_host_write(tmp_path):
    drive = write(tmp_path, "counter.pdl", DRIVE_PDL)
    machine = write(tmp_path, "m.toml", 'axes = 2\n[[axis]]\n[[axis]]\npdl = "counter.pdl"\n')
    assert drive.exists()
    sim = Simulation.from_files([], machine=machine)
    sim.write("drive1.lim", 3)
    sim.run()
    assert sim.read("drive1.n") == 1  # 3 / 3: no fault, the write was seen
    assert sim.faults == []
    with pytest.raises(WriteError, match="outside the _lp limits"):
        sim.write("drive1.lim", 1000)
    with pytest.raises(WriteError, match="'x_ref_pos' is read-only"):
        sim.write("drive1.x_ref_pos", 5)
    with pytest.raises(KeyError, match="drive1.n"):
        sim.read("drive1.nn")


def test_gdl_states_are_written_as_scenario_inputs(tmp_path):
    app = write(tmp_path, "cell.gdl", CELL_GDL)
    sim = Simulation.from_files([app])
    sim.step(1)
    sim.write("start.STATUS", "ON")
    assert sim.read("start.STATUS") == 1.0  # at once
    sim.step(1)
    assert sim.read("runs.VALUE") == 1
    assert "t=0.001 input STATUS OF start = ON" in sim.messages
    sim.write("zero.VALUE", 5)
    sim.write("start.STATUS", False)
    sim.step(1)
    assert sim.read("runs.VALUE") == 2 and sim.faults == []  # 10 / 5
    with pytest.raises(WriteError, match="takes ON or OFF"):
        sim.write("start.STATUS", "MAYBE")
