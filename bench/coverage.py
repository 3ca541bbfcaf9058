"""Benchmark: what coverage of machine programs costs (`--cov-report`).

For each workload, the CPU time of the same run with coverage on over the time with it
off: `coverage_ratio_<name>` for the run (`Session.run`) and `coverage_total_ratio_<name>`
for compile and run together (the compile cache off in both, as a compile with coverage
never uses it). Target: every run ratio <= 1.5; `coverage_ratio_max` is the largest.
Workloads:
- `compute`: an HMPL loop of arithmetic and an `if`, 200,000 iterations, no wait: the
  worst case, nothing but the user's statements (each one probed);
- `sleepy`: an HMPL loop of 3,000 iterations with a Sleep(1) in each (a task that
  wakes every cycle, bench/debug.py's program);
- `pdl_loop`: a PDL drive task counting in a loop with an `if`;
- `one_machine`, `pick_and_place`: examples/04 (HMPL, PDL and GDL on one machine) and
  examples/05 (moves, a scenario).
The statement that each run ends in the same state as without coverage is checked
(the printed lines, the final time).

Timing: `time.process_time`, the median of the repeats, the cases interleaved (off, on,
off, on, ...).
Run: MOTIONVM_NO_CACHE=1 python bench/coverage.py [--repeat R]
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from motionvm.session import RunSpec, Session, Source

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

COMPUTE = """\
int total = 0;
void main()
{
    int k;
    for (k = 0; k < 200000; k++) {
        if (k % 3 == 0)
            total = total + 2;
        else
            total = total - 1;
    }
    Print("total=%d", total);
}
"""

SLEEPY = """\
int count = 0;
double level = 0.0;
void main()
{
    int k;
    for (k = 0; k < 3000; k++) {
        count = count + 1;
        level = level * 0.5 + k;
        Sleep(1);
    }
    Print("count=%d", count);
}
"""

PDL_LOOP = """\
#long n, m;
n = 0;
loop(20000) do
  n++;
  if (n > 10000) do
    m++;
  end;
end;
printl("n=%ld m=%ld", n, m);
"""


def _workloads(folder: Path) -> dict[str, dict]:
    def write(name: str, text: str) -> str:
        path = folder / name
        path.write_text(text)
        return str(path)

    ex = EXAMPLES
    return {
        "compute": {"sources": [write("compute.hmpl", COMPUTE)]},
        "sleepy": {"sources": [write("sleepy.hmpl", SLEEPY)]},
        "pdl_loop": {
            "sources": [write("loop.pdl", PDL_LOOP)],
            "options": {"starts": ("top",)},
        },
        "one_machine": {
            "sources": [str(ex / "04_one_machine.hmpl"), str(ex / "04_one_machine.cell.gdl")],
            "machine": str(ex / "04_one_machine.toml"),
            "scenario": str(ex / "04_one_machine.scenario.toml"),
        },
        "pick_and_place": {
            "sources": [str(ex / "05_pick_and_place.hmpl")],
            "machine": str(ex / "05_pick_and_place.toml"),
            "scenario": str(ex / "05_pick_and_place.scenario.toml"),
        },
    }


def _run(work: dict, coverage: bool) -> tuple[float, float, tuple]:
    """(run CPU [s], compile + run CPU [s], (printed lines, final time))."""
    lines: list[str] = []
    spec = RunSpec(
        [Source(p) for p in work["sources"]],
        machine=work.get("machine"),
        scenario=work.get("scenario"),
        options=work.get("options", {}),
        coverage=coverage,
    )
    cwd = os.getcwd()
    os.chdir(Path(work["sources"][0]).parent)  # machine files name their programs so
    try:
        t0 = time.process_time()
        session = Session(spec, emit=lines.append, report=lambda s: None)
        t1 = time.process_time()
        session.run(timeout=120)
        t2 = time.process_time()
    finally:
        os.chdir(cwd)
    end = session.controller.sim_time
    if coverage:
        assert session.coverage is not None and session.coverage.data()
    session.close()
    return t2 - t1, t2 - t0, (tuple(lines), end)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    opts = parser.parse_args()
    os.environ["MOTIONVM_NO_CACHE"] = "1"
    folder = Path(tempfile.mkdtemp(prefix="motionvm-bench-coverage-"))
    works = _workloads(folder)
    worst = 0.0
    for name, work in works.items():
        _run(work, False)  # warm-up: imports, first compile
        run = {False: [], True: []}
        total = {False: [], True: []}
        state = {}
        for _ in range(opts.repeat):
            for cov in (False, True):
                r, t, s = _run(work, cov)
                run[cov].append(r)
                total[cov].append(t)
                assert state.setdefault(cov, s) == s, name
        assert state[False] == state[True], name  # coverage changes nothing of the run
        ratio = statistics.median(run[True]) / statistics.median(run[False])
        total_ratio = statistics.median(total[True]) / statistics.median(total[False])
        worst = max(worst, ratio)
        print(f"{name}: run {statistics.median(run[False]) * 1000:.1f} ms without coverage")
        print(f"RESULT coverage_ratio_{name}={ratio:.2f}")
        print(f"RESULT coverage_total_ratio_{name}={total_ratio:.2f}")
    print(f"RESULT coverage_ratio_max={worst:.2f}")


if __name__ == "__main__":
    main()
