"""HMPL, PDL and GDL on one machine and one clock (examples/04_one_machine.*)."""

from __future__ import annotations

import csv
import re
from pathlib import Path

from motionvm.api import Simulation
from motionvm.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FILES = ["04_one_machine.hmpl", "04_one_machine.cell.gdl"]
MACHINE = "04_one_machine.toml"
SCENARIO = "04_one_machine.scenario.toml"
STAMP = re.compile(r"^\[t=(\d+\.\d{6})\]\[(task \d+|drive \d+ task \d+|gdl(?: \w+)?)\] \S")
"""The one `--stamp` prefix of every language: 6 decimals, then the source."""


def test_stamped_lines_of_three_languages_are_in_time_order(monkeypatch, tmp_path):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    sim = Simulation.from_files(FILES, machine=MACHINE, scenario=SCENARIO, stamp=True)
    sim.run()
    assert sim.faults == []
    times = []
    kinds = set()
    for line in sim.messages:
        m = STAMP.match(line)
        assert m, line
        times.append(float(m.group(1)))
        kinds.add(m.group(2).split()[0])
    assert kinds == {"gdl", "drive", "task"}
    assert times == sorted(times)
    # GDL: its event trace is stamped `[gdl]`, a procedure's lines name the procedure
    assert "[t=0.050000][gdl] input STATUS OF start_button = ON" in sim.messages
    assert "[t=0.050000][gdl run_conveyor] set OPERATING$CONDITION OF conveyor = RUNNING" in (
        sim.messages
    )


def test_without_stamp_gdl_keeps_its_trace_format(monkeypatch, tmp_path):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    sim = Simulation.from_files(FILES, machine=MACHINE, scenario=SCENARIO)
    sim.run()
    assert "t=0.050 input STATUS OF start_button = ON" in sim.messages
    assert not any(line.startswith("[t=") for line in sim.messages)


def test_each_language_moves_its_own_axis_of_one_machine(monkeypatch, tmp_path):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    sim = Simulation.from_files(FILES, machine=MACHINE, scenario=SCENARIO)
    sim.run()
    axes = sim.controller.axes
    assert [round(a.pos_fb, 6) for a in axes] == [10.0, 2.0, 10.0]
    assert axes[1].controlled_by == "PDL drive"
    assert axes[2].controlled_by == "GDL motor conveyor"
    assert sim.messages[-1] == "axis 1 (PDL) at 2.000 mm, axis 2 (GDL) at 10.000 mm"


def test_hmpl_moves_of_a_gdl_motor_axis_are_refused(monkeypatch, tmp_path):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    prog = tmp_path / "m.hmpl"
    prog.write_text('void main() { Print("%x", MoveAbs(2, 5.0)); }\n', encoding="utf-8")
    sim = Simulation.from_files([prog, FILES[1]], machine=MACHINE, scenario=SCENARIO)
    sim.run(until=0.01)
    assert sim.messages[-1] == "830200f0"  # eERR_AXIS_CMD_INVALID_CONTROL_MODE of axis 2


def test_one_scope_records_channels_of_all_three(monkeypatch, tmp_path, capsys):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    out = tmp_path / "all.csv"
    channels = "system_timeInMs,axis0.pos_fb,drive1.x_ref_pos,axis1.pos_fb,conveyor.SPEED"
    argv = ["run", "--machine", MACHINE, *FILES, "--scenario", SCENARIO]
    assert main([*argv, "--scope", channels, "--scope-out", str(out)]) == 0
    rows = list(csv.reader(out.read_text().splitlines()))
    assert rows[0] == ["time", *channels.split(",")]
    last = rows[-1]
    assert float(last[2]) == 10.0 and last[3] == "20000" and float(last[4]) == 2.0
    assert max(float(r[5]) for r in rows[1:]) == 100.0  # the conveyor ran at its speed
    ms = [float(r[1]) for r in rows[1:]]
    assert ms == [round(float(r[0]) * 1000) for r in rows[1:]]  # one clock for all


def test_jumped_and_stepped_mixed_runs_are_identical(monkeypatch, tmp_path):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    runs = []
    for skip in (True, False):
        sim = Simulation.from_files(
            FILES, machine=MACHINE, scenario=SCENARIO, stamp=True, skip=skip
        )
        sim.run()
        runs.append((sim.messages, sim.faults, sim.time))
    assert runs[0] == runs[1]
