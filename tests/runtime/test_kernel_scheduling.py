"""Scheduler: fairness between busy tasks, determinism, Sleep timing, faults stop one task."""

from __future__ import annotations

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile


def _sim(*sources: str, **kw) -> Simulation:
    return Simulation([TaskFile(i, f"t{i}.hmpl", s) for i, s in enumerate(sources)], **kw)


BUSY = """
void main() {
    StartTask(1);
    int n = 0;
    for (;;) { n++; system_ltest0 = n; }
}
"""
BUSY1 = """
void main() {
    int n = 0;
    for (;;) { n++; system_ltest1 = n; }
}
"""


def test_busy_loops_never_freeze_the_controller_and_share_it():
    sim = _sim(BUSY, BUSY1)
    sim.run(until=0.05)
    a, b = sim.read("system_ltest0"), sim.read("system_ltest1")
    assert sim.time == 0.05
    assert a > 1000 and b > 1000
    # both get the same slice per cycle; task 1 starts one cycle later (StartTask)
    assert abs(a - b) <= 2 * (sim.runtime.task_slice + 64)


def test_two_runs_give_identical_results():
    def once():
        sim = _sim(BUSY, BUSY1)
        sim.run(until=0.02)
        return sim.read("system_ltest0"), sim.read("system_ltest1"), sim.messages

    assert once() == once()


def test_sleep_wakes_exactly_and_clock_jumps_ahead():
    sim = _sim("""
void main() {
    Sleep(250);
    Print("%d", system_timeInMs);
    Sleep(1);
    Print("%d", system_timeInMs);
}
""")
    sim.run()
    assert sim.messages == ["250", "251"]


def test_a_fault_stops_only_its_task():
    sim = _sim(
        """
void main() {
    StartTask(1);
    Sleep(5);
    int z = 0;
    Print("%d", 1 / z);
}
""",
        """
void main() {
    for (int i = 0; i < 10; i++) { Sleep(1); }
    Print("task 1 done at %d", system_timeInMs);
}
""",
    )
    sim.run()
    assert len(sim.faults) == 1
    assert (
        "t0.hmpl:6:5: runtime error in task 0 at t=0.005 s: integer division by zero"
        in sim.faults[0]
    )
    assert sim.messages == ["task 1 done at 11"]


def test_mutex_is_released_when_its_holder_stops():
    sim = _sim(
        """
void main() {
    MutexLock(3);
    StartTask(1);
    Sleep(3);
}
""",
        """
void main() {
    MutexLock(3);
    Print("task 1 got the mutex at %d", system_timeInMs);
}
""",
    )
    sim.run()
    assert sim.messages == ["task 1 got the mutex at 3"]


def test_events_reach_the_host_callback():
    seen = []
    sim = _sim("""
void main() {
    SendEvent(42);
    SendMsgEvent("variable: %d", 88);
}
""")
    sim.on_event(lambda kind, payload: seen.append((kind, payload)))
    sim.run()
    assert seen == [("event", 42), ("msg", "variable: 88")]


def test_realtime_pacing_never_runs_ahead_of_the_wall_clock():
    import time

    sim = _sim('void main() { Sleep(200); Print("%d", system_timeInMs); }')
    t0 = time.monotonic()
    sim.controller.run(realtime=True)
    assert time.monotonic() - t0 >= 0.19
    assert sim.messages == ["200"]
