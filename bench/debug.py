"""Benchmark: what the debugger costs, and how fast it goes back in time.

1. `debug_no_breakpoint_ratio`: CPU time of a run under the debug engine with no
   breakpoint (time skipping on) over the same run as `motionvm run` makes it
   (`Session.run`). Target: <= 2.
2. `debug_breakpoint_every_cycle_ratio`: the same with a breakpoint on a line that runs
   every cycle, whose condition never holds (so the run goes to its end). Target: <= 5.
3. Time travel in a 60 s run of 8 moving axes and 8 tasks (each task moves its axis
   back and forth, waiting in `Till(IsInPos(a))`): CPU seconds of `go_to_time(30)` from
   the end (`travel_goto_s`), of `step_back` from a breakpoint hit late in the run
   (`travel_step_back_s`) and of `reverse_continue` to the hit before it
   (`travel_reverse_continue_s`). Target: each < 1 s. The history kept is the list of
   inputs the user gave (`travel_history_inputs`): none here.

Timing: `time.process_time`, the median of the repeats, cases interleaved; each repeat
of a case must end in the same state (the printed lines, the final time).
Run: python bench/debug.py [--repeat R]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from motionvm.debug import BreakpointSpec, DebugEngine, Position
from motionvm.session import RunSpec, Session, Source

BUSY = """\
int count = 0;
double level = 0.0;

void main()
{
    int k;
    for (k = 0; k < 3000; k++) {
        count = count + 1;
        level = level * 0.5 + k;
        Sleep(1);
    }
    Print("count=%d", count);
}
"""
BUSY_LINE = 9  # count = count + 1

MOVER = """\
_AUTORUN_ void main()
{
    int k;
    Enable(AXIS); Till(IsEnabled(AXIS));
    for (k = 0; k < 60; k++) {
        MoveAbs(AXIS, 200.0 + AXIS);
        Till(IsInPos(AXIS));
        MoveAbs(AXIS, -200.0 - AXIS);
        Till(IsInPos(AXIS));
    }
    Print("axis %d done at %d", AXIS, system_timeInMs);
}
"""
MOVER_LINE = 6  # MoveAbs(AXIS, 200.0 + AXIS);


def _plain(path: str) -> tuple[list[str], float]:
    lines: list[str] = []
    session = Session(RunSpec([Source(path)]), emit=lines.append, report=lambda s: None)
    session.run()
    t = session.controller.sim_time
    session.close()
    return lines, t


def _debugged(path: str, breakpoint_line: int | None) -> tuple[list[str], float]:
    lines: list[str] = []
    engine = DebugEngine(RunSpec([Source(path)]), emit=lines.append, report=lambda s: None)
    if breakpoint_line is not None:
        engine.set_breakpoints(path, [BreakpointSpec(breakpoint_line, condition="count < 0")])
    stop = engine.start(stop_on_entry=False)
    assert stop.reason == "exited", stop
    t = engine.controller.sim_time
    engine.close()
    return lines, t


def _timed(fn, *args):
    t0 = time.process_time()
    result = fn(*args)
    return time.process_time() - t0, result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    opts = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="motionvm-bench-debug-"))
    busy = folder / "busy.hmpl"
    busy.write_text(BUSY)
    movers = []
    for a in range(8):
        p = folder / f"mover{a}.hmpl"
        p.write_text(MOVER.replace("AXIS", str(a)))
        movers.append(str(p))

    cases = {
        "plain": lambda: _plain(str(busy)),
        "debug": lambda: _debugged(str(busy), None),
        "debug_bp": lambda: _debugged(str(busy), BUSY_LINE),
    }
    times: dict[str, list[float]] = {k: [] for k in cases}
    results: dict[str, object] = {}
    for _ in range(opts.repeat):
        for name, fn in cases.items():
            dt, result = _timed(fn)
            times[name].append(dt)
            assert results.setdefault(name, result) == result, name
    assert results["plain"] == results["debug"] == results["debug_bp"]
    assert results["plain"][0] == ["count=3000"], results["plain"]
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"RESULT debug_no_breakpoint_ratio={med['debug'] / med['plain']:.2f}")
    print(f"RESULT debug_breakpoint_every_cycle_ratio={med['debug_bp'] / med['plain']:.2f}")

    spec = RunSpec([Source(p) for p in movers])
    travel: dict[str, list[float]] = {"goto": [], "back": [], "reverse": []}
    for _ in range(opts.repeat):
        lines: list[str] = []
        engine = DebugEngine(spec, emit=lines.append, report=lambda s: None)
        stop = engine.start(stop_on_entry=False)
        assert stop.reason == "exited" and stop.time > 55, stop
        assert len(lines) == 8, lines
        dt, stop = _timed(engine.go_to_time, 30.0)
        assert stop.position == Position(30000), stop
        travel["goto"].append(dt)
        engine.set_breakpoints(movers[3], [BreakpointSpec(MOVER_LINE, hit_condition=">= 10")])
        hit = engine.resume()
        assert hit.reason == "breakpoint", hit
        dt, back = _timed(engine.step_back)
        assert back.position < hit.position
        travel["back"].append(dt)
        engine.go_to(hit.position)
        dt, earlier = _timed(engine.reverse_continue)
        assert earlier.reason == "breakpoint" and earlier.position < hit.position, earlier
        travel["reverse"].append(dt)
        history = len(engine.history.inputs)
        engine.close()
    print(f"RESULT travel_goto_s={statistics.median(travel['goto']):.3f}")
    print(f"RESULT travel_step_back_s={statistics.median(travel['back']):.3f}")
    print(f"RESULT travel_reverse_continue_s={statistics.median(travel['reverse']):.3f}")
    print(f"RESULT travel_history_inputs={history}")


if __name__ == "__main__":
    main()
