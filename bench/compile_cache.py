"""Benchmark: the compile cache on a generated 20,000-line HMPL program.

Prints the cold compile throughput (no cache) and the CPU time from nothing compiled to
the end of the first controller cycle, through the API, with an empty cache (the program
is compiled and stored) and with a warm one (it is read back), then `RESULT name=value`
lines. A warm run must give what a cold one gives: the program runs to its end in both
and its result variable and messages are compared. Then the same for a generated PDL
program and GDL application (about 5,000 lines each): the CPU time of compiling them
cold and of reading them back from the cache, the programs read back compared with the
compiled ones. Every figure is CPU time (`time.process_time`), the median of REPEAT runs
after a warm-up. The cache folder is a temporary one. Run: python bench/compile_cache.py
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from motionvm.api import Simulation
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.lower import emit_python
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source.cache import CompileCache
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


def generated_pdl(blocks: int = 500) -> str:
    """A PDL program of `blocks` 10-line blocks (variables, loops, conditions, prints)."""
    out = ["#long total;\n", "#task/0;\n"]
    for i in range(blocks):
        out.append(f"""#long a{i}, b{i};
a{i} = {i};
loop(3) do
  b{i} = b{i} + a{i};
end;
if (b{i} > {i * 5}) do
  total = total + 1;
end;
printl("block {i}: %ld", b{i});
total = total + b{i};
""")
    return "".join(out) + "halt;\n"


def generated_gdl(procedures: int = 400) -> str:
    """A GDL application of `procedures` 12-line procedures on integer variables, each
    run by a flag of its own."""
    out = ["MODULE gen;\n"]
    for i in range(procedures):
        out.append(f"  INTEGER$VARIABLE v{i} [ INITIAL$VALUE = {i} ];\n  DIGITAL$FLAG f{i} [ ];\n")
    for i in range(procedures):
        out.append(f"""  PROCEDURE p{i};
  DECLARE {{ STATUS OF f{i} }};
  BEGIN
    IF VALUE OF v{i} > {i + 10} THEN
      VALUE OF v{i} = 0;
    ELSE
      VALUE OF v{(i + 1) % procedures} = VALUE OF v{i} * 2 + 1;
    END$IF;
    WHILE VALUE OF v{i} > 100 DO
      VALUE OF v{i} = VALUE OF v{i} - 7;
    END$WHILE;
  END$PROCEDURE;
""")
    return "".join(out) + "END$MODULE;\n"


def pdl_gdl_cold_warm(tmp: str) -> dict[str, tuple[float, float, int]]:
    """(cold s, warm s, lines) of compiling a generated PDL program and GDL application
    without and with a (filled) cache; CPU time, medians."""
    cache = CompileCache(Path(tmp, "cache-pdl-gdl"), "bench")
    pdl_src, gdl_src = generated_pdl(), generated_gdl()

    def pdl(c):
        sink = DiagnosticSink()
        prog = compile_pdl("gen.pdl", sink=sink, text=pdl_src, cache=c)
        assert prog is not None, [d.headline() for d in sink.items]
        return prog

    def gdl(c):
        sink = DiagnosticSink()
        app = compile_app(["gen.gdl"], sink=sink, texts={"gen.gdl": gdl_src}, cache=c)
        assert app is not None, [d.headline() for d in sink.items]
        return app

    out = {}
    for name, fn, src in (("pdl", pdl, pdl_src), ("gdl", gdl, gdl_src)):
        cache.kind = name
        colds, warms = [], []
        for k in range(REPEAT + 1):
            t0 = time.process_time()
            cold = fn(None)
            t1 = time.process_time()
            if k == 0:
                fn(cache)  # fills the cache
            t2 = time.process_time()
            warm = fn(cache)
            t3 = time.process_time()
            if k:
                colds.append(t1 - t0)
                warms.append(t3 - t2)
        if name == "gdl":  # the same procedures, and functions for all of them
            assert emit_python(cold) == emit_python(warm)
            assert cold.functions.keys() == warm.functions.keys()
        else:  # the same code (read back) and the same tree (compiled again when asked)
            assert cold.code == warm.code
            assert cold.python_source() == warm.python_source()
        out[name] = (statistics.median(colds), statistics.median(warms), src.count("\n"))
    return out


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
        others = pdl_gdl_cold_warm(tmp)
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
    for name, (cold_s, warm_s, lines) in others.items():
        print(f"{name.upper()} ({lines} lines): cold compile {cold_s:.3f} s CPU, "
              f"from the cache {warm_s:.3f} s CPU")  # fmt: skip
        print(f"RESULT {name}_cold_compile_cpu_s={cold_s:.3f}")
        print(f"RESULT {name}_warm_cache_cpu_s={warm_s:.3f}")


if __name__ == "__main__":
    main()
