"""A simulation as a context manager: close() frees its memory; so does dropping it."""

from __future__ import annotations

import gc
import os

import pytest
from api_programs import COUNTER

from motionvm.api import SessionError, Simulation

RSS_GROWTH_LIMIT_MB = 100.0
"""50 simulations of ~24 MB each may not leave more than this behind."""


def rss_mb() -> float:
    resident_pages = int(open("/proc/self/statm").read().split()[1])
    return resident_pages * os.sysconf("SC_PAGE_SIZE") / 1e6


def test_a_with_block_closes_the_simulation():
    with Simulation.from_source(COUNTER) as sim:
        sim.run()
        assert not sim.closed
    assert sim.closed
    assert sim.messages == ["count 10 table[3] 0"]  # what it recorded stays readable


def test_a_closed_simulation_cannot_run():
    sim = Simulation.from_source(COUNTER)
    sim.close()
    sim.close()  # twice is fine
    with pytest.raises(SessionError, match="closed"):
        sim.run()
    with pytest.raises(SessionError, match="closed"):
        sim.step()


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc")
@pytest.mark.parametrize("how", ["drop", "close"])
def test_fifty_simulations_leave_bounded_memory(how):
    gc.collect()
    before = rss_mb()
    for _ in range(50):
        sim = Simulation.from_source(COUNTER)
        sim.run()
        if how == "close":
            sim.close()
        del sim  # no gc.collect(): reference counting alone must free it
    growth = rss_mb() - before
    assert growth < RSS_GROWTH_LIMIT_MB, f"RSS grew {growth:.0f} MB over 50 simulations"
