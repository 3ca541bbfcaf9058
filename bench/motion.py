"""Benchmark: simulated seconds per wall second with axes doing random point-to-point moves.

Two HMPL tasks share the axes (task 0 the first half, task 1 the rest). Each cycle a
task gives every axis of its half that is in position a new random target in
[-400, 400] mm (a seeded linear congruential generator in HMPL), so the axes move
almost all the time. Default machine axes (ideal drives, 1-cycle delay), 1 ms cycle.
Prints a table and `RESULT realtime_factor_<N>axes=<value>` for N = 1, 8, 32, 64.
Timing: after one untimed warm-up run of the case (the interpreter specializes the hot
code on its first runs), the median of 5 runs, in CPU seconds of this process
(`time.process_time`: other load on a busy machine does not count).
Run: python bench/motion.py [--seconds S]
"""

from __future__ import annotations

import argparse
import statistics
import time

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.sim.machine import MachineConfig, default_axes

TASK = """
int seed = SEED;
void main() {
    int i;
    START
    for (i = FIRST; i < LAST; i++) Enable(i);
    for (i = FIRST; i < LAST; i++) Till(IsEnabled(i));
    for (;;) {
        for (i = FIRST; i < LAST; i++) {
            if (IsInPos(i)) {
                seed = seed * 1103515245 + 12345;
                MoveAbs(i, ((seed >> 8) & 65535) / 65536.0 * 800.0 - 400.0);
            }
        }
        RunScheduler();
    }
}
"""


def _sources(n_axes: int) -> list[str]:
    half = (n_axes + 1) // 2
    spans = [(0, half), (half, n_axes)]
    return [TASK.replace("SEED", str(1000 + k)).replace("FIRST", str(a)).replace("LAST", str(b))
            .replace("START", "StartTask(1);" if k == 0 else "")
            for k, (a, b) in enumerate(spans)]  # fmt: skip


def simulation(n_axes: int) -> Simulation:
    """The benchmark's simulation with `n_axes` default axes (not yet run)."""
    tasks = [TaskFile(i, f"bench{i}.hmpl", s) for i, s in enumerate(_sources(n_axes))]
    return Simulation(tasks, machine=MachineConfig(axes=default_axes(n_axes)))


def measure(n_axes: int, seconds: float, repeat: int = 5) -> float:
    """Simulated s per CPU s over `seconds` of simulated time: the median of `repeat`
    runs after one untimed warm-up run. Every run must end in the same state."""
    times, states = [], set()
    for k in range(repeat + 1):
        sim = simulation(n_axes)
        sim.run(until=0.05)  # enable the axes
        t_0 = time.process_time()
        sim.run(until=0.05 + seconds)
        if k:
            times.append(time.process_time() - t_0)
        if not all(a.moving or a.in_pos for a in sim.controller.motion.axes) or sim.faults:
            raise SystemExit(f"benchmark broken: an axis is idle or a task faulted {sim.faults}")
        states.add(tuple(a.pos_fb for a in sim.controller.motion.axes))
    if len(states) != 1:
        raise SystemExit("benchmark broken: runs of one case ended in different states")
    return seconds / statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=4.0, help="simulated seconds per case")
    args = ap.parse_args()
    rows = []
    for n in (1, 8, 32, 64):
        factor = measure(n, args.seconds)
        rows.append((n, factor))
    print(f"{'axes':>5} {'x real time':>12} {'us per cycle':>13} {'us per axis-cycle':>18}")
    for n, factor in rows:
        us = 1e3 / factor  # 1 ms of simulated time per cycle
        print(f"{n:>5} {factor:>12.1f} {us:>13.1f} {us / n:>18.2f}")
    for n, factor in rows:
        print(f"RESULT realtime_factor_{n}axes={factor:.1f}")


if __name__ == "__main__":
    main()
