"""Benchmark: the simulated PDL drive against real time, and PDL kernels against Python.

1. Real-time factor: a drive at 15 kHz with 4 busy tasks (three arithmetic loops and
   one task moving the axis back and forth), 1 statement per task per phase; the
   figure is simulated drive seconds per CPU second, for the drive alone and for the
   run a user makes (`motionvm run busy.pdl`: the drive on a machine axis, stepped by
   the controller, moving the axis's CiA 402 drive).
2. Kernels: each PDL program runs to its end on one task with an unlimited budget
   (so only the generated code is measured, not the scheduler) against the same
   algorithm written as plain Python: the same statements and loops (PDL allows one
   operator per statement, so `s = ((s ^ x) + k) & MASK` stands for `s = s @ x;
   s = s + k;`), locals for scalars, lists for arrays, the 32-bit masking the
   algorithm needs. The ratio is PDL time / Python time; the RESULT is the median.

Timing: CPU seconds of this process (`time.process_time`), the median of 5 repeats after
one untimed warm-up, the two sides of each comparison interleaved; every run must do
the same work, and each kernel must compute the same result in PDL as in Python.

Targets: real-time factor >= 5, kernel ratio <= 2.0.
Run: python bench/pdl.py
"""

# ruff: noqa: SIM113 — the Python kernels mirror the PDL statements, index counters included

from __future__ import annotations

import statistics
import time

from motionvm.lang.pdl.drive_rt import Drive, DriveConfig
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

REPEAT = 5
WORK = ("c0", "c1", "acc3", "moves")
"""Variables of the busy program that show the work a run did."""
SIM_SECONDS = 4.0

BUSY = """
#long c0, c1, c2, a1, b1, t2, q2, moves;
#long arr[16], i3, acc3;
#task/0;
l0: c0++; a1 = c0 * 3; a1 = a1 % 1000; b1 = b1 + a1; goto l0;
#task/1;
l1: c1 = c1 + 7; t2 = c1 & 255; q2 = q2 @ t2; c2 = shift(q2, -1); goto l1;
#task/2;
arr = {1, 2, 3, 4, 5, 6, 7};
l2: i3 = 0;
loop(16) do acc3 = acc3 + arr[i3+]; end;
goto l2;
#task/3;
X_vel_max = 200000;
X_acc = 2000000;
X_dcc = 2000000;
mv: X_trg = 100000;
till(~x_run);
X_trg = 0;
till(~x_run);
moves++;
goto mv;
"""

KERNELS: dict[str, tuple[str, object]] = {}


def kernel(name: str, pdl: str):
    def reg(fn):
        KERNELS[name] = (pdl, fn)
        return fn

    return reg


@kernel(
    "bubble",
    """
#long seed, i, j, n, t, u, v;
#long a[300];
#task/0;
seed = 12345;
i = 0;
loop(300) do
   seed = seed * 1103515245;
   seed = seed + 12345;
   t = shift(seed, -16);
   a[i+] = t & 32767;
end;
n = 299;
loop(299) do
   j = 0;
   loop(n) do
      u = a[j];
      j++;
      v = a[j];
      if (u > v) do
         a[j] = u;
         t = j - 1;
         a[t] = v;
      end;
   end;
   n--;
end;
ltest1 = a[0];
halt;
""",
)
def py_bubble() -> int:
    a = [0] * 300
    seed = 12345
    i = 0
    for _ in range(300):
        seed = (seed * 1103515245 + 12345) & 0xFFFFFFFF
        a[i] = (seed >> 16) & 32767
        i += 1
    n = 299
    for _ in range(299):
        j = 0
        for _ in range(n):
            u = a[j]
            j += 1
            v = a[j]
            if u > v:
                a[j] = u
                a[j - 1] = v
        n -= 1
    return a[0]


@kernel(
    "checksum",
    """
#long i, s, x, k;
#long data[2000];
#task/0;
i = 0;
loop(2000) do data[i] = i * 2654435761; i++; end;
k = 0;
loop(50) do
   i = 0;
   loop(2000) do
      x = data[i+];
      s = s @ x;
      s = s + k;
   end;
   k++;
end;
ltest1 = s;
halt;
""",
)
def py_checksum() -> int:
    data = [0] * 2000
    i = 0
    for _ in range(2000):
        data[i] = (i * 2654435761) & 0xFFFFFFFF
        i += 1
    s = 0
    k = 0
    for _ in range(50):
        i = 0
        for _ in range(2000):
            x = data[i]
            i += 1
            s = ((s ^ x) + k) & 0xFFFFFFFF
        k += 1
    return s


@kernel(
    "filter",
    """
#float y, x, e, k, d;
#long i;
#task/0;
k = 0.01;
loop(0) do
   x = i & 1023;
   d = x - y;
   e = d * k;
   y = y + e;
   i++;
end;
ff1 = y;
halt;
""",
)
def py_filter() -> float:
    y, k = 0.0, 0.01
    i = 0
    for _ in range(65536):
        x = i & 1023
        d = x - y
        e = d * k
        y = y + e
        i += 1
    return y


def compile_text(name: str, text: str):
    sink = DiagnosticSink()
    program = compile_pdl(f"bench/{name}.pdl", sink=sink, text=text)
    if program is None:
        raise SystemExit("\n".join(render_diagnostic(d) for d in sink.items))
    return program


def realtime_factors() -> tuple[float, float, Drive]:
    """Simulated seconds per CPU second of the drive alone and of the same program as a
    user runs it (`motionvm run busy.pdl`: on the drive of axis 0 of the default machine,
    stepped by the controller's cycle, moving the machine's axis): medians of REPEAT
    interleaved runs after one untimed warm-up pair. Every run must do the same work."""
    import os
    import tempfile

    from motionvm.api import Simulation

    program = compile_text("busy", BUSY)
    alone, machine, works = [], [], set()
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "busy.pdl")
        with open(path, "w", encoding="utf-8") as f:
            f.write(BUSY)
        for k in range(REPEAT + 1):
            drive = Drive(program, DriveConfig())
            t0 = time.process_time()
            drive.run(SIM_SECONDS)
            t_alone = time.process_time() - t0
            sim = Simulation.from_files([path])
            t0 = time.process_time()
            sim.run(until=SIM_SECONDS)
            t_machine = time.process_time() - t0
            machine_drive = sim.session.side("PDL").drives.drives[0][1]
            work = tuple(drive.read(v) for v in WORK)
            if tuple(machine_drive.read(v) for v in WORK) != work:
                raise SystemExit("benchmark broken: the machine run did other work than the drive")
            works.add(work)
            if k:
                alone.append(t_alone)
                machine.append(t_machine)
    if len(works) != 1:
        raise SystemExit("benchmark broken: runs of the drive did different work")
    return SIM_SECONDS / statistics.median(alone), SIM_SECONDS / statistics.median(machine), drive


def _same(pdl_value, py_value) -> bool:
    """The PDL kernel's result (a 32-bit integer, or a float) equals the Python one's."""
    if isinstance(py_value, float):
        return abs(pdl_value - py_value) <= 1e-3 * max(1.0, abs(py_value))
    return (int(pdl_value) - py_value) % 2**32 == 0


def kernel_times(name: str) -> tuple[float, float]:
    """Median CPU seconds of the PDL kernel and of its Python twin, REPEAT runs each,
    interleaved, after one untimed warm-up pair; both must compute the same result."""
    text, py = KERNELS[name]
    program = compile_text(name, text)
    result = "ff1" if "ff1 =" in text else "ltest1"
    t_pdl, t_py = [], []
    for k in range(REPEAT + 1):
        d = Drive(program, DriveConfig(budget=10**9))
        t0 = time.process_time()
        assert d.run(None)
        t_1 = time.process_time()
        expected = py()  # type: ignore[operator]
        t_2 = time.process_time()
        if not _same(d.read(result), expected):
            raise SystemExit(
                f"benchmark broken: {name}: PDL {d.read(result)!r}, Python {expected!r}"
            )
        if k:
            t_pdl.append(t_1 - t0)
            t_py.append(t_2 - t_1)
    return statistics.median(t_pdl), statistics.median(t_py)


def main() -> None:
    factor, machine, drive = realtime_factors()
    print(f"drive at 15 kHz, 4 busy tasks, {SIM_SECONDS:g} s simulated")
    print(f"  {'real-time factor':<24}{factor:8.1f} x")
    counts = ", ".join(f"{v}={drive.read(v)}" for v in WORK)
    print(f"  work done: {counts}")
    print(f"  {'on a machine axis':<24}{machine:8.1f} x  (motionvm run busy.pdl)")
    print()
    print(f"{'kernel':<12}{'PDL [ms]':>10}{'Python [ms]':>13}{'ratio':>8}")
    ratios = []
    for name in KERNELS:
        t_pdl, t_py = kernel_times(name)
        ratios.append(t_pdl / t_py)
        print(f"{name:<12}{t_pdl * 1e3:10.1f}{t_py * 1e3:13.1f}{t_pdl / t_py:8.2f}")
    ratio = statistics.median(ratios)
    print(f"{'median':<35}{ratio:8.2f}")
    print(f"RESULT pdl_realtime_factor={factor:.1f}")
    print(f"RESULT pdl_machine_realtime_factor={machine:.1f}")
    print(f"RESULT pdl_kernel_ratio={ratio:.2f}")


if __name__ == "__main__":
    main()
