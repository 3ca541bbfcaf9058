"""A PDL drive moves its machine axis, on the controller's clock (lang/pdl/machine_drives.py).

The program's profile is the position demand of the axis's CiA 402 drive under local
control; the feedback shows it 1 + delay_cycles cycles later. Across cycles the
controller jumps over the drives' sleeps; jumped and stepped runs agree exactly.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.objects import SW_REMOTE, State
from motionvm.lang.pdl.machine_drives import (
    CONTROLLED_BY,
    PdlDrives,
    compile_drives,
    compile_program,
)
from motionvm.runtime.clients import CycleClient, PassiveClient
from motionvm.sim.controller import Controller
from motionvm.sim.machine import DEFAULT_MACHINE, load_machine
from motionvm.sim.scope import ChannelRegistry, ScopeRecorder
from motionvm.sim.scope_sources import registry_for

SRC = Path(__file__).parents[3] / "src" / "motionvm"

MOVER = """\
#task/0;
sleep 50;
X_trg=20000;
till(~x_run);
printl("at %ld", x_ref_pos);
sleep 200;
X_trg=5000;
till(~x_run);
printl("back at %ld", x_ref_pos);
halt;
"""

TICKER = """\
#long n;
#task/1;
loop(5) do
  sleep 37;
  n++;
  printl("tick %ld", n);
end;
halt;
"""

MACHINE = """\
axes = 3

[[axis]]

[[axis]]
max_vel = 100.0
max_acc = 10000.0
pdl = "mover.pdl"
{drive}
[[axis]]
pdl = "ticker.pdl"
"""


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


def machine_file(tmp: Path, drive: str = "") -> Path:
    write(tmp, "mover.pdl", MOVER)
    write(tmp, "ticker.pdl", TICKER)
    return write(tmp, "m.toml", MACHINE.format(drive=drive))


class CycleCounter(PassiveClient):
    """Counts the cycles the controller steps; never holds the clock."""

    def __init__(self) -> None:
        self.stepped = 0

    def end_cycle(self) -> None:
        self.stepped += 1


def assemble(path: Path, stamp: bool = True):
    """(controller, client, lines, counter): a run of the machine file, as a run assembles it."""
    machine = load_machine(path)
    lines: list[str] = []
    ctl = Controller(machine.cycle_time, machine)
    drives = compile_drives(machine, lines.append)
    assert drives is not None, lines
    client = PdlDrives(ctl, drives, machine, emit=lines.append, report=lines.append, stamp=stamp)
    ctl.add_client(client)
    counter = CycleCounter()
    ctl.add_client(counter)
    client.boot()
    return ctl, client, lines, counter


def record(ctl, client, channels: list[str]) -> ScopeRecorder:
    registry = registry_for(ctl, client)
    recorder = ScopeRecorder(registry.resolve_all(channels), ctl.cycle_time)
    recorder.attach(ctl)
    return recorder


# ---------------------------------------------------------------- the drive's local control


def test_local_demand_moves_the_motor_and_clears_the_remote_bit() -> None:
    d = Cia402Drive(position=100.0)
    assert d.local_demand is None
    d.follow_local_demand(100.0)
    d.controlword = 0  # the master's controlword is not processed under local control
    for target in (150.0, 250.0, 250.0):
        d.follow_local_demand(target)
        d.step(0.001)
    assert d.state is State.OPERATION_ENABLED
    assert not d.statusword & SW_REMOTE
    assert (d.position_actual, d.position_demand, d.following_error) == (250, 250, 0)
    assert d.velocity_actual == 0
    d.follow_local_demand(None)
    assert d.state is State.SWITCH_ON_DISABLED and d.statusword & SW_REMOTE


# ---------------------------------------------------------------- the machine axis moves


def test_the_program_moves_the_machine_axis(tmp_path: Path) -> None:
    ctl, client, lines, _ = assemble(machine_file(tmp_path), stamp=False)
    assert isinstance(client, CycleClient)
    axis = ctl.axes[1]
    assert axis.controlled_by == CONTROLLED_BY
    ctl.run()
    assert lines == ["tick 1", "tick 2", "at 20000", "tick 3", "tick 4", "tick 5", "back at 5000"]
    assert axis.pos_fb == 0.5  # 5000 counts at 10000 counts/mm
    assert (axis.drive.position_actual, axis.drive.position_demand) == (5000, 5000)
    assert not axis.drive.statusword & SW_REMOTE
    assert ctl.axes[2].pos_fb == 0.0  # the ticker never moves its axis


@pytest.mark.parametrize("delay", [0, 1, 3])
def test_feedback_shows_the_drive_reference_after_the_latency(tmp_path: Path, delay: int) -> None:
    drive = f'drive = {{ mechanics = {{ model = "ideal", delay_cycles = {delay} }} }}\n'
    ctl, client, _, _ = assemble(machine_file(tmp_path, drive))
    rec = record(ctl, client, ["drive1.ref_pos[0]", "drive1.x_ref_pos", "axis1.pos_fb"])
    ctl.run()
    ref, x_ref, pos_fb = rec.columns
    latency = delay  # the demand handed over before a cycle's motion step
    assert len(ref) > 300 and min(ref) < max(ref)
    for k in range(len(ref) - latency):
        assert pos_fb[k + latency] * 10000 == pytest.approx(ref[k], abs=1e-6), k
        assert abs(pos_fb[k + latency] * 10000 - x_ref[k]) <= 0.5
    assert pos_fb[-1] * 10000 == pytest.approx(ref[-1]) == 5000  # the run waits for the feedback


def test_hmpl_getters_read_the_drive_motion(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    m = machine_file(tmp_path)
    hmpl = write(
        tmp_path,
        "main.hmpl",
        'void main() { Sleep(150); Print("%.4f %d", GetPosFb(1), MoveAbs(1, 1.0) != 0); }\n',
    )
    assert main(["run", "--machine", str(m), str(hmpl)]) == 0
    assert "2.0000 1\n" in capsys.readouterr().out


# ---------------------------------------------------------------- one clock, exact jumps


def test_stepped_and_jumped_runs_agree(tmp_path: Path) -> None:
    path = machine_file(tmp_path)
    ctl, client, jumped, counter = assemble(path)
    ctl.run()
    ctl2, client2, stepped, counter2 = assemble(path)
    while ctl2.busy():
        ctl2.step()
    assert jumped == stepped and len(stepped) == 7
    assert ctl.cycle == ctl2.cycle == counter2.stepped
    assert counter.stepped < ctl.cycle / 2  # the sleeps were jumped over
    for (_, a), (_, b) in zip(client.drives, client2.drives, strict=True):
        assert (a.phase, a.fclk, a.read("x_ref_pos")) == (b.phase, b.fclk, b.read("x_ref_pos"))
    assert [x.pos_fb for x in ctl.axes] == [x.pos_fb for x in ctl2.axes]


def test_a_run_with_hmpl_tasks_is_the_same_without_jumps(
    tmp_path: Path, capsys, monkeypatch
) -> None:
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path / "data"))
    m = machine_file(tmp_path)
    hmpl = write(
        tmp_path,
        "main.hmpl",
        "void main() { int i; for (i = 0; i < 4; i++) { Sleep(30);"
        ' Print("%.4f", GetPosFb(1)); } }\n',
    )
    argv = ["run", "--machine", str(m), str(hmpl), "--stamp"]
    assert main(argv) == 0
    jumped = capsys.readouterr()
    monkeypatch.setattr(Controller, "next_event", lambda self: self.cycle)  # step every cycle
    assert main(argv) == 0
    assert capsys.readouterr() == jumped
    # mid-move: the task of cycle 60 reads the feedback of cycle 59, which shows the
    # drive's reference of cycle 57 (3200 counts)
    assert "[t=0.060000][task 0] 0.3200\n" in jumped.out


def test_next_event_is_the_cycle_of_the_next_wake_up(tmp_path: Path) -> None:
    ctl, client, _, _ = assemble(machine_file(tmp_path))
    assert client.next_event() == 0  # the tasks have not run yet
    ctl.step()  # cycle 0 runs the phases before 0 ms: none
    ctl.step()  # cycle 1 runs phases 0..14: both programs go to sleep
    # drive 1 sleeps 50 ms, drive 2 37 ms = 555 phases: the cycle that runs phase 555
    # (the phases of [37, 38) ms) is cycle 38
    assert client.next_event() == 38
    ctl.run()
    assert client.next_event() is None and not client.busy()


def test_standalone_assembly_is_the_default_machine_with_one_drive(tmp_path: Path) -> None:
    prog = write(tmp_path, "p.pdl", MOVER)
    lines: list[str] = []
    drives = compile_program(str(prog), [], lines.append)
    ctl = Controller(DEFAULT_MACHINE.cycle_time, DEFAULT_MACHINE)
    client = PdlDrives(
        ctl, drives, DEFAULT_MACHINE, emit=lines.append, report=lines.append, stamp=True,
        standalone=True,
    )  # fmt: skip
    ctl.add_client(client)
    client.boot()
    ctl.run()
    assert lines == ["[t=0.350133][task 0] at 20000", "[t=0.800333][task 0] back at 5000"]
    assert ctl.axes[0].controlled_by == CONTROLLED_BY
    drive = ctl.axes[0].drive
    # the run ends with the drive; the motor follows delay_cycles = 1 cycle later
    assert abs(drive.position_actual - 5000) < 5
    assert ChannelRegistry(client.scope_sources()).resolve("x_ref_pos").getter() == 5000


# ---------------------------------------------------------------- layering


def _imports(path: Path) -> list[str]:
    names = []
    for node in ast.walk(ast.parse(path.read_text("utf-8"))):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.append(node.module)
    return names


@pytest.mark.parametrize("layer", ["source", "runtime", "drives", "motion", "io", "comm", "sim"])
def test_lower_layers_import_no_language(layer: str) -> None:
    bad = [
        f"{p.relative_to(SRC)}: {name}"
        for p in sorted((SRC / layer).rglob("*.py"))
        for name in _imports(p)
        if name.startswith("motionvm.lang")
    ]
    assert bad == []
