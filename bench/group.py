"""Benchmark: axis group paths with velocity look-ahead (manual 8.1.4).

Two cases on a group of two default axes (1 ms cycle, default group profile:
100 mm/s, 500 mm/s^2, Ts 50 ms, BM_LOOKAHEAD):
- `polyline`: 10,000 short segments (0.2 .. 1 mm) turning by a seeded mix of small
  (< 5 deg), medium (< 30 deg) and large (90 .. 150 deg) angles;
- `arc`: a circle of radius 50 mm approximated by 2,000 chords.
The segments are queued through the motion commands (LineAbs2D) as the queue (512)
frees room, in batches of `BATCH`, as a task topping it up would (timing each single
call would cost more than the call).

Prints per case the planning time per segment (the CPU time of the LineAbs2D calls:
geometry, caps, junction, look-ahead pass) and the real-time factor of the whole run
(simulated seconds / CPU seconds of queueing and stepping); then
`RESULT group_plan_us_per_segment=` (the larger of the two cases) and
`RESULT group_realtime_factor=` (the smaller). Timing: `time.process_time`, the median
of 5 runs after one untimed warm-up run.

A third case, `program`, runs an HMPL program through `Simulation` (time skipping on):
one task draws a 2-D group on look-ahead lines and arcs, another a 3-D group on
buffered lines, each waiting on IsGrpInPos between moves; it prints
`RESULT group_program_realtime_factor=` (simulated seconds / CPU seconds of
`Simulation.run()`), its output asserted equal to a `--no-skip` run. `--old SRC`
(a `src` directory of another checkout, e.g. a worktree of an older commit) measures
the program there too, in a subprocess, interleaved with this one, and prints
`RESULT group_program_realtime_factor_old=`.
Run: python bench/group.py [--repeat N] [--old SRC]
"""

from __future__ import annotations

import argparse
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from motionvm.motion.axis_config import create
from motionvm.motion.commands import MotionCommands
from motionvm.motion.group_plan import BM_LOOKAHEAD
from motionvm.motion.kernel import MotionKernel

DT = 0.001
BATCH = 64


def polyline(n: int = 10_000, seed: int = 7) -> list[tuple[float, float]]:
    rnd = random.Random(seed)
    x = y = heading = 0.0
    pts = []
    for _ in range(n):
        r = rnd.random()
        if r < 0.7:
            turn = rnd.uniform(-5.0, 5.0)
        elif r < 0.9:
            turn = rnd.uniform(-30.0, 30.0)
        else:
            turn = rnd.choice((-1.0, 1.0)) * rnd.uniform(90.0, 150.0)
        heading += math.radians(turn)
        step = rnd.uniform(0.2, 1.0)
        x += step * math.cos(heading)
        y += step * math.sin(heading)
        pts.append((round(x, 6), round(y, 6)))
    return pts


def arc(n: int = 2_000, r: float = 50.0) -> list[tuple[float, float]]:
    return [(r * math.sin(2 * math.pi * k / n), r - r * math.cos(2 * math.pi * k / n))
            for k in range(1, n + 1)]  # fmt: skip


def machine() -> MotionCommands:
    c = MotionCommands(MotionKernel([create({}) for _ in range(2)], DT))
    c.Enable(0)
    c.Enable(1)
    while not (c.IsEnabled(0) and c.IsEnabled(1)):
        c.motion.step()
    assert c.SetupGroup(0, 0, 1) == 0
    assert c.SetGrpBufferMode(0, BM_LOOKAHEAD) == 0
    return c


def run(points: list[tuple[float, float]]) -> tuple[float, float, int, tuple]:
    """(planning CPU s, whole CPU s, cycles, final position) of one run."""
    c = machine()
    g = c.motion.groups[0]
    step = c.motion.step
    plan_cpu = 0.0
    i, n = 0, len(points)
    cycles = 0
    t_run = time.process_time()
    while i < n or g.moving:
        if i < n and len(g.planner.queue) <= g.queue_size - BATCH:
            t_0 = time.process_time()
            room = g.queue_size - len(g.planner.queue)
            for x, y in points[i : i + room]:
                if c.LineAbs2D(0, x, y) != 0:
                    raise SystemExit(
                        f"benchmark broken: LineAbs2D refused: {c.GetGrpLastErr(0):#x}"
                    )
            i = min(n, i + room)
            plan_cpu += time.process_time() - t_0
        step()
        cycles += 1
    whole = time.process_time() - t_run
    return plan_cpu, whole, cycles, tuple(a.ref_pos for a in g.axes)


def measure(name: str, points, repeat: int) -> tuple[float, float]:
    plans, wholes, ends = [], [], set()
    cycles = 0
    for k in range(repeat + 1):
        plan, whole, cycles, end = run(points)
        ends.add(end)
        if k:
            plans.append(plan)
            wholes.append(whole)
    if len(ends) != 1 or list(ends)[0] != points[-1]:
        raise SystemExit(f"benchmark broken: {name} ends at {ends}, not {points[-1]}")
    us = statistics.median(plans) / len(points) * 1e6
    rtf = cycles * DT / statistics.median(wholes)
    print(f"{name:9} {len(points):6} segments  {cycles * DT:8.2f} s simulated  "
          f"{us:7.1f} us/segment planning  {rtf:7.1f}x real time")  # fmt: skip
    return us, rtf


PLANE = """void main() {
    int i;
    StartTask(1);
    Enable(0); Enable(1);
    Till(IsEnabled(0) && IsEnabled(1));
    SetupGroup(0, 0, 1);
    SetGrpBufferMode(0, BM_LOOKAHEAD);
    for (i = 0; i < 10; i++) {
        LineAbs2D(0, 100, 0);
        ArcAngle2D(0, 100, 50, 180);
        LineAbs2D(0, 0, 100);
        ArcAngle2D(0, 0, 50, 180);
        Till(IsGrpInPos(0));
    }
    Print("g0 at %.9f %.9f", GetPosFb(0), GetPosFb(1));
}
"""
SPACE = """void main() {
    int i;
    Enable(2); Enable(3); Enable(4);
    Till(IsEnabled(2) && IsEnabled(3) && IsEnabled(4));
    SetupGroup(1, 2, 3, 4);
    for (i = 0; i < 10; i++) {
        LineAbs3D(1, 80, 40, 20);
        Till(IsGrpInPos(1));
        LineAbs3D(1, 80, 120, 0);
        Till(IsGrpInPos(1));
        LineAbs3D(1, 0, 0, 50);
        Till(IsGrpInPos(1));
    }
    Print("g1 at %.9f %.9f %.9f", GetPosFb(2), GetPosFb(3), GetPosFb(4));
}
"""


def program_once(skip: bool = True) -> tuple[float, float, list[str]]:
    """(simulated s, CPU s of `Simulation.run()`, output) of the program case."""
    from motionvm.api import Simulation

    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for name, text in (("plane.hmpl", PLANE), ("space.hmpl", SPACE)):
            p = Path(tmp) / name
            p.write_text(text, encoding="utf-8")
            paths.append(p)
        sim = Simulation.from_files(paths, skip=skip, stamp=True)
        t_0 = time.process_time()
        sim.run(timeout=600)
        cpu = time.process_time() - t_0
        return sim.time, cpu, list(sim.messages)


def _old_once(src: str) -> tuple[float, float]:
    """(simulated s, CPU s) of the program case with the motionvm of `src` (pure Python
    there, as here in a checkout without a compiled build)."""
    env = dict(os.environ, PYTHONPATH=src)
    here = str(Path(__file__).parent)
    code = (f"import sys; sys.path.insert(0, {here!r}); import group as b; "
            "t, c, _ = b.program_once(); print(t, c)")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                         capture_output=True, text=True).stdout.split()  # fmt: skip
    return float(out[0]), float(out[1])


def measure_program(repeat: int, old: str | None) -> None:
    sim_time, _, stepped = program_once(skip=False)
    new, olds = [], []
    for k in range(repeat + 1):
        t, cpu, out = program_once()
        if out != stepped or t != sim_time:
            raise SystemExit("benchmark broken: the program skipping differs from stepping")
        if old is not None:
            t_old, cpu_old = _old_once(old)
            if t_old != sim_time:
                raise SystemExit(f"benchmark broken: old run ends at {t_old}, not {sim_time}")
        if k:
            new.append(cpu)
            if old is not None:
                olds.append(cpu_old)
    rtf = sim_time / statistics.median(new)
    print(f"program   {sim_time:8.2f} s simulated  {rtf:9.1f}x real time")
    print(f"RESULT group_program_realtime_factor={rtf:.1f}")
    if olds:
        rtf_old = sim_time / statistics.median(olds)
        print(f"program (old) {rtf_old:9.1f}x real time")
        print(f"RESULT group_program_realtime_factor_old={rtf_old:.1f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--old", help="src directory of another checkout to compare the program with")
    ap.add_argument("--program-only", action="store_true", help="run the program case only")
    args = ap.parse_args()
    if not args.program_only:
        results = [measure("polyline", polyline(), args.repeat),
                   measure("arc", arc(), args.repeat)]  # fmt: skip
        print(f"RESULT group_plan_us_per_segment={max(r[0] for r in results):.1f}")
        print(f"RESULT group_realtime_factor={min(r[1] for r in results):.1f}")
    measure_program(args.repeat, args.old)


if __name__ == "__main__":
    main()
