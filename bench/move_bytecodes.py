"""Executed bytecodes and Python calls of one `MoveAbs` from rest.

A noise-free companion of the wait program in `bench/motion.py`: one default axis is
enabled, then `MoveAbs` of 100 mm (alternately to 100 and back to 0) is counted with
`sys.settrace` (opcode events) from the motion command down to the planned T-curve,
the axis left to come into position between moves. Prints the totals per move and the
functions called, with their calls and bytecodes per move.
Run: python bench/move_bytecodes.py [--moves N]
"""

from __future__ import annotations

import argparse
import sys

from opcode_count import OpcodeCount

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.motion.commands import MotionCommands
from motionvm.sim.machine import MachineConfig, default_axes

TASK = "void main() { Enable(0); Till(IsEnabled(0)); for (;;) RunScheduler(); }"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--moves", type=int, default=10, help="moves to count")
    args = ap.parse_args()
    machine = MachineConfig(axes=default_axes(1))
    sim = Simulation([TaskFile(0, "move.hmpl", TASK)], machine=machine, skip=False)
    sim.run(until=0.05)  # enabled
    commands = MotionCommands(sim.controller.motion)
    axis = sim.controller.motion.axes[0]
    counter = OpcodeCount()
    calls, ops = counter.calls, counter.ops

    for k in range(args.moves):
        sys.settrace(counter.trace)
        status = commands.MoveAbs(0, 0.0 if k % 2 else 100.0)
        sys.settrace(None)
        sim.run(until=sim.time + 2.0)
        if status != 0 or not axis.in_pos:
            raise SystemExit(f"benchmark broken: status {status}, in position {axis.in_pos}")
    n = args.moves
    print(f"bytecodes per move: {sum(ops.values()) / n:.1f}")
    print(f"Python calls per move: {sum(calls.values()) / n:.1f}")
    for key, count in ops.most_common():
        print(
            f"  {key[0]:18s} {key[1]:24s} calls {calls[key] / n:4.1f}  bytecodes {count / n:6.1f}"
        )


if __name__ == "__main__":
    main()
