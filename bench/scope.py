"""Benchmark: the memory of a scope recording of one simulated hour.

A program moves axis 0 back and forth and counts its moves for one simulated hour
(`motionvm run --until 3600`), recording 8 channels every cycle (1 ms: 3.6 million
samples per channel) to a .csv file. The figure is the peak resident memory of that
`motionvm run` process (`ru_maxrss` of the child, Linux: kB), in MB. The file must hold
one row per cycle. Target: under 150 MB.
Run: python bench/scope.py [--seconds S]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PROGRAM = """
int moves;
void main() {
    Enable(0); Till(IsEnabled(0));
    for (;;) {
        MoveAbs(0, moves % 2 ? 0.0 : 50.0);
        Till(IsInPos(0));
        moves++;
        HIMC_GPO(1) = moves % 2;
        Sleep(100);
    }
}
"""
CHANNELS = (
    "system_timeInMs,moves,gpo1,axis0.ref_pos,axis0.ref_vel,axis0.pos_fb,axis0.vel_fb,axis1.pos_fb"
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3600.0, help="simulated seconds")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        prog = Path(tmp) / "hour.hmpl"
        prog.write_text(PROGRAM, encoding="utf-8")
        out = Path(tmp) / "hour.csv"
        cmd = [sys.executable, "-m", "motionvm", "run", "--until", str(args.seconds),
               "--scope", CHANNELS, "--scope-out", str(out), str(prog)]  # fmt: skip
        t_0 = time.process_time()
        proc = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ))
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise SystemExit(f"benchmark broken: exit {proc.returncode}: {proc.stderr}")
        with out.open("rb") as f:
            rows = sum(1 for _ in f) - 1
        expected = round(args.seconds / 0.001)  # cycles 0 .. until - 1
        if rows != expected:
            raise SystemExit(f"benchmark broken: {rows} rows, expected {expected}")
        size_mb = out.stat().st_size / 1e6
    peak_mb = usage.ru_maxrss / 1024.0
    cpu = usage.ru_utime + usage.ru_stime + (time.process_time() - t_0)
    print(f"{args.seconds:g} s simulated, {rows} samples x 8 channels, {size_mb:.1f} MB of .csv, "
          f"{cpu:.1f} s CPU, peak RSS {peak_mb:.1f} MB")  # fmt: skip
    print(f"RESULT scope_hour_peak_rss_mb={peak_mb:.1f}")


if __name__ == "__main__":
    main()
