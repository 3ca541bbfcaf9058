"""Benchmark: the controller's per-cycle framework cost and the task side of stepping.

Time skipping off (every cycle is computed), default machine axes:
1. `idle`: one HMPL task in `for (;;) RunScheduler();` on a machine without axes: what
   one controller cycle costs when nothing happens (the run loop, `Controller.step`, the
   clients' hooks, the task kernel's visit and resume of the task):
   `framework_us_per_cycle`.
2. `poll<N>` against `rest<N>`: the task side of bench/motion.py's stepping case. Two
   HMPL tasks share N enabled axes (half each); in `poll<N>` each loops over its axes
   calling `IsInPos(i)` every cycle, then `RunScheduler()`; in `rest<N>` it only calls
   `RunScheduler()`. No axis moves in either, so the difference is the tasks' loops and
   status queries: `task_us_per_axis_cycle` = (poll<N> - rest<N>) / N.

Timing: CPU seconds of this process (`time.process_time`), the median of 5 repeats
after one untimed warm-up, the repeats of all cases interleaved; every repeat of a case
must end in the same state. With `--against SRC` each repeat runs in a child process,
alternately with this tree's source and with SRC on PYTHONPATH (old against new in one
run); it prints both figures and their ratio. `--count` counts instead, with a
`sys.settrace` opcode tracer, the bytecodes and Python calls per cycle of each case
(noise-free), and the functions called most.
Run: python bench/framework.py [--cycles C] [--repeat R] [--against SRC] [--count]
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from opcode_count import OpcodeCount

IDLE = "void main() { for (;;) RunScheduler(); }"
TASK = """
int hits;
void main() {
    int i;
    START
    for (i = FIRST; i < LAST; i++) Enable(i);
    for (i = FIRST; i < LAST; i++) Till(IsEnabled(i));
    for (;;) {
        POLL
        RunScheduler();
    }
}
"""
LOOP = "for (i = FIRST; i < LAST; i++) { if (IsInPos(i)) hits++; }"
AXES = (1, 8)
WARM = 0.1
"""Simulated seconds before the timed part (the axes enabled and settled)."""


def simulation(case: str):
    """The case's simulation (not yet run): `idle` or `poll<N>`."""
    from motionvm.api import Simulation
    from motionvm.lang.hmpl.compiler import TaskFile
    from motionvm.sim.machine import MachineConfig, default_axes

    if case == "idle":
        tasks, n_axes = [TaskFile(0, "idle.hmpl", IDLE)], 0
    else:
        n_axes = int(case[4:])
        half = (n_axes + 1) // 2
        text = TASK.replace("POLL", LOOP if case.startswith("poll") else "")
        tasks = [
            TaskFile(k, f"task{k}.hmpl", text.replace("FIRST", str(a)).replace("LAST", str(b))
                     .replace("START", "StartTask(1);" if k == 0 else ""))
            for k, (a, b) in enumerate([(0, half), (half, n_axes)])
        ]  # fmt: skip
    return Simulation(tasks, machine=MachineConfig(axes=default_axes(n_axes)), skip=False)


def once(case: str, cycles: int) -> tuple[float, list]:
    """(CPU seconds of `cycles` stepped cycles, end state) of one run of `case`."""
    sim = simulation(case)
    sim.run(until=WARM)
    t_0 = time.process_time()
    sim.run(until=WARM + cycles * 0.001)
    cpu = time.process_time() - t_0
    axes = sim.controller.motion.axes
    if sim.faults or any(a.moving or not a.in_pos for a in axes if a.enabled):
        raise SystemExit(f"benchmark broken: a task faulted or an axis moves {sim.faults}")
    hits = sim.read("hits") if case != "idle" else 0
    end = [sim.controller.clock.cycle, hits, [a.pos_fb for a in axes]]
    sim.close()
    return cpu, end


def cases() -> list[str]:
    return ["idle", *(f"{kind}{n}" for n in AXES for kind in ("rest", "poll"))]


def count(case: str, cycles: int) -> tuple[int, collections.Counter, collections.Counter]:
    """(bytecodes, calls by function, bytecodes by function) of `cycles` run-loop cycles."""
    sim = simulation(case)
    sim.run(until=WARM)
    counter = OpcodeCount()

    controller = sim.controller
    end = controller.clock.cycle + cycles
    sys.settrace(counter.trace)
    try:
        controller.run(until=end * 0.001)
    finally:
        sys.settrace(None)
    sim.close()
    return counter.total, counter.calls, counter.ops


def child(case: str, cycles: int) -> None:
    cpu, end = once(case, cycles)
    print(json.dumps([cpu, end]))


def run_child(src: str, case: str, cycles: int) -> tuple[float, list]:
    env = dict(os.environ, PYTHONPATH=src)
    out = subprocess.run(
        [sys.executable, __file__, "--child", case, "--cycles", str(cycles)],
        env=env, capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    cpu, end = json.loads(out)
    return cpu, end


def report(name: str, us: dict[str, float]) -> None:
    print(f"{name}: idle cycle {us['idle']:.2f} us; " + ", ".join(
        f"{n} axes: {us[f'rest{n}']:.2f} us/cycle resting, {us[f'poll{n}']:.2f} polled, "
        f"{(us[f'poll{n}'] - us[f'rest{n}']) / n:.2f} us per axis-cycle polled"
        for n in AXES))  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=20000, help="timed cycles per run")
    ap.add_argument("--repeat", type=int, default=5, help="timed repeats per case (median)")
    ap.add_argument("--against", help="another source tree to time in the same run")
    ap.add_argument("--count", action="store_true", help="count bytecodes instead")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.child, args.cycles)
        return
    if args.count:
        n = min(args.cycles, 300)
        for case in cases():
            total, calls, ops = count(case, n)
            print(f"{case}: {total / n:.1f} bytecodes, {sum(calls.values()) / n:.2f} calls"
                  " per cycle")  # fmt: skip
            for key, c in calls.most_common(30):
                print(f"  {c / n:6.2f} calls {ops[key] / n:7.1f} bytecodes  {key[0]} {key[1]}")
            print(f"RESULT bytecodes_per_cycle_{case}={total / n:.1f}")
        return
    here = str(Path(__file__).resolve().parent.parent / "src")
    trees = {"new": here} if not args.against else {"new": here, "old": args.against}
    times: dict[tuple, list[float]] = {}
    ends: dict[str, set] = {}
    for k in range(args.repeat + 1):  # the first round warms up, untimed
        for case in cases():
            for name, src in trees.items():
                if args.against:
                    cpu, end = run_child(src, case, args.cycles)
                else:
                    cpu, end = once(case, args.cycles)
                ends.setdefault(case, set()).add(json.dumps(end))
                if k:
                    times.setdefault((name, case), []).append(cpu / args.cycles * 1e6)
    for case, found in ends.items():
        if len(found) != 1:
            raise SystemExit(f"benchmark broken: runs of case {case} ended in different states")
    us = {key: statistics.median(v) for key, v in times.items()}
    for name in trees:
        report(name, {case: us[name, case] for case in cases()})
    if args.against:
        for case in cases():
            print(f"RESULT {case}_old_over_new={us['old', case] / us['new', case]:.2f}")
    print(f"RESULT framework_us_per_cycle={us['new', 'idle']:.2f}")
    for n in AXES:
        per_axis = (us["new", f"poll{n}"] - us["new", f"rest{n}"]) / n
        print(f"RESULT task_us_per_axis_cycle_{n}axes={per_axis:.2f}")


if __name__ == "__main__":
    main()
