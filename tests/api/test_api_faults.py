"""Structured faults: the report line as before, its parts as fields; raise_faults."""

from __future__ import annotations

import pickle

import pytest
from api_programs import CELL_GDL, DRIVE_PDL, write

from motionvm.api import Fault, Simulation, TaskFault

DIVIDE = "int z;\nvoid main() {\n    Sleep(5);\n    z = 1 / z;\n}\n"


def test_an_hmpl_fault_is_todays_line_with_fields():
    sim = Simulation.from_source(DIVIDE, name="div.hmpl")
    sim.run()
    line = "div.hmpl:4:5: runtime error in task 0 at t=0.005 s: integer division by zero"
    assert sim.faults == [line]  # string-compatible
    (fault,) = sim.fault_records
    assert isinstance(fault, Fault) and str(fault) == fault.text == line
    assert (fault.file, fault.line, fault.col) == ("div.hmpl", 4, 5)
    assert (fault.task, fault.language, fault.who) == (0, "HMPL", "task 0")
    assert fault.time == pytest.approx(0.005) and fault.message == "integer division by zero"


def test_a_pdl_drive_fault_names_its_drive(tmp_path):
    write(tmp_path, "counter.pdl", DRIVE_PDL)
    machine = write(tmp_path, "m.toml", 'axes = 2\n[[axis]]\n[[axis]]\npdl = "counter.pdl"\n')
    sim = Simulation.from_files([], machine=machine)
    sim.run()
    (fault,) = sim.fault_records
    assert ": runtime error in drive 1 task 0 at t=" in fault
    assert (fault.drive, fault.task, fault.line, fault.language) == (1, 0, 8, "PDL")
    assert fault.file.endswith("counter.pdl") and fault.message == "division by zero"
    assert fault.who == "drive 1 task 0"


def test_a_gdl_fault_names_its_procedure(tmp_path):
    app = write(tmp_path, "cell.gdl", CELL_GDL)
    sim = Simulation.from_files([app])
    for value in ("ON", "OFF"):
        sim.write("start.STATUS", value)
        sim.step(1)
    (fault,) = sim.fault_records
    assert (fault.procedure, fault.task, fault.language, fault.line) == ("counter", None, "GDL", 12)
    assert fault.message == "division by zero" and fault.who == "procedure counter"
    assert str(fault).startswith(f"{app}:12:")


def test_raise_faults_raises_from_run_at_the_first_fault():
    sim = Simulation.from_source(DIVIDE, name="div.hmpl", raise_faults=True)
    with pytest.raises(TaskFault) as exc:
        sim.run()
    assert exc.value.fault.line == 4 and str(exc.value) == sim.faults[0]
    assert sim.time == 0.006  # stopped at the end of the faulting cycle
    assert sim.run().finished  # the fault was raised once; the run goes on


def test_raise_faults_raises_from_step_in_the_faulting_cycle():
    sim = Simulation.from_source(DIVIDE, raise_faults=True)
    sim.step(5)
    with pytest.raises(TaskFault, match="integer division by zero"):
        sim.step(100)
    assert sim.time == 0.006


def test_without_raise_faults_a_fault_only_stops_its_task():
    sim = Simulation.from_source(DIVIDE)
    assert sim.run().finished and sim.fault_count == 1


def test_a_fault_survives_pickling_with_its_fields():
    sim = Simulation.from_source(DIVIDE, name="div.hmpl")
    sim.run()
    (fault,) = sim.fault_records
    copy = pickle.loads(pickle.dumps(fault))
    assert isinstance(copy, Fault) and copy == fault and copy.fields() == fault.fields()


def test_an_internal_error_is_a_fault_record_of_kind_internal():
    """An exception that is no fault of the program (here: of the host's event callback)
    is reported as an internal error, and `fault_records` holds it too."""

    def callback(kind, payload):
        raise LookupError(f"host callback failed on {kind} {payload}")

    sim = Simulation.from_source(
        "void main() {\n    Sleep(2);\n    SendEvent(7);\n}\n", name="e.hmpl"
    )
    sim.on_event(callback)
    sim.run()
    assert sim.fault_count == 1
    (fault,) = sim.fault_records
    assert fault is sim.faults[0] and fault.kind == "internal"
    assert fault.startswith("e.hmpl:3:5: internal error in task 0: LookupError: host callback")
    assert (fault.file, fault.line, fault.task, fault.language) == ("e.hmpl", 3, 0, "HMPL")
    assert fault.message == "LookupError: host callback failed on event 7"
    assert fault.time == pytest.approx(0.002)
    assert pickle.loads(pickle.dumps(fault)).kind == "internal"


def test_a_program_error_is_a_fault_record_of_kind_runtime():
    sim = Simulation.from_source(DIVIDE)
    sim.run()
    assert [f.kind for f in sim.fault_records] == ["runtime"]


@pytest.mark.parametrize(
    ("exc", "kind"), [(ZeroDivisionError(), "runtime"), (LookupError("no such key"), "internal")]
)
def test_a_pdl_drive_fault_tells_an_internal_error_from_the_programs(exc, kind):
    from motionvm.lang.pdl.drive_faults import describe_fault
    from motionvm.lang.pdl.program import compile_pdl
    from motionvm.source import DiagnosticSink

    program = compile_pdl("d.pdl", sink=DiagnosticSink(), text=DRIVE_PDL)
    fault = describe_fault(program, 0, exc, 0.25)
    assert fault.kind == kind and fault.language == "PDL" and fault.time == 0.25
    assert ("internal error (LookupError" in fault.message) is (kind == "internal")
