"""Benchmark: the compile cache on a generated 20,000-line HMPL program.

Prints the cold compile throughput (no cache) and the CPU time from nothing compiled to
the end of the first controller cycle, through the API, with an empty cache (the program
is compiled and stored) and with a warm one (it is read back), then `RESULT name=value`
lines. A warm run must give what a cold one gives: the program runs to its end in both
and its result variable and messages are compared. Every figure is CPU time
(`time.process_time`), the median of REPEAT runs after a warm-up. The cache folder is a
temporary one. Run: python bench/compile_cache.py
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink

REPEAT = 5
FUNCTIONS = 1250  # 16 lines each: 20,000 lines


def generated_program() -> str:
    """FUNCTIONS similar functions (loops, switch, strings, floats) and a main that calls
    some of them and prints the sum."""
    funcs = []
    for i in range(FUNCTIONS):
        funcs.append(f"""int f{i}(int a, int b) {{
    int s = 0;
    for (int i = 0; i < a; i++) {{
        if (i % 3 == 0) s += i * b;
        else s -= b;
    }}
    double d = s * 0.5 + {i};
    char buf[32];
    StringPrint(buf, "%d", s);
    switch (a) {{
    case 1: s++; break;
    case 2: s--; break;
    default: s = s + {i};
    }}
    return s + (int)d;
}}
""")
    calls = " + ".join(f"f{i}({i % 7}, {i % 5})" for i in range(0, FUNCTIONS, 97))
    main = f'void main() {{ system_ltest0 = {calls}; Print("%d", system_ltest0); }}\n'
    return "".join(funcs) + main


def cold_lines_per_s(src: str) -> tuple[float, int]:
    """Lines per CPU second compiling `src` without the cache."""
    nlines = src.count("\n")

    def comp() -> float:
        sink = DiagnosticSink()
        t0 = time.process_time()
        prog, mem = compile_tasks([TaskFile(0, "<gen>.hmpl", src)], sink)
        t = time.process_time() - t0
        assert prog is not None, [d.headline() for d in sink.items]
        mem.release()
        return t

    comp()
    return nlines / statistics.median(comp() for _ in range(REPEAT)), nlines


def to_first_cycle(path: Path) -> tuple[float, Simulation]:
    """CPU time [s] of compiling (or reading back) `path` and running one cycle."""
    t0 = time.process_time()
    sim = Simulation.from_files([path])
    sim.step(1)
    return time.process_time() - t0, sim


def outcome(sim: Simulation) -> tuple[object, list[str]]:
    """The program's result variable and messages, run to its end."""
    sim.run(until=1.0)
    result = (sim.read("system_ltest0"), list(sim.messages))
    sim.close()
    return result


def main() -> None:
    src = generated_program()
    lps, nlines = cold_lines_per_s(src)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp, "big.hmpl")
        path.write_text(src)
        os.environ.pop("MOTIONVM_NO_CACHE", None)
        empties, warms, results = [], [], []
        for k in range(REPEAT + 1):
            os.environ["MOTIONVM_CACHE_DIR"] = str(Path(tmp, f"cache{k}"))
            t_empty, sim = to_first_cycle(path)
            results.append(outcome(sim))
            t_warm, sim = to_first_cycle(path)
            results.append(outcome(sim))
            if k:  # the first round warms up imports
                empties.append(t_empty)
                warms.append(t_warm)
    if any(r != results[0] for r in results):
        print("warm and cold runs differ", file=sys.stderr)
        raise SystemExit(1)
    empty, warm = statistics.median(empties), statistics.median(warms)
    print(f"cold compile {lps:,.0f} lines/s ({nlines} lines)")
    print(f"to the first cycle: empty cache {empty:.3f} s CPU, warm cache {warm:.3f} s CPU")
    print(f"result {results[0][0]}, {len(results)} runs equal")
    print(f"RESULT compile_cold_lines_per_s={lps:.1f}")
    print(f"RESULT first_cycle_empty_cache_cpu_s={empty:.3f}")
    print(f"RESULT first_cycle_warm_cache_cpu_s={warm:.3f}")


if __name__ == "__main__":
    main()
