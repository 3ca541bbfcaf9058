"""Benchmark: cold compile throughput of PDL and GDL (no compile cache).

Compiles the generated PDL program and GDL application of `compile_cache.py` (about
5,000 lines each; `--scale K` makes them K times longer) without the cache, REPEAT times
after a warm-up, and prints the lines per CPU second (`time.process_time`, the median),
then `RESULT name=value` lines. Every compile must give what the first one gave (the
generated Python). Compare two trees A/B in one run, alternating (/work/notes/ab2.sh
style): PYTHONPATH=OLD/src python bench/pdl_compile.py, then the same with NEW.
Run: python bench/pdl_compile.py [--scale K]
"""

from __future__ import annotations

import argparse
import statistics
import time

from compile_cache import generated_gdl, generated_pdl

from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.lower import emit_python
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source.diagnostics import DiagnosticSink

REPEAT = 7  # odd: the median is one of the runs


def pdl(src: str):
    """A cold compile of `src`, and its generated Python (read after the timing)."""
    sink = DiagnosticSink()
    prog = compile_pdl("gen.pdl", sink=sink, text=src)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog, prog.python_source


def gdl(src: str):
    """A cold compile of `src`, and its generated Python (read after the timing)."""
    sink = DiagnosticSink()
    app = compile_app(["gen.gdl"], sink=sink, texts={"gen.gdl": src})
    assert app is not None, [d.headline() for d in sink.items]
    return app, lambda: emit_python(app)


def lines_per_s(compile_fn, src: str) -> float:
    """Lines of `src` per CPU second of a cold compile, the median of REPEAT runs."""
    first = compile_fn(src)[1]()  # warm-up (imports, the compiler's own tables)
    times = []
    for _ in range(REPEAT):
        t0 = time.process_time()
        _, code = compile_fn(src)
        times.append(time.process_time() - t0)
        assert code() == first, "a compile gave other code"
    return src.count("\n") / statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=int, default=1, help="programs K times longer")
    args = ap.parse_args()
    pdl_src = generated_pdl(500 * args.scale)
    gdl_src = generated_gdl(400 * args.scale)
    for name, fn, src in (("pdl", pdl, pdl_src), ("gdl", gdl, gdl_src)):
        lps = lines_per_s(fn, src)
        print(f"{name.upper()} ({src.count(chr(10))} lines): cold compile {lps:,.0f} lines/s")
        print(f"RESULT {name}_cold_lines_per_s={lps:.0f}")


if __name__ == "__main__":
    main()
