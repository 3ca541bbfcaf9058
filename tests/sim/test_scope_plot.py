"""Scope plots: which channels share a panel, references under feedback, bits, legends."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, Channel, ScopeRecorder
from motionvm.sim.scope_plot import (
    MAGNITUDE_FACTOR,
    build_figure,
    comparable,
    layout,
    pairs,
    signal_role,
)


def synthetic(signals: dict[str, tuple[str, list[float]]], cycle_time: float = 0.001):
    """A recorder holding `signals` (name -> (unit, one value per sample)), as if recorded."""
    n = len(next(iter(signals.values()))[1])
    step = {"k": 0}
    channels = [
        Channel(name, unit, lambda values=values: values[step["k"]])
        for name, (unit, values) in signals.items()
    ]
    rec = ScopeRecorder(channels, cycle_time)
    for k in range(n):
        step["k"] = k
        rec.sample(k)
    return rec


def ramp(lo: float, hi: float, n: int = 50) -> list[float]:
    return [lo + (hi - lo) * k / (n - 1) for k in range(n)]


def panel_names(rec) -> list[list[str]]:
    return [
        [rec.channels[t.index].name for t in p.traces] for p in layout(rec.channels, rec.columns)
    ]


# ---------------------------------------------------------------- layout (no matplotlib)


@pytest.mark.parametrize(
    ("name", "role"),
    [
        ("axis0.ref_pos", ("ref", ("axis0", ("pos",), ""))),
        ("axis0.pos_fb", ("fb", ("axis0", ("pos",), ""))),
        ("drive1.x_ref_pos", ("ref", ("drive1", ("x", "pos"), ""))),
        ("drive1.X_ACT_POS", ("fb", ("drive1", ("x", "pos"), ""))),
        ("drive1.ref_pos[0]", ("ref", ("drive1", ("pos",), "[0]"))),
        ("gantry0.linear_ref", ("ref", ("gantry0", ("linear",), ""))),
        ("axis0.coe_pos_cmd", ("ref", ("axis0", ("coe", "pos"), ""))),
        ("x_ref_pos", ("ref", ("", ("x", "pos"), ""))),
        ("axis0.pos_err", None),
        ("axis0.pos_fb_raw", ("fb", ("axis0", ("pos", "raw"), ""))),
        ("ref", None),
        ("system_dtest0", None),
    ],
)
def test_signal_roles(name, role):
    assert signal_role(name) == role


def test_references_pair_with_feedback_of_the_same_owner_and_unit():
    chans = [
        Channel("axis0.ref_pos", "mm", float),
        Channel("axis1.pos_fb", "mm", float),
        Channel("axis1.ref_pos", "mm", float),
        Channel("axis0.pos_fb", "mm", float),
        Channel("drive0.x_ref_pos", "count", float),
        Channel("drive0.x_act_pos", "mm", float),  # another unit: no pair
        Channel("axis0.ref_acc", "mm/s²", float),  # no feedback counterpart
    ]
    assert pairs(chans) == {0: 3, 2: 1}


def test_magnitude_rule():
    assert comparable([(-500.0, 500.0), (0.0, 100.0)])
    assert not comparable([(-500.0, 500.0), (-0.01, 0.01)])  # a following error: own panel
    assert not comparable([(1000.0, 1001.0), (0.0, 1.0)])  # far apart levels flatten both
    assert comparable([(0.0, 100.0), (5.0, 5.0)])  # a constant inside the range fits
    assert not comparable([(0.0, 1.0), (1e6, 1e6)])  # ... one far outside does not
    assert comparable([(0.0, MAGNITUDE_FACTOR), (0.0, 1.0)])
    assert not comparable([(0.0, MAGNITUDE_FACTOR * 1.01), (0.0, 1.0)])
    assert comparable([None, (0.0, 1.0)])  # a channel with no finite value fits anywhere


def test_panels_by_unit_and_magnitude():
    rec = synthetic(
        {
            "axis0.ref_pos": ("mm", ramp(-500, 500)),
            "axis0.pos_err": ("mm", ramp(-0.01, 0.01)),
            "axis0.ref_vel": ("mm/s", ramp(0, 1000)),
            "axis0.pos_fb": ("mm", ramp(-499, 499)),
            "axis1.ref_pos": ("mm", ramp(0, 200)),
            "gpo3": (BIT_UNIT, [k % 2 for k in range(50)]),
            "axis0.vel_fb": ("mm/s", ramp(0, 990)),
            "count": (RAW_UNIT, ramp(0, 5)),
            "axis0.di_bit_HOME": (BIT_UNIT, [k > 25 for k in range(50)]),
        }
    )
    assert panel_names(rec) == [
        ["axis0.ref_pos", "axis0.pos_fb", "axis1.ref_pos"],
        ["axis0.pos_err"],
        ["axis0.ref_vel", "axis0.vel_fb"],
        ["count"],
        ["gpo3", "axis0.di_bit_HOME"],
    ]
    roles = {
        rec.channels[t.index].name: t.role
        for p in layout(rec.channels, rec.columns)
        for t in p.traces
    }
    assert roles["axis0.ref_pos"] == "ref" and roles["axis0.pos_fb"] == "fb"
    assert roles["axis1.ref_pos"] == "plain" and roles["gpo3"] == "bit"


def test_a_reference_shares_with_its_feedback_even_when_one_rests():
    rec = synthetic(
        {"axis0.ref_pos": ("mm", [0.0] * 10), "axis0.pos_fb": ("mm", ramp(0, 1e-9, 10))}
    )
    assert panel_names(rec) == [["axis0.ref_pos", "axis0.pos_fb"]]


def test_each_channel_has_its_own_colour_and_style():
    rec = synthetic({f"v{i}": ("mm", ramp(0, 1 + i % 3)) for i in range(25)})
    [panel] = layout(rec.channels, rec.columns)
    looks = [(t.colour, str(t.linestyle)) for t in panel.traces]
    assert len(set(looks)) == 25


# ---------------------------------------------------------------- the figure


@pytest.fixture
def figure_of():
    pytest.importorskip("matplotlib")
    return build_figure


def test_figure_structure(figure_of):
    rec = synthetic(
        {
            "axis0.ref_pos": ("mm", ramp(-500, 500)),
            "axis0.pos_fb": ("mm", ramp(-499, 499)),
            "axis0.pos_err": ("mm", ramp(-0.01, 0.01)),
            "gpo3": (BIT_UNIT, [k % 2 for k in range(50)]),
            "gpi1": (BIT_UNIT, [k > 10 for k in range(50)]),
        }
    )
    fig = figure_of(rec, "move.hmpl")
    position, error, bits = fig.axes
    ref, fb = position.get_lines()
    assert (ref.get_label(), ref.get_linestyle()) == ("axis0.ref_pos [mm]", "--")
    assert (fb.get_label(), fb.get_linestyle()) == ("axis0.pos_fb [mm]", "-")
    assert ref.get_zorder() < fb.get_zorder()  # the reference is drawn under its feedback
    assert ref.get_color() != fb.get_color()
    assert [t.get_text() for t in position.get_legend().get_texts()] == [
        "axis0.ref_pos [mm]",
        "axis0.pos_fb [mm]",
    ]
    assert [t.get_text() for t in error.get_legend().get_texts()] == ["axis0.pos_err [mm]"]
    assert error.get_ylim()[1] < 0.1  # the following error is not flattened
    # bits: thin steps, stacked, each labelled on the y axis, in a compact panel
    assert [line.get_drawstyle() for line in bits.get_lines()] == ["steps-post"] * 2
    assert all(line.get_linewidth() < 1.0 for line in bits.get_lines())
    assert [t.get_text() for t in bits.get_yticklabels()] == ["gpo3", "gpi1"]
    assert [t.get_text() for t in bits.get_legend().get_texts()] == ["gpo3 [bool]", "gpi1 [bool]"]
    low_gpo3 = min(bits.get_lines()[0].get_ydata())
    assert low_gpo3 > max(bits.get_lines()[1].get_ydata())  # stacked, first on top
    assert bits.get_position().height < position.get_position().height / 2
    # one time axis in seconds
    assert position.get_shared_x_axes().joined(position, bits)
    assert bits.get_xlabel() == "time [s]"
    assert bits.get_xlim() == (0.0, 0.049)
    assert fig.get_suptitle() == "move.hmpl (50 samples)"


def test_figure_of_an_empty_recording(figure_of):
    rec = synthetic({"axis0.ref_pos": ("mm", []), "gpo1": (BIT_UNIT, [])})
    fig = figure_of(rec)
    assert len(fig.axes) == 2


def test_figure_with_nan(figure_of):
    rec = synthetic({"a": ("mm", [0.0, math.nan, 2.0]), "b": ("mm", [0.0, 1.0, math.inf])})
    assert len(figure_of(rec).axes) == 1


def test_plot_of_a_real_move(tmp_path: Path):
    pytest.importorskip("matplotlib")
    prog = tmp_path / "move.hmpl"
    prog.write_text(
        "void main() { Enable(0); Till(IsEnabled(0)); HIMC_GPO(3) = 1; MoveAbs(0, 20.0); "
        "Till(IsInPos(0)); HIMC_GPO(3) = 0; }\n"
    )
    out = tmp_path / "move.svg"
    argv = ["--scope", "axis0.ref_pos,axis0.pos_fb,axis0.ref_vel,gpo3", "--scope-out", out]
    assert main(["run", *map(str, argv), str(prog)]) == 0
    svg = out.read_text()
    assert svg.count('<g id="axes_') == 3  # position, velocity, bits
