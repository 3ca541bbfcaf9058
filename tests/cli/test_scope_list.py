"""`motionvm scope --list [FILES] [--machine M] [--scenario S]`: the channels a run of the
files would offer, one per line with its unit, without running anything."""

from __future__ import annotations

from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
GLOBALS = 'int count;\ndouble speeds[2];\nvoid main() { count = 1; Print("ran"); }\n'


def channels(stdout: str) -> dict[str, str]:
    out = {}
    for line in stdout.splitlines():
        name, _, unit = line.partition(" ")
        out[name] = unit.strip()
    return out


def test_the_default_machine_alone(motionvm, tmp_path):
    r = motionvm("scope", "--list", cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == ""
    found = channels(r.stdout)
    assert found["axis0.ref_pos"] == "mm"
    assert found["gpo3"] == "bool"
    assert len(found) == len(r.stdout.splitlines())  # one channel per line, no repeats


def test_a_programs_globals_are_listed_and_it_does_not_run(motionvm, tmp_path):
    (tmp_path / "g.hmpl").write_text(GLOBALS, "utf-8")
    r = motionvm("scope", "--list", "g.hmpl", cwd=tmp_path)
    assert r.returncode == 0
    assert "ran" not in r.stdout.splitlines()
    found = channels(r.stdout)
    assert {"count", "speeds[0]", "speeds[1]"} <= set(found)
    assert found["system_timeInMs"] == "ms"  # HMPL's system variables come with HMPL


def test_every_language_of_a_machine(motionvm):
    r = motionvm(
        "scope",
        "--list",
        "--machine",
        "04_one_machine.toml",
        "04_one_machine.hmpl",
        "04_one_machine.cell.gdl",
        "--scenario",
        "04_one_machine.scenario.toml",
        cwd=EXAMPLES,
    )
    assert r.returncode == 0, r.stderr
    found = channels(r.stdout)
    assert found["drive1.x_ref_pos"] == "count"  # the PDL drive of axis 1
    assert found["start_button.STATUS"] == "bool"  # a GDL state
    assert found["axis2.ref_pos"] == "mm"


def test_the_listed_channels_can_be_recorded(motionvm, tmp_path):
    (tmp_path / "g.hmpl").write_text(GLOBALS, "utf-8")
    found = channels(motionvm("scope", "--list", "g.hmpl", cwd=tmp_path).stdout)
    picked = ["count", "speeds[1]", "axis1.ref_pos", "gpi1", "system_dtest0"]
    assert set(picked) <= set(found)
    r = motionvm("run", "g.hmpl", "--scope", ",".join(picked), "--scope-out", "s.csv", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "s.csv").read_text("utf-8").splitlines()[0].count(",") == len(picked)


def test_errors_of_the_files_and_the_command_line(motionvm, tmp_path):
    (tmp_path / "bad.hmpl").write_text("void main() { int x = 1 }\n", "utf-8")
    r = motionvm("scope", "--list", "bad.hmpl", cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == "" and "bad.hmpl:1:" in r.stderr
    r = motionvm("scope", "--list", "--machine", "nowhere.toml", cwd=tmp_path)
    assert r.returncode == 3
    r = motionvm("scope", cwd=tmp_path)
    assert r.returncode == 3 and "motionvm scope --list" in r.stderr
    r = motionvm("scope", "--list", "missing.hmpl", cwd=tmp_path)
    assert r.returncode == 3 and "missing.hmpl: no such file" in r.stderr
