"""scope(channels, every): record from now on; the data as a DataFrame or a dict of lists."""

from __future__ import annotations

import sys

import pytest
from api_programs import COUNTER

from motionvm.api import Recording, Simulation


def recording(every: int = 1) -> tuple[Simulation, Recording]:
    sim = Simulation.from_source(COUNTER)
    sim.step(2)
    rec = sim.scope(["count", "axis0.pos_fb", "gpi3"], every=every)
    return sim, rec


def test_recording_starts_now_and_samples_every_cycle():
    sim, rec = recording()
    sim.step(3)
    sim.write("gpi3", 1)
    sim.step(1)
    data = rec.as_dict()
    assert data == {
        "time": [0.002, 0.003, 0.004, 0.005],
        "count": [3, 4, 5, 6],
        "axis0.pos_fb": [0.0] * 4,
        "gpi3": [0, 0, 0, 1],
    }
    assert rec.units == {"count": "raw", "axis0.pos_fb": "mm", "gpi3": "bool"}


def test_every_nth_cycle_and_stop():
    sim, rec = recording(every=2)
    sim.step(4)
    rec.stop()
    sim.run()
    assert rec.as_dict()["count"] == [3, 5]


def test_without_pandas_data_names_the_extra_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas -> ImportError
    sim, rec = recording()
    sim.step(2)
    with pytest.raises(ImportError, match=r"pip install 'motionvm\[data\]'"):
        rec.data()
    assert rec.as_dict()["count"] == [3, 4]  # needs nothing


def test_with_pandas_the_data_is_a_dataframe_indexed_by_time():
    pd = pytest.importorskip("pandas")
    sim, rec = recording()
    sim.step(2)
    frame = rec.data()
    assert isinstance(frame, pd.DataFrame)
    assert frame.index.name == "time" and list(frame.index) == [0.002, 0.003]
    assert list(frame.columns) == ["count", "axis0.pos_fb", "gpi3"]
    assert list(frame["count"]) == [3, 4]


def test_an_unknown_channel_is_a_key_error():
    sim = Simulation.from_source(COUNTER)
    with pytest.raises(KeyError, match="did you mean count"):
        sim.scope(["coutn"])
    with pytest.raises(ValueError, match="every"):
        sim.scope(["count"], every=0)
