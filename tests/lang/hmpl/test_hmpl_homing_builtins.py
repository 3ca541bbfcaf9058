"""HMPL homing (manual chapter 20) and touch probe (chapter 13) built-ins through the host API."""

from __future__ import annotations

from pathlib import Path

from motionvm.api import Simulation
from motionvm.drives.objects import DI_PROBE_INPUT
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.lang.hmpl.lib import implemented_builtins
from motionvm.motion.axis_config import create
from motionvm.sim.machine import MachineConfig

MANUAL = Path(__file__).resolve().parents[2] / "programs" / "hmpl" / "manual"

CH13 = ["EnableTouchProbe", "DisableTouchProbe", "IsTouchProbeEnabled", "IsTouchProbeTriggered",
        "GetTouchProbePos", "SetTouchProbeFunc"]  # fmt: skip
CH20 = ["MoveHome", "SetHomeMethod", "SetHomeSwitchVel", "SetHomeZeroVel", "SetHomeAcc",
        "SetHomeOffset", "SetHomeTimeout", "IsHomed", "IsHoming", "SetHomedStatus"]  # fmt: skip


def sim_of(source: str, axes: list[dict] | None = None, tasks: list[str] = ()) -> Simulation:
    files = [TaskFile(0, "program.hmpl", source)]
    files += [TaskFile(i + 1, f"task{i + 1}.hmpl", t) for i, t in enumerate(tasks)]
    if axes is None:
        return Simulation(files)
    return Simulation(files, machine=MachineConfig(axes=tuple(map(create, axes))))


def run(source: str, **kw) -> list[str]:
    sim = sim_of(source, **kw)
    sim.run(until=300)
    assert not sim.faults, sim.faults
    return sim.messages


def test_every_function_of_chapters_13_and_20_is_implemented():
    have = implemented_builtins()
    assert all(name in have for name in CH13 + CH20)
    assert have["MoveHome"] is True  # blocking
    assert not any(have[name] for name in CH13 + CH20 if name != "MoveHome")


def test_move_home_blocks_and_other_tasks_see_is_homing():
    main = """
void main() {
    StartTask(1);
    Enable(0); Till(IsEnabled(0));
    SetHomeMethod(0, HOME_METHOD_34);
    system_ltest0 = 1;
    int r = MoveHome(0);
    Print("r %d homed %d homing %d pos %.4f t %d", r, IsHomed(0), IsHoming(0), GetPosFb(0),
          system_timeInMs > 1000);
    system_ltest0 = 2;
}"""
    watcher = """
void main() {
    Till(system_ltest0 == 1);
    Sleep(100);
    Print("watcher: homing %d homed %d moving %d", IsHoming(0), IsHomed(0), IsMoving(0));
}"""
    msgs = run(main, tasks=[watcher])
    # default machine: from 0 mm the first index moving positive is at 10 mm (2 s at 5 mm/s)
    assert msgs == ["watcher: homing 1 homed 0 moving 1", "r 0 homed 1 homing 0 pos 0.0000 t 1"]


def test_move_home_offset_and_failure_codes():
    msgs = run(
        """
void main() {
    Print("disabled %x", MoveHome(0));
    Enable(0); Till(IsEnabled(0));
    SetHomeMethod(0, HOME_METHOD_24);
    SetHomeOffset(0, 12.5);
    Print("24: %d %.4f %d", MoveHome(0), GetPosFb(0), IsHomed(0));
    MoveAbs(0, 0); Till(IsInPos(0));
    Print("zero is %.4f mm from the switch edge", -12.5);
    SetHomeMethod(0, HOME_METHOD_1);
    Print("no switch %x homing %d last %x", MoveHome(0), IsHoming(0), GetAxisLastErr(0));
    SetHomeMethod(0, HOME_METHOD_18);
    SetHomeTimeout(0, 300);
    Print("timeout %x homing %d homed %d", MoveHome(0), IsHoming(0), IsHomed(0));
    Print("set %d homing %d", SetHomedStatus(0, 1), IsHoming(0));
    Print("homed %d", IsHomed(0));
}""",
        axes=[{"hw_left": False}],
    )
    assert msgs == [
        "disabled 83000078",
        "24: 0 12.5000 1",
        "zero is -12.5000 mm from the switch edge",
        "no switch 8300042e homing 1 last 8300042e",
        "timeout 83000424 homing 1 homed 0",
        "set 0 homing 0",
        "homed 1",
    ]


def test_settings_check_their_arguments():
    msgs = run("""
void main() {
    Print("%x %x %x %x", SetHomeMethod(0, 3), SetHomeMethod(0, 37), SetHomeSwitchVel(0, 0),
          SetHomeZeroVel(0, -2));
    Print("%x %x %x %x", SetHomeAcc(0, 0), SetHomeTimeout(0, 0), SetHomedStatus(0, 5),
          SetHomeOffset(0, 1.5));
    Print("%d %d %x", SetHomeMethod(99, 33), IsHomed(99), GetSystemLastErr());
}""")
    assert msgs == [
        "8300012c 0 83000140 83000140",
        "8300014a 8300012c 8300012c 0",
        "5007 0 138f",
    ]


def test_method_37_needs_no_enabled_axis():
    msgs = run("""
void main() {
    SetHomeMethod(2, HOME_METHOD_37);
    SetHomeOffset(2, -4);
    Print("%d %.1f %d", MoveHome(2), GetPosFb(2), IsHomed(2));
}""")
    assert msgs == ["0 -4.0 1"]


def test_user_homing_example_1_leaves_the_index_at_zero():
    sim = Simulation.from_files([MANUAL / "ch20_01_02_user_homing_1.hmpl"])
    sim.run(until=60)
    a = sim.controller.axes[0]
    assert sim.messages[-1] == "Axis homing succeeds."
    assert a.pos_fb_raw == 10.0 and a.pos_fb == 0.0 and a.ref_pos == 0.0
    assert not a.ignore_swl and a.motion_status & (1 << 11)


def test_touch_probe_2_latches_the_external_input_on_either_edge():
    sim = sim_of("""
void main() {
    double p;
    SetTouchProbeFunc(1, 1, 0, 1);   // probe 2, single trigger, negative edge
    EnableTouchProbe(1);
    Till(IsTouchProbeEnabled(1));
    Enable(1); Till(IsEnabled(1));
    MoveVel(1, 10);
    Till(IsTouchProbeTriggered(1));
    Stop(1); Till(!IsMoving(1));
    GetTouchProbePos(1, &p);
    Print("latched %.3f", p);
}""")
    drive = sim.controller.axes[1].drive
    for _ in range(300):  # input on after 0.3 s of the run, off again at 0.5 s
        sim.step()
    drive.sensors.external |= DI_PROBE_INPUT
    for _ in range(200):
        sim.step()
    assert sim.messages == []  # a rising edge does not trigger a negative-edge probe
    drive.sensors.external &= ~DI_PROBE_INPUT
    sim.run(until=5)
    assert len(sim.messages) == 1
    latched = float(sim.messages[0].split()[1])
    assert 4.0 < latched < 5.0  # about 10 mm/s * (0.5 s - enable time)


def test_touch_probe_bad_axis_and_pointer():
    sim = sim_of("""
void main() {
    Print("%x %d %d", EnableTouchProbe(64), IsTouchProbeEnabled(64), IsTouchProbeTriggered(-1));
    GetTouchProbePos(0, 0);
}""")
    sim.run(until=1)
    assert sim.messages == ["138f 0 0"]
    assert sim.faults and "GetTouchProbePos" in sim.faults[0]
