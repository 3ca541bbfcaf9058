"""Benchmark: one moving axis-cycle, stepped, against a C++ peer in the same run.

The peer is pyplcopen's `AxisSim` (a C++ PLCopen axis kernel with Python bindings, from
PyPI), which runs in a venv of its own (`bench/.peer-venv`, git-ignored; made by
`python bench/peer.py --install`, which needs the network once). Both sides move one
axis at 100 mm/s (1,000 mm/s^2) at a 1 ms cycle, stepping every cycle:

- motionvm: `AXES` default axes, each commanded once (HMPL `MoveAbs` to a far target),
  then `Simulation.run()` with time skipping off and every axis computed every cycle
  (no deferred axes): the CPU time of the cycles over the axes moved is the cost of one
  moving axis-cycle (the controller's per-cycle work is shared by the axes, as in a
  machine); also the axes' own cycle alone (`step_axes`), and the run as it goes by
  default, where axes nobody reads are advanced in batches (`axis_cycle_deferred_ns`);
- peer: `AxisSim.move_absolute` to a far target, which cycles the axis inside C++ until
  its cycle limit: the distance after `CYCLES`, the CPU time per cycle of a move of
  `PEER_CYCLES`;
- motionvm's axis cycle alone: the same axes, moving, stepped `CYCLES` times by the
  motion kernel's loop over them (`step_axes`) without the controller's per-cycle work
  (tasks, clock, the run's checks): what the axes' own cycle costs.

Both must have moved the same distance (within 1 %: the two kernels shape the ramp
differently). Timing: `time.process_time`, the median of `REPEAT` interleaved runs of
each side (the peer's in its own process, timed inside it). Prints `RESULT` lines: the
costs in ns and their ratios to the peer. Run: python bench/peer.py [--install]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
import venv
from pathlib import Path

from motionvm import compiled_build
from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.motion.axis_cycle import step_axes
from motionvm.sim.machine import MachineConfig, default_axes

VENV = Path(__file__).resolve().parent / ".peer-venv"
PEER = "pyplcopen==0.21.0"
AXES = 8
SECONDS = 2.0
CYCLES = round(SECONDS * 1000)
PEER_CYCLES = 200 * CYCLES  # the peer's timed move (its cost per cycle is some ns)
REPEAT = 5
VEL, ACC = 100.0, 1000.0  # mm/s, mm/s^2
FAR = 900.0  # mm: within the default axes' software limits; no axis gets there

PROGRAM = f"""
void main() {{
    int a;
    for (a = 0; a < {AXES}; a++) {{ SetVel(a, {VEL}); SetAcc(a, {ACC}); SetDec(a, {ACC}); Enable(a); }}
    for (a = 0; a < {AXES}; a++) Till(IsEnabled(a));
    for (a = 0; a < {AXES}; a++) MoveAbs(a, {FAR});
}}
"""

PEER_RUN = f"""
import time
import pyplcopen

def move(cycles):  # per cycle: 0.1 mm/cycle, 0.001 mm/cycle^2 (100 mm/s, 1000 mm/s^2 at 1 kHz)
    axis = pyplcopen.AxisSim()
    axis.power_on()
    axis.cycle(10)
    start = axis.command_position()
    t0 = time.process_time()
    try:
        axis.move_absolute(1e9, {VEL / 1000}, {ACC / 1e6}, {ACC / 1e6}, 1e-4, cycles)
    except RuntimeError:
        pass  # its cycle limit: the move goes on
    return time.process_time() - t0, axis.command_position() - start

_, moved = move({CYCLES})
cpu, _ = move({PEER_CYCLES})
print(cpu / {PEER_CYCLES} * 1e9, moved)
"""


def peer_python() -> Path:
    return VENV / "bin" / "python"


def install() -> None:
    """The peer's venv with pyplcopen."""
    if not peer_python().exists():
        venv.create(VENV, with_pip=True)
    subprocess.run([peer_python(), "-m", "pip", "install", "--quiet", PEER], check=True)


def peer_once() -> tuple[float, float]:
    """(ns per cycle, distance moved [mm]) of the peer."""
    done = subprocess.run(
        [peer_python(), "-c", PEER_RUN], capture_output=True, text=True, check=True
    )
    ns, moved = done.stdout.split()
    return float(ns), float(moved)


def _moving() -> Simulation:
    """The simulation with every axis enabled and moving."""
    sim = Simulation(
        [TaskFile(0, "peer.hmpl", PROGRAM)],
        machine=MachineConfig(axes=default_axes(AXES)),
        skip=False,
    )
    sim.run(until=0.02)  # enabled, every move commanded
    if not all(a.moving for a in sim.controller.motion.axes) or sim.faults:
        raise SystemExit(f"benchmark broken: an axis does not move {sim.faults}")
    return sim


def ours_once(defer: bool = False) -> tuple[float, float]:
    """(ns per moving axis-cycle, distance axis 0 moved [mm]) of motionvm; `defer`: as
    a run goes by default, the axes nobody reads advanced in batches (motion/deferred.py),
    else every axis computed every cycle."""
    sim = _moving()
    sim.controller.defer_axes = defer
    axes = sim.controller.motion.axes
    start, cycles0 = axes[0].ref_pos, sim.controller.cycle
    t0 = time.process_time()
    sim.run(until=0.02 + SECONDS)
    cpu = time.process_time() - t0
    cycles = sim.controller.cycle - cycles0
    return cpu / (cycles * AXES) * 1e9, axes[0].ref_pos - start


def axes_once() -> float:
    """ns per moving axis-cycle of the axes' own cycle (`step_axes` alone)."""
    axes = _moving().controller.motion.axes
    t0 = time.process_time()
    for _ in range(CYCLES):
        step_axes(axes)
    cpu = time.process_time() - t0
    if not all(a.moving for a in axes):
        raise SystemExit("benchmark broken: an axis stopped")
    return cpu / (CYCLES * AXES) * 1e9


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--install", action="store_true", help=f"make {VENV} with {PEER} first")
    args = ap.parse_args()
    if args.install:
        install()
    if not peer_python().exists():
        sys.exit(f"no peer: run `python bench/peer.py --install` first (makes {VENV})")
    ours_once(), ours_once(True), axes_once(), peer_once()  # warm-up
    ours, deferred, alone, peer = [], [], [], []
    for _ in range(REPEAT):
        ours.append(ours_once())
        deferred.append(ours_once(True))
        alone.append(axes_once())
        peer.append(peer_once())
    moved_ours, moved_peer = ours[0][1], peer[0][1]
    if abs(moved_ours - moved_peer) > 0.01 * moved_peer or deferred[0][1] != moved_ours:
        raise SystemExit(f"the two moves differ: {moved_ours:.3f} mm vs {moved_peer:.3f} mm")
    o = statistics.median(ns for ns, _ in ours)
    d = statistics.median(ns for ns, _ in deferred)
    p = statistics.median(ns for ns, _ in peer)
    a = statistics.median(alone)
    print(f"motion cycle: {compiled_build.STATUS}")
    print(f"a moving axis-cycle: motionvm {o:.0f} ns, peer (C++) {p:.1f} ns: {o / p:.1f}x")
    print(f"the axes' own cycle (no controller work): {a:.0f} ns: {a / p:.1f}x")
    print(f"as a run goes by default (axes nobody reads deferred): {d:.0f} ns: {d / p:.1f}x")
    print(f"RESULT axis_cycle_ns={o:.1f}")
    print(f"RESULT peer_axis_cycle_ns={p:.2f}")
    print(f"RESULT axis_cycle_ratio_to_peer={o / p:.1f}")
    print(f"RESULT axis_step_alone_ns={a:.1f}")
    print(f"RESULT axis_step_alone_ratio_to_peer={a / p:.1f}")
    print(f"RESULT axis_cycle_deferred_ns={d:.1f}")
    print(f"RESULT axis_cycle_deferred_ratio_to_peer={d / p:.1f}")


if __name__ == "__main__":
    main()
