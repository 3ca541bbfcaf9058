"""Scope plots: channels -> panels (by unit and magnitude) -> a matplotlib Figure.

The rules (docs/scope.md, "Plots"):
- Time [s] on one x axis shared by every panel.
- A *reference* channel is drawn dashed, under its *feedback* counterpart (solid), in
  the same panel and the same hue (the reference lighter). A name is a reference when
  one of its `_`-separated words is `ref` or `cmd`, feedback when one is `fb`, `act`
  or `actual`; the two are counterparts when the rest of the name (the owner before
  the first `.`, the other words, an index) and the unit are the same: `axis0.ref_pos`
  and `axis0.pos_fb`, `drive1.x_ref_pos` and `drive1.x_act_pos`, `gantry0.linear_ref`
  and `gantry0.linear_fb`, `axis0.coe_pos_cmd` and `axis0.coe_pos_fb`. A reference
  recorded without its feedback is an ordinary solid trace.
- Channels share a panel only when they have the same unit and comparable magnitudes:
  with all of them, the panel's y range (lowest to highest value) is at most
  `MAGNITUDE_FACTOR` (20) times the peak-to-peak of each channel in it that is not
  constant. So a 0.01 mm following error gets its own panel beside a 500 mm position,
  and a position resting near 1000 mm does not share with one moving 0..1 mm. A
  reference and its feedback always share. Panels are filled in the order of the
  channels: a channel (or pair) joins the first panel it fits, else opens a new one.
- Bits (unit `bool`) are thin step traces stacked in one compact panel at the bottom,
  each labelled with its name on the y axis.
- Each channel has its own colour and line style; every panel has a legend of its
  channels with their units.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT

MAGNITUDE_FACTOR = 20.0
"""Channels share a panel while its y range is within this factor of each one's peak-to-peak."""
REFERENCE_WORDS = frozenset({"ref", "cmd"})
FEEDBACK_WORDS = frozenset({"fb", "act", "actual"})

# matplotlib's tab20: hue k is a dark shade 2k (feedback, plain channels) and a light 2k + 1
# (its reference).
PALETTE = (
    "#1f77b4", "#aec7e8", "#ff7f0e", "#ffbb78", "#2ca02c", "#98df8a", "#d62728", "#ff9896",
    "#9467bd", "#c5b0d5", "#8c564b", "#c49c94", "#e377c2", "#f7b6d2", "#7f7f7f", "#c7c7c7",
    "#bcbd22", "#dbdb8d", "#17becf", "#9edae5",
)  # fmt: skip
HUES = len(PALETTE) // 2
PLAIN_STYLES: tuple = ("-", "-.", (0, (1, 1)))  # a new style each time the hues repeat
REFERENCE_STYLES: tuple = ("--", (0, (8, 3)), (0, (3, 2)))

FIGURE_WIDTH = 10.0  # [in]
ANALOG_HEIGHT = 2.4  # [in] of one panel of numbers
BIT_ROW_HEIGHT = 0.28  # [in] per bit in the bits panel
BIT_PANEL_PAD = 0.35  # [in]
TITLE_HEIGHT = 0.9  # [in]
BIT_PITCH = 1.5  # rows of the bits panel are this far apart; a bit's trace spans 0..1

_INDEX = re.compile(r"(.*?)(\[.*\])?")


@dataclass(frozen=True, slots=True)
class Trace:
    """One channel as drawn."""

    index: int
    """The channel's position in the recorder's channels (and columns)."""
    role: str
    """`ref` (dashed, under its feedback), `fb`, `plain` or `bit`."""
    colour: str
    linestyle: str | tuple


@dataclass(slots=True)
class Panel:
    """One subplot: channels of one unit and comparable magnitude, or all the bits."""

    unit: str
    traces: list[Trace] = field(default_factory=list)

    @property
    def is_bits(self) -> bool:
        return self.unit == BIT_UNIT


def signal_role(name: str) -> tuple[str, tuple] | None:
    """(`ref` or `fb`, the counterpart key) of a reference or feedback name, else None.

    `axis0.ref_pos` -> ('ref', ('axis0', ('pos',), '')); `axis0.pos_fb` gives the same
    key as `fb`. Case is ignored, as PDL names ignore it.
    """
    owner, dot, variable = name.lower().partition(".")
    if not dot:
        owner, variable = "", owner
    m = _INDEX.fullmatch(variable)
    base, index = (m.group(1), m.group(2) or "") if m else (variable, "")
    words = base.split("_")
    for role, marks in (("ref", REFERENCE_WORDS), ("fb", FEEDBACK_WORDS)):
        hits = [w for w in words if w in marks]
        if len(hits) == 1 and len(words) > 1:
            rest = tuple(w for w in words if w not in marks)
            return role, (owner, rest, index)
    return None


def pairs(channels: Sequence) -> dict[int, int]:
    """Reference channel index -> its feedback counterpart's index (same key and unit)."""
    roles = [None if c.is_bit else signal_role(c.name) for c in channels]
    out: dict[int, int] = {}
    taken: set[int] = set()
    for i, r in enumerate(roles):
        if r is None or r[0] != "ref":
            continue
        for j, f in enumerate(roles):
            if (
                j not in taken
                and f is not None
                and f[0] == "fb"
                and f[1] == r[1]
                and channels[j].unit == channels[i].unit
            ):
                out[i] = j
                taken.add(j)
                break
    return out


def extent(values: Sequence[float]) -> tuple[float, float] | None:
    """(lowest, highest) finite value; None if there is none."""
    finite = [float(v) for v in values if math.isfinite(v)]
    return (min(finite), max(finite)) if finite else None


def comparable(extents: Sequence[tuple[float, float] | None]) -> bool:
    """True if channels with these extents may share a panel (MAGNITUDE_FACTOR)."""
    known = [e for e in extents if e is not None]
    if not known:
        return True
    span = max(hi for _, hi in known) - min(lo for lo, _ in known)
    return all(span <= MAGNITUDE_FACTOR * (hi - lo) for lo, hi in known if hi > lo)


def layout(channels: Sequence, columns: Sequence[Sequence[float]]) -> list[Panel]:
    """The panels of a plot, top to bottom: numbers first, then one panel of bits."""
    partner = pairs(channels)
    fb_of = {fb: ref for ref, fb in partner.items()}
    groups: list[list[int]] = []
    seen: set[int] = set()
    for i in range(len(channels)):
        if i in seen:
            continue
        ref = fb_of.get(i, i)
        group = [ref, partner[ref]] if ref in partner else [i]
        seen.update(group)
        groups.append(group)

    extents = [None if c.is_bit else extent(col) for c, col in zip(channels, columns)]
    panels: list[Panel] = []
    bits = Panel(BIT_UNIT)
    for g, group in enumerate(groups):
        hue, repeat = g % HUES, (g // HUES) % len(PLAIN_STYLES)
        traces = []
        for i in group:
            if channels[i].is_bit:
                role = "bit"
            elif len(group) == 1:
                role = "plain"
            else:
                role = "ref" if i in partner else "fb"
            light = role == "ref"
            colour = PALETTE[2 * hue + light]
            style = REFERENCE_STYLES[repeat] if light else PLAIN_STYLES[repeat]
            traces.append(Trace(i, role, colour, style))
        if traces[0].role == "bit":
            bits.traces.extend(traces)
            continue
        unit = channels[group[0]].unit
        for panel in panels:
            members = [t.index for t in panel.traces] + group
            if panel.unit == unit and comparable([extents[i] for i in members]):
                panel.traces.extend(traces)
                break
        else:
            panels.append(Panel(unit, traces))
    if bits.traces:
        panels.append(bits)
    return panels


def legend_label(channel) -> str:
    return f"{channel.name} [{channel.unit}]"


def _y_label(unit: str) -> str:
    if unit == BIT_UNIT:
        return "bits"
    if unit == RAW_UNIT:
        return "value"
    return f"[{unit}]"


def panel_height(panel: Panel) -> float:
    """[in]"""
    if panel.is_bits:
        return BIT_PANEL_PAD + BIT_ROW_HEIGHT * len(panel.traces)
    return ANALOG_HEIGHT


def build_figure(recorder, title: str = ""):
    """The scope plot of `recorder` as a matplotlib Figure (with an Agg canvas), one
    subplot per panel of `layout`; nothing is written."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    channels, columns, times = recorder.channels, recorder.columns, recorder.times
    panels = layout(channels, columns) or [Panel(RAW_UNIT)]
    heights = [panel_height(p) for p in panels]
    fig = Figure(figsize=(FIGURE_WIDTH, TITLE_HEIGHT + sum(heights)), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(
        len(panels), 1, sharex=True, squeeze=False, gridspec_kw={"height_ratios": heights}
    )[:, 0]
    for ax, panel in zip(axes, panels):
        if panel.is_bits:
            _draw_bits(ax, panel, channels, columns, times)
        else:
            for t in panel.traces:
                ax.plot(
                    times,
                    columns[t.index],
                    label=legend_label(channels[t.index]),
                    color=t.colour,
                    linestyle=t.linestyle,
                    linewidth=1.8 if t.role == "ref" else 1.1,
                    zorder=2 if t.role == "ref" else 3,  # the reference under its feedback
                )
            ax.grid(True, linewidth=0.3)
        ax.set_ylabel(_y_label(panel.unit))
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    if len(times) > 1 and times[-1] > times[0]:
        axes[-1].set_xlim(times[0], times[-1])
    axes[-1].set_xlabel("time [s]")
    every = f", every {recorder.every} cycles" if recorder.every > 1 else ""
    fig.suptitle(f"{title or 'motionvm scope'} ({len(times)} samples{every})")
    return fig


def _draw_bits(ax, panel: Panel, channels, columns, times) -> None:
    """Bits stacked top to bottom in the order of the channels, 0/1 steps on a row each."""
    n = len(panel.traces)
    ticks, names = [], []
    for row, t in enumerate(panel.traces):
        base = (n - 1 - row) * BIT_PITCH
        ax.plot(
            times,
            [base + (1.0 if v else 0.0) for v in columns[t.index]],
            label=legend_label(channels[t.index]),
            color=t.colour,
            linestyle=t.linestyle,
            linewidth=0.8,
            drawstyle="steps-post",
        )
        ticks.append(base + 0.5)
        names.append(channels[t.index].name)
    ax.set_yticks(ticks, names, fontsize="small")
    ax.set_ylim(-0.25, (n - 1) * BIT_PITCH + 1.25)
    ax.grid(True, axis="x", linewidth=0.3)
