"""The position trigger (manual chapter 12) on a controller: pulse count and positions,
interpolation inside the cycle, the velocity rule of 12.1.1, IsPTEnabled, the scope
channels, and the property: floor(|end - start| / interval) + 1 pulses at the
programmed positions for any start, end, interval and velocity within the rule."""

from __future__ import annotations

import math
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.io.trigger_commands import TriggerCommands
from motionvm.motion.commands import MotionCommands
from motionvm.sim.controller import Controller

settings.register_profile(
    "pt-ci", max_examples=30, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "pt-thorough", max_examples=300, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "pt-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "pt-ci"
)

POS_TOL = 1e-3
"""A pulse lies at its programmed position within 1 um [mm]."""
INVALID_VEL = 0x0140
INVALID_STATE = 0x0064


class Rig:
    """A controller with the motion and PT commands, stepped until a condition holds."""

    def __init__(self) -> None:
        self.ctl = Controller()
        self.m = MotionCommands(self.ctl.motion)
        self.pt = TriggerCommands(self.ctl.motion, self.ctl.triggers)
        self.samples: list[tuple[float, float]] = []

    def until(self, cond, limit: int = 100_000, axis: int = 0) -> None:
        for _ in range(limit):
            if cond():
                return
            self.ctl.step()
            t = (self.ctl.cycle - 1) * self.ctl.cycle_time
            self.samples.append((t, self.ctl.axes[axis].pos_fb))
        raise AssertionError("condition never held")

    def ready(self, axis: int = 0, at: float = 0.0) -> None:
        m = self.m
        m.Enable(axis)
        self.until(lambda: m.IsEnabled(axis))
        if at:
            m.MoveAbs(axis, at)
            self.until(lambda: m.IsInPos(axis))
        m.SetHomedStatus(axis, 1)

    def move(self, axis: int, target: float) -> int:
        code = self.m.MoveAbs(axis, target)
        if code == 0:
            self.until(lambda: self.m.IsInPos(axis), axis=axis)
        return code

    def fb_at(self, t: float) -> float:
        """The feedback position at `t`, interpolated between the recorded samples."""
        for (t0, x0), (t1, x1) in zip(self.samples, self.samples[1:]):
            if t0 <= t <= t1:
                return x0 + (x1 - x0) * (t - t0) / (t1 - t0)
        raise AssertionError(f"no sample around t={t}")


def test_equal_interval_positive_then_negative():
    r = Rig()
    r.ready()
    pt = r.pt
    assert pt.SetPT_StartPos(0, 10) == pt.SetPT_Interval(0, 1) == pt.SetPT_EndPos(0, 20) == 0
    assert pt.EnablePT(0) == 0 and pt.IsPTEnabled(0) == 1
    r.move(0, 30)
    trig = r.ctl.triggers[0]
    assert [p for _, p in trig.pulses] == [float(k) for k in range(10, 21)]
    assert pt.IsPTEnabled(0) == 0
    pt.SetPT_StartPos(0, 20)
    pt.SetPT_EndPos(0, 10)
    assert pt.EnablePT(0) == 0
    r.move(0, 0)
    assert [p for _, p in trig.pulses[11:]] == [float(k) for k in range(20, 9, -1)]
    assert trig.count == 22
    times = [t for t, _ in trig.pulses]
    assert times == sorted(times)
    for t, p in trig.pulses:
        assert abs(r.fb_at(t) - p) < POS_TOL


def test_array_mode_with_state_words_and_index_order():
    r = Rig()
    r.ready()
    pt = r.pt
    for i, pos in enumerate([10, 12, 13, 16, 17, 20, 22, 25, 26, 28, 30]):
        assert pt.SetPT_PosArray(0, i, pos) == 0
    pt.SetPT_StateArray(0, 0, 0b11111111011)  # position 2 (13 mm) stays silent
    pt.SetPT_StartIndex(0, 0)
    pt.SetPT_EndIndex(0, 10)
    assert pt.EnablePT(0) == 0
    r.move(0, 40)
    trig = r.ctl.triggers[0]
    assert [p for _, p in trig.pulses] == [10, 12, 16, 17, 20, 22, 25, 26, 28, 30]
    assert pt.IsPTEnabled(0) == 0
    pt.SetPT_StartIndex(0, 10)
    pt.SetPT_EndIndex(0, 0)
    pt.SetPT_StateArray(0, 0, -1)
    assert pt.EnablePT(0) == 0
    r.move(0, 0)
    assert [p for _, p in trig.pulses[10:]] == [30, 28, 26, 25, 22, 20, 17, 16, 13, 12, 10]


def test_non_monotonic_array_and_bad_arguments_are_refused():
    r = Rig()
    r.ready()
    pt = r.pt
    for i, pos in enumerate([1, 3, 2]):
        pt.SetPT_PosArray(0, i, pos)
    pt.SetPT_EndIndex(0, 2)
    assert pt.EnablePT(0) & 0xFFFFFFFF == 0x8300012C
    assert r.m.GetAxisLastErr(0) & 0xFFFFFFFF == 0x8300012C
    assert pt.SetPT_PulseWidth(0, 30) & 0xFFFF == 0x012C
    assert pt.SetPT_PulseWidth(0, 80_020) & 0xFFFF == 0x012C
    assert pt.SetPT_PulseWidth(0, 20) == 0
    assert pt.SetPT_Interval(0, 0.0) & 0xFFFF == 0x012C
    assert pt.SetPT_PosArray(0, 256, 1.0) & 0xFFFF == 0x012C
    assert pt.SetPT_StateArray(0, 8, 1) & 0xFFFF == 0x012C
    assert pt.EnablePT(99) == 0x138F and pt.IsPTEnabled(99) == 0


def test_a_train_of_more_positions_than_a_length_holds_is_refused():
    r = Rig()
    r.ready()
    pt = r.pt
    pt.SetPT_StartPos(0, 0.0)
    pt.SetPT_EndPos(0, 1e308)  # 1e308 positions 1 mm apart: finite, but no length holds it
    pt.SetPT_Interval(0, 1.0)
    assert pt.EnablePT(0) & 0xFFFFFFFF == 0x8300012C
    assert pt.IsPTEnabled(0) == 0


def test_pt_needs_a_homed_axis():
    r = Rig()
    pt = r.pt
    pt.SetPT_Interval(0, 1)
    assert pt.EnablePT(0) & 0xFFFFFFFF == 0x83000000 | INVALID_STATE


def test_velocity_rule_of_12_1_1():
    r = Rig()
    r.ready()
    pt, m = r.pt, r.m
    pt.SetPT_StartPos(0, 1)
    pt.SetPT_EndPos(0, 5)
    pt.SetPT_Interval(0, 0.05)  # 0.05 mm x 16 kHz = 800 mm/s
    assert pt.EnablePT(0) & 0xFFFFFFFF == 0x83000000 | INVALID_VEL  # SetVel is 1000
    assert m.GetAxisLastErr(0) & 0xFFFF == INVALID_VEL
    m.SetVel(0, 500)
    assert pt.EnablePT(0) == 0
    m.SetVel(0, 900)
    assert m.MoveAbs(0, 10) & 0xFFFF == INVALID_VEL  # the move is refused while armed
    assert m.MoveVel(0, 700) == 0  # a jog below the rule is fine
    r.until(lambda: not pt.IsPTEnabled(0))
    assert r.ctl.triggers[0].count == 81
    assert m.MoveVel(0, 900) == 0  # the PT is off again: no limit


def test_positions_passed_before_enabling_are_skipped():
    r = Rig()
    r.ready(at=15)
    pt = r.pt
    pt.SetPT_StartPos(0, 10)
    pt.SetPT_EndPos(0, 20)
    pt.SetPT_Interval(0, 1)
    assert pt.EnablePT(0) == 0
    r.move(0, 25)
    assert [p for _, p in r.ctl.triggers[0].pulses] == [15.0, 16, 17, 18, 19, 20]


def test_scope_channels_and_exact_edges():
    r = Rig()
    r.ready()
    pt = r.pt
    pt.SetPT_PulseWidth(0, 1000)
    pt.SetPT_StartPos(0, 1)
    pt.SetPT_EndPos(0, 3)
    pt.SetPT_Interval(0, 1)
    pt.EnablePT(0)
    src = r.ctl.triggers
    count, _ = src.resolve("axis0.pt_count")
    out, unit = src.resolve("axis0.pt_out")
    out.record_edges()  # as a recording does when it attaches
    assert unit == "bool" and src.resolve("axis0.ref_pos") is None
    r.move(0, 5)
    assert count() == 3 and out() == 0
    edges = out.edges()
    assert [lvl for _, lvl in edges] == [1, 0] * 3
    for (t_on, _), (t_off, _) in zip(edges[::2], edges[1::2]):
        assert t_off - t_on == pytest.approx(1e-6)


def test_run_waits_for_a_jog_through_the_positions():
    r = Rig()
    r.ready()
    pt, m = r.pt, r.m
    pt.SetPT_StartPos(0, 1)
    pt.SetPT_EndPos(0, 2)
    pt.SetPT_Interval(0, 0.5)
    pt.EnablePT(0)
    m.SetSWRL(0, 1000)
    m.IgnoreSWL(0, 1)
    m.MoveVel(0, 10)
    r.until(lambda: m.GetPosFb(0) > 0.2)
    assert r.ctl.busy()  # the PT still waits for its positions
    r.ctl.run(until=1.0)
    assert r.ctl.triggers[0].count == 3


@PROFILE
@given(
    start=st.floats(-50.0, 50.0),
    interval=st.floats(0.05, 2.0),
    k=st.integers(0, 30),
    frac=st.one_of(st.just(0.0), st.floats(0.01, 0.99)),
    negative=st.booleans(),
    speed=st.floats(0.05, 0.95),
)
def test_property_pulse_count_and_positions(start, interval, k, frac, negative, speed):
    d = -1.0 if negative else 1.0
    end = start + d * (k + frac) * interval
    r = Rig()
    r.ready(at=start - d * 1.0)
    limit = interval * 16000.0
    span = abs(end - start) + 2.0
    v = min(1000.0, max(span * 2.0, speed * limit), 0.95 * limit)
    r.m.SetVel(0, v)
    pt = r.pt
    pt.SetPT_StartPos(0, start)
    pt.SetPT_EndPos(0, end)
    pt.SetPT_Interval(0, interval)
    assert pt.EnablePT(0) == 0
    assert r.move(0, end + d * 1.0) == 0
    trig = r.ctl.triggers[0]
    assert trig.count == math.floor(abs(end - start) / interval * (1 + 1e-12)) + 1 == k + 1
    assert pt.IsPTEnabled(0) == 0
    for i, (t, p) in enumerate(trig.pulses):
        assert abs(p - (start + d * i * interval)) < POS_TOL
        assert abs(r.fb_at(t) - p) < POS_TOL


MANUAL = __import__("pathlib").Path(__file__).resolve().parents[1] / "programs" / "hmpl" / "manual"


@pytest.mark.parametrize(
    ("program", "positions"),
    [
        ("ch12_01_03_example_1.hmpl", list(range(10, 21)) + list(range(20, 9, -1))),
        (
            "ch12_01_03_example_2.hmpl",
            [
                10,
                12,
                13,
                16,
                17,
                20,
                22,
                25,
                26,
                28,
                30,
                30,
                28,
                26,
                25,
                22,
                20,
                17,
                16,
                13,
                12,
                10,
            ],
        ),
        ("ch12_01_03_example_2_axis_0.hmpl", []),
    ],
)
def test_manual_examples_pulse_at_their_positions(program, positions, tmp_path, monkeypatch):
    from motionvm.api import Simulation

    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    with Simulation.from_files([MANUAL / program]) as sim:
        sim.run(timeout=60)
        trig = sim.controller.triggers[1]
        assert [p for _, p in trig.pulses] == [float(p) for p in positions]
        assert trig.count == len(positions)


def test_vcd_has_each_pulse_at_its_exact_time(tmp_path):
    from motionvm.sim.scope import ScopeRecorder
    from motionvm.sim.scope_sources import registry_for

    r = Rig()
    r.ready()
    reg = registry_for(r.ctl)
    rec = ScopeRecorder(reg.resolve_all(["axis0.pt_out", "axis0.pos_fb"]), r.ctl.cycle_time)
    rec.attach(r.ctl)
    pt = r.pt
    pt.SetPT_PulseWidth(0, 2000)
    pt.SetPT_StartPos(0, 1)
    pt.SetPT_EndPos(0, 2)
    pt.SetPT_Interval(0, 0.5)
    pt.EnablePT(0)
    r.move(0, 3)
    rec.save(tmp_path / "pt.vcd")
    lines = (tmp_path / "pt.vcd").read_text().splitlines()
    assert "$timescale 1 ns $end" in lines
    ident = next(ln.split()[3] for ln in lines if ln.endswith("pt_out $end"))
    stamps = {}
    for ln in lines:
        if ln.startswith("#"):
            now = int(ln[1:])
        elif ln in (f"1{ident}", f"0{ident}"):
            stamps.setdefault(ln[0], []).append(now)
    pulses = r.ctl.triggers[0].pulses
    assert stamps["1"] == [round(t * 1e9) for t, _ in pulses]
    offs = stamps["0"][1:]  # the first is the initial value
    assert [off - on for on, off in zip(stamps["1"], offs)] == [2000] * 3


def test_a_last_position_between_two_counts_is_reached_by_a_move_to_it():
    r = Rig()
    r.ready()
    pt = r.pt
    pt.SetPT_StartPos(0, 10)
    pt.SetPT_EndPos(0, 20.00004)  # 0.4 counts past 20 mm: the axis stops on 20 mm
    pt.SetPT_Interval(0, 1.000004)
    assert pt.EnablePT(0) == 0
    r.move(0, 20.00004)
    assert r.ctl.triggers[0].count == 11 and pt.IsPTEnabled(0) == 0


def test_a_long_train_keeps_a_bounded_pulse_list_and_a_recording_every_edge():
    from motionvm.io.position_trigger import PULSES_KEPT

    r = Rig()
    r.ready()
    pt = r.pt
    assert pt.SetPT_StartPos(0, 0.5) == pt.SetPT_Interval(0, 0.01) == 0
    assert pt.SetPT_EndPos(0, 100.5) == 0  # 10001 positions, 15 pulses a cycle at 150 mm/s
    out, _ = r.ctl.triggers.resolve("axis0.pt_out")
    out.record_edges()  # a recording's channel keeps its edges
    read, _ = r.ctl.triggers.resolve("axis0.pt_out")  # a channel only read keeps none
    dropped, _ = r.ctl.triggers.resolve("axis0.pt_out")
    dropped.record_edges()
    del dropped  # nor does a recorded channel nobody holds any more
    r.m.SetVel(0, 150.0)
    assert pt.EnablePT(0) == 0
    r.move(0, 101.0)
    trig = r.ctl.triggers[0]
    assert trig.count == 10_001 and pt.IsPTEnabled(0) == 0
    assert PULSES_KEPT <= len(trig.pulses) < 2 * PULSES_KEPT
    assert trig.pulses[-1][1] == pytest.approx(100.5)
    assert [p for _, p in trig.pulses] == sorted(p for _, p in trig.pulses)
    assert list(trig._outputs) == [out] and read.times == [] and read() == 0
    edges = out.edges()
    assert len(edges) == 2 * 10_001 and [lvl for _, lvl in edges[:4]] == [1, 0, 1, 0]
