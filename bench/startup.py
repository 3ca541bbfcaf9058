"""Benchmark: the CPU time of a whole `motionvm run` of the hello example.

Each repeat starts a new Python process running `python -m motionvm run
examples/01_hello.hmpl` and takes its CPU time (user + system, from the operating
system's accounting of the finished child, so other load on a busy machine does not
count). Two cases, their repeats interleaved:
1. `hello_run_cpu_s`: with Python's bytecode cache, as after any install (the cache is
   kept in a temporary folder through `PYTHONPYCACHEPREFIX`, filled by an untimed
   warm-up run, so the source tree is left alone);
2. `hello_run_cpu_s_no_pyc`: without a cache of motionvm's modules
   (`PYTHONDONTWRITEBYTECODE=1`, the package's source copied to a temporary folder):
   each of its modules is compiled from source at every start, as on a machine that
   forbids writing the cache (the standard library keeps its installed cache).
Prints the median of the repeats of each case; every run must print the same output.
Run: python bench/startup.py [--repeat R]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HELLO = ROOT / "examples" / "01_hello.hmpl"


def child_cpu(env: dict[str, str]) -> tuple[float, bytes]:
    """(CPU seconds, stdout) of one `motionvm run` of the hello example."""
    before = os.times()
    out = subprocess.run(
        [sys.executable, "-m", "motionvm", "run", str(HELLO)],
        env=env, capture_output=True, check=True,
    ).stdout  # fmt: skip
    after = os.times()
    cpu = (after.children_user - before.children_user) + (
        after.children_system - before.children_system
    )
    return cpu, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="timed runs per case (median)")
    args = ap.parse_args()
    base = dict(os.environ)
    base.pop("PYTHONDONTWRITEBYTECODE", None)
    with tempfile.TemporaryDirectory() as cached, tempfile.TemporaryDirectory() as bare:
        shutil.copytree(ROOT / "src" / "motionvm", Path(bare) / "motionvm",
                        ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
        path = base.get("PYTHONPATH", "")
        envs = {
            "hello_run_cpu_s": {
                **base, "PYTHONPATH": f"{ROOT / 'src'}{os.pathsep}{path}",
                "PYTHONPYCACHEPREFIX": cached,
            },
            "hello_run_cpu_s_no_pyc": {
                **base, "PYTHONPATH": f"{bare}{os.pathsep}{path}",
                "PYTHONDONTWRITEBYTECODE": "1",
            },
        }  # fmt: skip
        _, expected = child_cpu(envs["hello_run_cpu_s"])  # warm-up: fills the cache
        times: dict[str, list[float]] = {name: [] for name in envs}
        for _ in range(args.repeat):
            for name, env in envs.items():
                cpu, out = child_cpu(env)
                assert out == expected, f"{name}: the output differs"
                times[name].append(cpu)
        assert not list(Path(bare).rglob("__pycache__")), "the no-cache case wrote a cache"
    for name, values in times.items():
        print(f"{name}: median {statistics.median(values):.3f} s of "
              f"{', '.join(f'{v:.3f}' for v in sorted(values))}")  # fmt: skip
    for name, values in times.items():
        print(f"RESULT {name}={statistics.median(values):.3f}")


if __name__ == "__main__":
    main()
