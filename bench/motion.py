"""Benchmark: simulated seconds per CPU second of the motion side, stepping and skipping.

1. Stepping (`realtime_factor_<N>axes`, N = 1, 8, 32, 64): two HMPL tasks share the
   axes (task 0 the first half, task 1 the rest). Each cycle a task gives every axis of
   its half that is in position a new random target in [-400, 400] mm (a seeded linear
   congruential generator in HMPL), so the axes move almost all the time. Default
   machine axes (ideal drives, 1-cycle delay), 1 ms cycle, time skipping off: every
   cycle is computed.
2. Skipping (`wait_program_realtime_factor`, `cycles_computed_ratio`): the typical
   program, 8 axes x 20 `MoveAbs` of 100 mm each followed by `Till(IsInPos(a))`, one
   task per axis: the CPU time of `Simulation.run()` after `Simulation.from_files()`
   (which compiles), against the simulated time `Simulation.time`; and the cycles the
   controller computed against the cycles simulated. The same program also runs with
   skipping off: both must print the same lines and leave every axis in the same state.
   `busy_wait_program_realtime_factor`: the same program with the busy loop
   `while (!IsInPos(a));` in place of the `Till` (skipping on; the same outcome).

Timing: CPU seconds of this process (`time.process_time`: other load on a busy machine
does not count), the median of 5 repeats after one untimed warm-up run; the repeats of
all cases are interleaved, so a slow spell of the machine hits every case alike. Every
repeat of a case must end in the same state.
Run: python bench/motion.py [--seconds S] [--repeat R] [--only wait|stepped]
(`--only wait` runs just the wait program, skipping and stepping; `--only stepped` just
the stepping cases; the default runs every case.)
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

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

WAIT_TASK = """
void main() {
    int k;
    START
    Enable(AXIS);
    Till(IsEnabled(AXIS));
    for (k = 0; k < 20; k++) {
        MoveAbs(AXIS, k % 2 ? 0.0 : 100.0);
        Till(IsInPos(AXIS));
    }
    Print("axis %d done at %d ms, at %.6f mm", AXIS, system_timeInMs, GetPosFb(AXIS));
}
"""
WAIT_AXES = 8
AXIS_COUNTS = (1, 8, 32, 64)


def _sources(n_axes: int) -> list[str]:
    half = (n_axes + 1) // 2
    spans = [(0, half), (half, n_axes)]
    return [TASK.replace("SEED", str(1000 + k)).replace("FIRST", str(a)).replace("LAST", str(b))
            .replace("START", "StartTask(1);" if k == 0 else "")
            for k, (a, b) in enumerate(spans)]  # fmt: skip


def simulation(n_axes: int) -> Simulation:
    """The stepping benchmark's simulation with `n_axes` default axes (not yet run)."""
    tasks = [TaskFile(i, f"bench{i}.hmpl", s) for i, s in enumerate(_sources(n_axes))]
    return Simulation(tasks, machine=MachineConfig(axes=default_axes(n_axes)), skip=False)


def stepped_once(n_axes: int, seconds: float) -> tuple[float, tuple]:
    """(CPU seconds, end state) of `seconds` of simulated time, stepping."""
    sim = simulation(n_axes)
    sim.run(until=0.05)  # enable the axes
    t_0 = time.process_time()
    sim.run(until=0.05 + seconds)
    cpu = time.process_time() - t_0
    axes = sim.controller.motion.axes
    if not all(a.moving or a.in_pos for a in axes) or sim.faults:
        raise SystemExit(f"benchmark broken: an axis is idle or a task faulted {sim.faults}")
    return cpu, tuple(a.pos_fb for a in axes)


def wait_program(folder: Path, busy: bool = False) -> list[Path]:
    """The files of the wait program (task k drives axis k; task 0 starts the others);
    `busy`: waiting in a busy loop instead of `Till`."""
    paths = []
    task = (
        WAIT_TASK.replace("Till(IsInPos(AXIS));", "while (!IsInPos(AXIS));") if busy else WAIT_TASK
    )
    for k in range(WAIT_AXES):
        start = "".join(f"StartTask({j}); " for j in range(1, WAIT_AXES)) if k == 0 else ""
        p = folder / f"{'busy' if busy else 'wait'}{k}.hmpl"
        p.write_text(task.replace("START", start).replace("AXIS", str(k)), encoding="utf-8")
        paths.append(p)
    return paths


def wait_once(paths: list[Path], skip: bool) -> tuple[float, float, int, tuple]:
    """(CPU seconds of run(), simulated seconds, cycles computed, outcome) of one run."""
    sim = Simulation.from_files(paths, skip=skip)
    t_0 = time.process_time()
    sim.run(timeout=60.0)
    cpu = time.process_time() - t_0
    axes = sim.controller.motion.axes
    state = tuple((a.pos_fb, a.ref_pos, a.in_pos, a.moving, a.move_time_ms) for a in axes)
    outcome = (tuple(sim.messages), sim.time, state, len(sim.faults))
    return cpu, sim.time, sim.controller.cycles_computed, outcome


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--seconds", type=float, default=2.0, help="simulated seconds per stepping case"
    )
    ap.add_argument("--repeat", type=int, default=5, help="timed repeats per case (median)")
    ap.add_argument("--only", choices=("wait", "stepped"), help="run only these cases")
    args = ap.parse_args()
    times: dict[object, list[float]] = {}
    ends: dict[object, set] = {}
    with tempfile.TemporaryDirectory() as tmp:
        paths = {"wait": wait_program(Path(tmp)), "wait-busy": wait_program(Path(tmp), busy=True)}
        paths["wait-stepped"] = paths["wait"]
        counts = () if args.only == "wait" else AXIS_COUNTS
        waits = () if args.only == "stepped" else ("wait", "wait-stepped", "wait-busy")
        cases = [*counts, *waits]
        for k in range(args.repeat + 1):  # the first round warms up, untimed
            for case in cases:
                if case in waits:
                    cpu, sim_s, computed, end = wait_once(paths[case], case != "wait-stepped")
                    if case == "wait":
                        computed_ratio = computed / round(sim_s / 0.001)
                    end = ("wait", end)
                else:
                    cpu, end = stepped_once(case, args.seconds)
                    sim_s = args.seconds
                ends.setdefault(case, set()).add(end)
                if k:
                    times.setdefault(case, []).append(sim_s / cpu)
    for case, found in ends.items():
        if len(found) != 1:
            raise SystemExit(f"benchmark broken: runs of case {case} ended in different states")
    if waits and not ends["wait"] == ends["wait-stepped"] == ends["wait-busy"]:
        raise SystemExit("benchmark broken: skipping, stepping, busy waits ended differently")
    factor = {case: statistics.median(v) for case, v in times.items()}
    if counts:
        print(f"{'axes':>5} {'x real time':>12} {'us per cycle':>13} {'us per axis-cycle':>18}")
    for n in counts:
        us = 1e3 / factor[n]  # 1 ms of simulated time per cycle
        print(f"{n:>5} {factor[n]:>12.1f} {us:>13.1f} {us / n:>18.2f}")
    if waits:
        print(f"wait program: {factor['wait']:.1f}x real time skipping, "
              f"{factor['wait-stepped']:.1f}x stepping; {computed_ratio:.4f} of its cycles computed")  # fmt: skip
    for n in counts:
        print(f"RESULT realtime_factor_{n}axes={factor[n]:.1f}")
    if waits:
        print(f"RESULT wait_program_realtime_factor={factor['wait']:.1f}")
        print(f"RESULT wait_program_stepped_realtime_factor={factor['wait-stepped']:.1f}")
        print(f"RESULT busy_wait_program_realtime_factor={factor['wait-busy']:.1f}")
        print(f"RESULT cycles_computed_ratio={computed_ratio:.4f}")


if __name__ == "__main__":
    main()
