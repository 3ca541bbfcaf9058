"""Executed bytecodes and Python calls per axis-cycle of the stepping benchmark.

A noise-free companion of `bench/motion.py`: it builds the same simulation (N axes doing
continuous random point-to-point moves, 2 HMPL tasks, 1 ms cycle, time skipping off),
enables the axes, lets them move for a while, then counts with `sys.settrace` (opcode
events) what a number of cycles execute: in the motion kernel's step alone (the axes,
their generators, drives, motors and sensors) and in the whole controller cycle (with
the tasks and the scheduler). Prints the totals per axis-cycle and the functions called
most, with their calls and bytecodes per axis-cycle.
Run: python bench/motion_bytecodes.py [--axes N] [--cycles C]
"""

from __future__ import annotations

import argparse
import collections
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import motion  # noqa: E402  (bench/motion.py: the same simulation)
from opcode_count import OpcodeCount  # noqa: E402  (bench/opcode_count.py)


def count(
    n_axes: int, cycles: int, whole: bool
) -> tuple[int, collections.Counter, collections.Counter]:
    """(bytecodes, calls by function, bytecodes by function) of `cycles` cycles."""
    sim = motion.simulation(n_axes)
    sim.run(until=0.25)  # enabled and moving
    owner = sim.controller if whole else sim.controller.motion
    counter = OpcodeCount()

    step = owner.step

    def traced_step(*args, **kwargs):
        sys.settrace(counter.trace)
        try:
            return step(*args, **kwargs)
        finally:
            sys.settrace(None)

    owner.step = traced_step
    sim.run(until=0.25 + cycles * 0.001)
    return counter.total, counter.calls, counter.ops


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--axes", type=int, default=64)
    ap.add_argument("--cycles", type=int, default=300)
    args = ap.parse_args()
    per = args.axes * args.cycles
    for whole in (False, True):
        total, calls, ops = count(args.axes, args.cycles, whole)
        where = "controller cycle" if whole else "motion kernel step"
        print(f"{where}: {total / per:.1f} bytecodes, {sum(calls.values()) / per:.2f} calls"
              " per axis-cycle")  # fmt: skip
        if not whole:
            for key, n in calls.most_common(8):
                print(f"  {n / per:6.3f} calls {ops[key] / per:7.1f} bytecodes  {key[0]} {key[1]}")
        print(f"RESULT bytecodes_per_axis_cycle_{'cycle' if whole else 'motion'}="
              f"{total / per:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
