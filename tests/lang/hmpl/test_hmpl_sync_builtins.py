"""HMPL gear and gantry built-ins (manual chapters 6, 7; 5.4.5 IsGantry, 5.4.7 IsSync) via the host API."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.lib.sync import SyncScopeSource
from motionvm.sim.scope import ScopeError
from motionvm.sim.scope_sources import registry_for

ENABLE_0_TO_3 = """
    int i;
    for (i = 0; i < 4; i++) Enable(i);
    for (i = 0; i < 4; i++) Till(IsEnabled(i));
"""


def run(body: str, until: float | None = None) -> list[str]:
    sim = Simulation.from_source("void main() {" + body + "}")
    sim.run(until)
    assert not sim.faults, sim.faults
    return sim.messages


def test_gear_status_through_its_life():
    out = run(
        ENABLE_0_TO_3
        + """
    Print("%d %d %d %d %d", IsGearMaster(0), IsGearSlave(1), IsSync(1), IsInGear(1), GetGearRatio(1) == 0.0);
    Print("%d", EnableGear(0, 1));
    Print("%d %d %d %d %d", IsGearMaster(0), IsGearSlave(1), IsSync(1), IsInGear(1), IsGearMaster(1));
    Print("%d %.2f %d", GearIn(0, 1, -2.5), GetGearRatio(1), IsInGear(1));
    MoveRel(0, 10); Till(IsInPos(0));
    Print("%.4f", GetRefPos(1));
    Print("%d %d %d", GearOut(1), IsInGear(1), IsGearSlave(1));
    Print("%d %d %d %d", DisableGear(1), IsGearSlave(1), IsSync(1), IsGearMaster(0));
"""
    )
    assert out == ["0 0 0 0 1", "0", "1 1 1 0 0", "0 -2.50 1", "-25.0000", "0 0 1", "0 0 0 0"]


def test_gear_errors_return_and_store_the_manual_codes():
    out = run(
        ENABLE_0_TO_3
        + """
    Disable(3);
    Print("%x %x", EnableGear(0, 3), GetAxisLastErr(3));
    Print("%x %x", EnableGear(0, 99), GetSystemLastErr());
    Print("%x", EnableGear(2, 2));
    Print("%x %x", GearIn(0, 1, 1.0), GearOut(1));
    EnableGear(0, 1);
    Print("%x %x", GearIn(0, 1, 0.0), GearIn(2, 1, 1.0));
    GearIn(0, 1, 1.0);
    Print("%x %x", DisableGear(1), GetAxisLastErr(1));
    Print("%x %x", EnableGear(1, 2), EnableGear(2, 0));
    Print("%d %d %.1f", IsInGear(42), IsGearSlave(-1), GetGearRatio(8));
    GearOut(1);
"""
    )
    assert out == [
        "83030078 83030078",
        "138f 138f",
        "830201c2",
        "83010fa0 83010fa0",
        "830101d6 830101c2",
        "830100a0 830100a0",
        "830100a0 830000aa",
        "0 0 0.0",
    ]


def test_a_slave_follows_a_master_with_a_higher_id():
    sim = Simulation.from_source(
        "void main() {"
        + ENABLE_0_TO_3
        + """
    EnableGear(3, 1); GearIn(3, 1, 2.0);
    MoveAbs(3, 40); Till(IsInPos(3));
    Print("%.4f", GetPosFb(1));
    GearOut(1);
}"""
    )
    axes = sim.controller.axes
    trace = []
    while sim.controller.busy():
        sim.step()
        trace.append((axes[3].ref_pos, axes[1].ref_pos))
    assert sim.messages == ["80.0000"]
    lag = sim.controller.motion.gears.lag_cycles(1)  # 1 while axes step in id order
    moving = [i for i in range(1, len(trace)) if trace[i][0] != trace[i - 1][0]]
    assert moving
    for i in moving:
        assert trace[i][1] == pytest.approx(2.0 * trace[i - lag][0])


GANTRY_UP = """
    EnableGantryPair(0, 1);
    Enable(1);
    Till(IsEnabled(0) && IsEnabled(1));
"""


def test_gantry_pair_status_and_ids():
    out = run("""
    Print("%d %d %d %d", IsGantry(0), GetGantryPairID(0), IsGantryPair(0, 1), DisableGantryPair(0));
    Print("%d", EnableGantryPair(2, 5));
    Print("%d %d %d %d", EnableGantryPair(0, 1), GetGantryPairID(1), GetGantryPairID(5), IsGantry(1));
    Print("%d %d %d", IsGantryPair(1, 0), IsGantryPair(5, 2), IsGantryPair(0, 2));
    Print("%d %d %d", DisableGantryPair(5), GetGantryPairID(2), IsGantry(5));
    Print("%d %d", GetGantryPairID(77), IsGantryPair(0, 77));
""")
    assert out == ["0 -1 0 0", "0", "0 1 0 1", "1 1 0", "0 -1 0", "-1 0"]


def test_gantry_errors_return_and_store_the_manual_codes():
    out = run("""
    Enable(2); Till(IsEnabled(2));
    Print("%x %x", EnableGantryPair(0, 2), GetAxisLastErr(2));
    Print("%x %x", EnableGantryPair(3, 3), EnableGantryPair(3, 9));
    EnableGantryPair(0, 1);
    Print("%x", EnableGantryPair(4, 1));
    Enable(0); Till(IsEnabled(0) && IsEnabled(1));
    Print("%x", DisableGantryPair(1));
    Print("%x %x", EnableGear(1, 2), EnableGear(2, 0));
    Disable(0);
    Till(!IsEnabled(1));
    Print("%d", DisableGantryPair(1));
""")
    assert out == [
        "8302006e 8302006e",
        "8303012c 138f",
        "830100dc",
        "8300006e",
        "830100dc 830000dc",
        "0",
    ]


def test_enabling_either_gantry_axis_powers_both_and_the_rhs_moves_the_linear_axis():
    sim = Simulation.from_source(
        "void main() {"
        + GANTRY_UP
        + """
    MoveAbs(0, 25);
    MoveAbs(1, 0.5);
    Sleep(300);
    Print("%.4f %.4f", GetPosFb(0), GetPosFb(1));
}"""
    )
    sim.run(until=0.5)
    # GetPosFb of the paired axes reads linear and yaw (manual 7.1); the motors at 25.5/24.5
    assert sim.messages == ["25.0000 0.5000"]
    motors = sim.controller.motion.axes
    assert (round(motors[0].pos_fb, 4), round(motors[1].pos_fb, 4)) == (25.5, 24.5)


def test_the_sync_channels_are_offered_to_the_scope():
    sim = Simulation.from_source(
        "void main() {"
        + ENABLE_0_TO_3
        + """
    EnableGear(0, 2); GearIn(0, 2, 3.0); MoveAbs(0, 5); Till(IsInPos(0));
}"""
    )
    reg = registry_for(sim.controller, sim.runtime)
    assert sum(isinstance(s, SyncScopeSource) for s in reg.sources) == 1
    names = reg.names()
    assert "gear2.gear_cmd_pos" in names and "gantry0.yaw_fb" in names
    channels = [reg.resolve(n) for n in ("gear2.gear_cmd_pos", "gear2.master_pos_gear",
                                         "gear2.gear_ratio", "gantry0.linear_fb")]  # fmt: skip
    assert [c.getter() for c in channels] == [0.0, 0.0, 0.0, 0.0]  # no gear yet
    assert [c.unit for c in channels] == ["mm", "mm", "raw", "mm"]
    sim.run(until=1.0)
    assert [c.getter() for c in channels] == pytest.approx([15.0, 5.0, 3.0, 0.0])
    src = SyncScopeSource(sim.controller)
    assert src.resolve("axis0.ref_pos") is None
    with pytest.raises(ScopeError, match="gear channels are gear0..gear7"):
        src.resolve("gear2.ratio")


def test_paired_gantry_axes_read_as_linear_and_yaw():
    """Manual 7.1: Pos_linear = (RHS + LHS) / 2 on the RHS axis, Pos_yaw = (RHS - LHS) / 2 on the LHS."""
    from motionvm.api import Simulation

    sim = Simulation.from_source("""
void main() {
    EnableGantryPair(0, 1);
    Enable(0);
    Till(IsEnabled(0) && IsEnabled(1));
    Till(IsGantry(0) && IsGantry(1));
    MoveAbs(0, 20.0);
    Till(IsInPos(0));
    MoveAbs(1, 2.0);
    Till(IsInPos(1));
    Print("linear %.3f yaw %.3f ref %.3f %.3f", GetPosFb(0), GetPosFb(1), GetRefPos(0), GetRefPos(1));
}
""")
    sim.run(until=3.0)
    assert sim.messages == ["linear 20.000 yaw 2.000 ref 20.000 2.000"]
    motors = sim.controller.motion.axes
    assert (round(motors[0].pos_fb, 6), round(motors[1].pos_fb, 6)) == (22.0, 18.0)
