"""The host API and the command line assemble runs in one place: same inputs, same output.

For every example of examples/ (and a machine whose drives run PDL programs with no
HMPL file at all), `Simulation.from_files(...).messages` after `run()` must equal the
lines the CLI prints on stdout, and the fault reports must equal its stderr lines.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.cli import main

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"


def examples() -> list[Path]:
    return sorted(
        p for p in EXAMPLES.glob("*") if p.suffix in (".hmpl", ".gdl") and "." not in p.stem
    )


def _inputs(example: Path) -> tuple[list[str], dict]:
    files = [example.name] + sorted(
        p.name for p in EXAMPLES.glob(f"{example.stem}.task*{example.suffix}")
    )
    side = example.with_suffix(".toml")
    kw: dict = {}
    if side.is_file():
        kw = {"scenario": side.name} if example.suffix == ".gdl" else {"machine": side.name}
    if example.suffix == ".hmpl":  # a GDL application beside the tasks, and its scenario
        files += sorted(p.name for p in EXAMPLES.glob(f"{example.stem}.*.gdl"))
        scenario = example.with_name(f"{example.stem}.scenario.toml")
        if scenario.is_file():
            kw["scenario"] = scenario.name
    return files, kw


def _cli(argv: list[str], capsys) -> tuple[int, list[str], list[str]]:
    code = main(["run", *argv])
    out, err = capsys.readouterr()
    return code, out.splitlines(), err.splitlines()


@pytest.mark.parametrize("example", examples(), ids=lambda p: p.name)
def test_api_messages_equal_cli_stdout(example, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "cli"))
    files, kw = _inputs(example)
    argv = list(files)
    for key, value in kw.items():
        argv += [f"--{key}", value]
    code, out, err = _cli(argv, capsys)
    assert code == 0, err
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "api"))
    sim = Simulation.from_files(files, **kw)
    sim.run()
    assert sim.messages == out
    assert sim.faults == err


def test_machine_with_pdl_drives_alone(tmp_path, monkeypatch, capsys):
    """No HMPL file: the machine file's PDL drives run by themselves, in the API as in the CLI."""
    monkeypatch.chdir(EXAMPLES)
    code, out, err = _cli(["--machine", "03_pdl_drives.toml", "--stamp"], capsys)
    assert code == 0 and out, err
    sim = Simulation.from_files([], machine="03_pdl_drives.toml", stamp=True)
    sim.run()
    assert sim.messages == out


def test_a_machine_axis_on_a_pdl_drive_refuses_hmpl_moves_alike(tmp_path, monkeypatch, capsys):
    """MoveAbs on an axis whose drive runs a PDL program: one error code from both faces."""
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    prog = tmp_path / "m.hmpl"
    prog.write_text('void main() { Print("%x", MoveAbs(1, 5.0)); }\n', encoding="utf-8")
    code, out, _err = _cli(
        ["--machine", "03_pdl_drives.toml", "--until", "0.01", str(prog)], capsys
    )
    sim = Simulation.from_files([prog], machine="03_pdl_drives.toml")
    sim.run(until=0.01)
    assert code == 0 and out[0] == "830100f0" and out == sim.messages
