"""Going back in time is exact: the state shown after going back to a position equals the
state of a fresh run stopped there (random programs, random stop points)."""

from __future__ import annotations

import dataclasses
import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.debug import BreakpointSpec, DebugEngine, Position
from motionvm.session import RunSpec, Source
from motionvm.sim.variables import AxisState

settings.register_profile("travel-ci", max_examples=4, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("travel-thorough", max_examples=150, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("travel-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

statement = st.one_of(
    st.builds(lambda a, p: f"MoveAbs({a}, {p});", st.integers(0, 1), st.integers(-300, 300)),
    st.builds(lambda t: f"Sleep({t});", st.integers(0, 40)),
    st.builds(lambda k: f"n = n * 3 + {k}; total = total + n;", st.integers(-5, 5)),
    st.builds(lambda a: f"Till(IsInPos({a}));", st.integers(0, 1)),
    st.just('Print("%d n=%d pos=%.6f", system_timeInMs, n, GetPosFb(0));'),
    st.builds(lambda i: f"cells[{i}] = cells[{i}] + n;", st.integers(0, 3)),
)


def _task(body: list[str]) -> str:
    lines = "\n        ".join(body)
    return f"""int n = 1;
int total = 0;
int cells[4];

void main()
{{
    int k;
    for (k = 0; k < 3; k++) {{
        {lines}
    }}
    Print("done %d %d", n, total);
}}
"""


def _snapshot(engine: DebugEngine) -> dict:
    ctl = engine.controller
    state = {"time": ctl.sim_time, "position": engine.position()}
    for name in ("n", "total", "cells[0]", "cells[1]", "cells[2]", "cells[3]"):
        state[name] = engine.evaluate(name)
    for i, axis in enumerate(ctl.axes[:2]):
        state[f"axis{i}"] = dataclasses.asdict(AxisState.of(axis, ctl.sim_time))
    frame = engine.timeline.paused_frame
    if frame is not None:
        state["line"] = frame.f_lineno
        state["locals"] = engine.locals_of(frame)
    return state


def _engine(path: str, skip: bool = True) -> DebugEngine:
    spec = RunSpec([Source(path)], skip=skip)
    return DebugEngine(spec, emit=lambda s: None, report=lambda s: None)


@PROFILE
@given(
    body=st.lists(statement, min_size=1, max_size=4),
    first=st.integers(0, 120),
    later=st.integers(1, 80),
    hits=st.integers(1, 4),
)
def test_going_back_shows_the_state_of_a_fresh_run_stopped_there(
    tmp_path_factory, body, first, later, hits
):
    path = str(tmp_path_factory.mktemp("travel") / "p.hmpl")
    with open(path, "w") as f:
        f.write(_task(body))
    # a cycle boundary: forward past it, then back
    engine = _engine(path)
    engine.start()
    engine.go_to(Position(first + later))
    engine.go_to(Position(first))
    back = _snapshot(engine)
    fresh = _engine(path)
    fresh.start()
    fresh.go_to(Position(first))
    assert back == _snapshot(fresh)
    fresh.close()
    # inside a statement: a breakpoint's hit, then on, then back to it
    engine.go_to(Position(0))
    engine.set_breakpoints(path, [BreakpointSpec(9, hit_condition=str(hits))])
    # bounded: a program may wait forever (Till on an axis that never gets there)
    stop = engine.resume_to(Position(first + later + 400))
    if stop.reason == "breakpoint":
        there = _snapshot(engine)
        engine.set_breakpoints(path, [])
        engine.step_cycle(later)
        engine.go_to(stop.position)
        assert _snapshot(engine) == there
        engine.step_back()
        before = _snapshot(engine)
        assert before["position"] < stop.position
        other = _engine(path, skip=False)  # a run stepped every cycle: the same place
        other.start()
        other.go_to(before["position"])
        assert _snapshot(other) == before
        other.close()
    engine.close()


MOVER = """\
void main()
{
    int k;
    Enable(AXIS); Till(IsEnabled(AXIS));
    for (k = 0; k < 3; k++) {
        MoveAbs(AXIS, 20.0 + AXIS);
        Till(IsInPos(AXIS));
        MoveAbs(AXIS, -20.0);
        Till(IsInPos(AXIS));
    }
}
"""


def test_a_place_inside_a_cycle_after_a_jump_is_that_of_a_stepped_run(tmp_path):
    """Tasks polling `Till` are resumed in the cycle before a place inside a cycle, so
    the statements counted there are those of a run stepped from the start (after a
    jump, the first cycle could otherwise count one poll fewer)."""
    paths = []
    for axis in range(3):
        p = tmp_path / f"m{axis}.hmpl"
        p.write_text(MOVER.replace("AXIS", str(axis)))
        paths.append(str(p))

    def place(skip: bool, target: Position):
        spec = RunSpec([Source(p) for p in paths], skip=skip)
        engine = DebugEngine(spec, emit=lambda s: None, report=lambda s: None)
        engine.start()
        stop = engine.go_to(target)
        frame = engine.timeline.paused_frame
        where = (stop.position, stop.thread, frame.f_code.co_filename, frame.f_lineno)
        engine.close()
        return where

    for cycle in (5, 150, 333, 700):
        for count in (1, 2, 3):
            assert place(True, Position(cycle, count)) == place(False, Position(cycle, count))
