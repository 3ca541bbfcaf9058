"""HMPL axis, error and bus built-ins (manual chapters 5, 18, 2) through the host API."""

from __future__ import annotations

from motionvm.api import Simulation
from motionvm.motion.axis_config import create
from motionvm.sim.machine import MachineConfig
from motionvm.source.diagnostics import CompileError


def sim_of(source: str, axes: list[dict] | None = None) -> Simulation:
    if axes is None:
        return Simulation.from_source(source)
    return Simulation.from_source(source, machine=MachineConfig(axes=tuple(map(create, axes))))


def test_move_and_wait_in_position():
    sim = sim_of("""
void main() {
    Enable(0); Till(IsEnabled(0));
    MoveAbs(0, 12.5); Till(IsInPos(0));
    Print("%.4f %d %d", GetPosFb(0), IsMoving(0), IsInPos(0));
}
""")
    sim.run()
    assert sim.messages == ["12.5000 0 1"]
    assert not sim.faults


def test_the_run_ends_only_when_the_motion_has_finished():
    sim = sim_of("void main() { Enable(0); Till(IsEnabled(0)); MoveAbs(0, 100); }")
    sim.run()
    axis = sim.controller.axes[0]
    assert axis.in_pos and axis.pos_fb == 100.0
    assert sim.time >= 0.2


def test_the_clock_jumps_while_every_axis_rests():
    sim = sim_of(
        'void main() { Enable(0); Till(IsInPos(0)); Sleep(5000); Print("%d", system_timeInMs); }'
    )
    stepped = []
    real_step = sim.controller.step
    sim.controller.step = lambda *args, **kw: (stepped.append(1), real_step(*args, **kw))[1]
    sim.run()
    assert sim.messages and int(sim.messages[0]) > 5000
    assert len(stepped) < 100  # the 5 s sleep was jumped over


def test_two_runs_give_identical_traces():
    source = """
void main() {
    int i;
    for (i = 0; i < 4; i++) Enable(i);
    for (i = 0; i < 4; i++) Till(IsEnabled(i));
    SetSMTime(1, 30);
    MoveAbs(0, 100); MoveAbs(1, -50); MoveVel(2, 300); MoveRel(3, 7.5);
    Sleep(120);
    MoveAbs(0, -20); SetVelScale(1, 40); Stop(2);
    for (i = 0; i < 4; i++) Till(IsInPos(i));
}
"""

    def trace():
        sim = sim_of(source)
        rows = []
        for _ in range(700):
            sim.step()
            rows.append(tuple((a.ref_pos, a.pos_fb, a.ref_vel, a.motion_status, a.fault_status)
                              for a in sim.controller.axes))  # fmt: skip
        return rows

    first, second = trace(), trace()
    assert first == second
    assert first[-1][0][1] == -20.0 and first[-1][3][1] == 7.5


def test_drive_fault_from_the_host_is_seen_by_the_program():
    sim = sim_of("""
void main() {
    Enable(0); Till(IsEnabled(0));
    Till(IsDriveErr(0));
    Print("%d %d %x %x", IsEnabled(0), IsErrorStop(0), GetDriveErr(0), GetAxisLastErr(0));
    Reset(0);
    Till(!IsErrorStop(0));
    Print("%d %d", IsDriveErr(0), GetDriveErr(0));
}
""")
    sim.run(until=0.05)
    sim.controller.axes[0].drive.inject_fault(0x7305)
    sim.run(until=1.0)
    assert sim.messages == ["0 1 7305 830003f2", "0 0"]


def test_move_pvt_checks_its_count_and_its_times():
    sim = sim_of("""
void main() {
    double t[3] = {100.0, 50.0, 200.0};
    double p[3] = {1.0, 2.0, 3.0};
    double v[3] = {0.0, 0.0, 0.0};
    Enable(0); Till(IsEnabled(0));
    Print("%x %x", MovePVT(0, t, p, v, 51), MovePVT(0, t, p, v, 3));
    t[1] = 150.0;
    Print("%d", MovePVT(0, t, p, v, 3));
    Till(IsInPos(0));
    Print("%.1f", GetPosFb(0));
}
""")
    sim.run()
    assert sim.messages == ["8300012c 830008b6", "0", "3.0"]


def test_buffered_moves_are_counted():
    sim = sim_of("""
void main() {
    Enable(0); Till(IsEnabled(0));
    Print("%d", SetBufferMode(0, 1));
    MoveAbs(0, 10); MoveAbs(0, 20); MoveRel(0, 5);
    Print("%d %d", GetBufferMode(0), GetCmdNum(0));
    Till(IsInPos(0));
    Print("%d %.1f", GetCmdNum(0), GetPosFb(0));
}
""")
    sim.run()
    assert sim.messages == ["0", "1 2", "0 25.0"]


def test_torque_mode_and_current_feedback():
    sim = sim_of("""
void main() {
    Enable(0); Till(IsEnabled(0));
    Print("%x", MoveTrq(0, 0.5));
    Print("%d", SetOpMode(0, 10));
    Print("%d", MoveTrq(0, 3.0));
    Sleep(5);
    Print("%.2f %d", GetCurrFb(0), GetVelFb(0) > 0);
    Stop(0);
    Till(!IsMoving(0));
}
""")
    sim.run(until=2.0)
    assert sim.messages == ["830000f0", "0", "0", "2.00 1"]


def test_rollover_of_a_rotary_axis():
    sim = sim_of(
        """
void main() {
    SetRollover(0, 360);
    Enable(0); Till(IsEnabled(0));
    Print("%x", SetRollover(0, 90));
    MoveVel(0, 720); Sleep(1500); Stop(0); Till(IsInPos(0));
    Print("%d %d", GetRolloverTurns(0), GetPosFb(0) >= 0 && GetPosFb(0) < 360);
}
""",
        axes=[{"type": "rotary", "sw_left": -1e6, "sw_right": 1e6}],
    )
    sim.run()
    assert sim.messages[0] == "8300006e"
    assert sim.messages[1] in ("2 1", "3 1")


def test_a_rollover_below_one_encoder_count_is_refused():
    # 10000 counts per mm: one count is 0.0001 mm, the smallest rollover taken
    sim = sim_of("""
void main() {
    SetPos(0, 1); SetPos(1, -1);
    Print("%x %x", SetRollover(0, 1e-320), SetRollover(1, 0.00009));
    Print("%d %d", SetRollover(0, 0.0001), SetRollover(1, 0.0001));
    Print("%d %d", GetRolloverTurns(0), GetRolloverTurns(1));
}
""")
    sim.run()
    assert sim.messages == ["830001f4 830101f4", "0 0", "10000 -10000"]


def test_rollover_turns_beyond_an_int_saturate():
    # one count of rollover (10000 counts per mm) 1 m from the origin: 1e10 turns
    sim = sim_of("""
void main() {
    SetPos(0, 1e6); SetPos(1, -1e6);
    SetRollover(0, 0.0001); SetRollover(1, 0.0001);
    Print("%d %d", GetRolloverTurns(0), GetRolloverTurns(1));
}
""")
    sim.run()
    assert sim.messages == ["2147483647 -2147483648"]


def test_set_hmi_scope_sets_the_controller_flag():
    sim = sim_of("void main() { SetHMIScope(1); Sleep(10); SetHMIScope(0); }")
    sim.run(until=0.005)
    assert sim.controller.hmi_scope is True
    sim.run()
    assert sim.controller.hmi_scope is False


def test_estop_stops_every_task_and_disables_every_axis():
    sim = Simulation.from_source("""
void main() {
    StartTask(1);
    Enable(0); Till(IsEnabled(0));
    MoveVel(0, 100);
    Sleep(50);
    EStop();
}
#if _TASKID_ == 1
#endif
""")
    sim.run(until=1.0)
    assert not sim.controller.axes[0].enabled
    assert not sim.controller.kernel.any_running
    assert sim.controller.motion.system_last_error == 0x64


def test_a_misspelt_axis_function_gets_a_did_you_mean():
    try:
        Simulation.from_source("void main() { Enable(0); Till(isEnabled(0)); }")
    except CompileError as exc:
        assert "did you mean 'IsEnabled'" in str(exc)
    else:
        raise AssertionError("no compile error")
