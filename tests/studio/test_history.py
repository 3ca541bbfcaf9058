"""The studio's recording: bounded memory by halving its resolution, rows kept across a
replay, cut by a new input, thinned windows."""

from __future__ import annotations

import math

from motionvm.studio.history import History, Recorder
from motionvm.studio.views import state_text


class Clock:
    cycle = 0


def test_a_full_history_halves_its_resolution_and_keeps_its_whole_span():
    h = History(0.001, capacity=64)
    h.ensure(["x"])
    for c in range(1000):
        h.add(c, {"x": c * 2.0})
    assert len(h) < 64 and h.stride == 16  # 1000 cycles: 63 rows
    assert h.cycles[0] == 0 and h.cycles[-1] >= 1000 - h.stride
    assert all(c % h.stride == 0 for c in h.cycles)
    assert list(h.columns["x"]) == [c * 2.0 for c in h.cycles]


def test_rows_already_held_are_not_recorded_again_and_an_input_cuts_the_future():
    h, clock = History(0.001), Clock()
    rec = Recorder(h, clock, {"x": lambda: clock.cycle * 1.5})
    for c in range(10):
        clock.cycle = c
        rec.end_cycle()
    second = Recorder(h, clock, {"x": lambda: -1.0})  # a replay from cycle 4
    for c in range(4, 10):
        clock.cycle = c
        second.end_cycle()
    assert list(h.columns["x"]) == [c * 1.5 for c in range(10)]
    h.cut_after(5)
    assert h.last_cycle == 5
    clock.cycle = 6
    second.end_cycle()
    assert h.columns["x"][-1] == -1.0


def test_a_column_added_later_reads_nothing_before_it_and_windows_are_thinned():
    h = History(0.001)
    h.ensure(["x"])
    for c in range(100):
        h.add(c, {"x": 1.0})
    h.ensure(["y"])
    h.add(100, {"x": 1.0, "y": 2.0})
    assert math.isnan(h.columns["y"][0]) and h.row(100) == {"x": 1.0, "y": 2.0}
    assert h.row(0)["y"] is None  # JSON has no NaN
    times, values = h.window(0, 100, ["x", "y"], points=10)
    assert 10 <= len(times) <= 11 and times[0] == 0.0
    assert len(values["y"]) == len(times)
    assert h.index_at(1000) == 100 and h.index_at(-1) is None


def test_a_thinned_window_ends_at_its_last_row():
    h = History(0.001)
    h.ensure(["x"])
    for c in range(98):
        h.add(c, {"x": float(c)})
    for points in (1, 7, 10, 32, 97, 98, 200):
        times, values = h.window(0, 97, ["x"], points=points)
        assert times[-1] == 0.097 and values["x"][-1] == 97.0 and values["x"][0] == 0.0
        assert len(times) <= points + 1
    times, values = h.window(10, 20, ["x"], points=3)
    assert values["x"][0] == 10.0 and values["x"][-1] == 20.0


def test_an_axis_state_word_reads_as_the_table_shows_it():
    assert state_text(0) == "disabled"
    assert state_text(0b1) == "standstill"
    assert state_text(0b11) == "moving"
    assert state_text(0b10001) == "homing"
    assert state_text(0b1001) == "error"
    assert state_text(None) == "?"
