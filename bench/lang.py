"""Benchmark: HMPL compute kernels against the same algorithms in plain Python, one process.

Prints a table of times and the ratio HMPL/Python per kernel, the median ratio, and
compile throughput for a generated 4,000-line program, then `RESULT name=value` lines.
Every figure is CPU time (`time.process_time`), the median of REPEAT runs after a warm-up;
the HMPL and Python runs of a kernel alternate, so load on a shared machine slows both
alike, and each run's result must equal the other side's.
Run: python bench/lang.py
"""

from __future__ import annotations

import statistics
import sys
import time

from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.hmpl.rtapi import HmplRuntime
from motionvm.sim.controller import Controller
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

REPEAT = 7  # odd: the median is one of the runs

KERNELS: dict[str, tuple[str, object]] = {}


def kernel(name: str, hmpl: str):
    def reg(fn):
        KERNELS[name] = (hmpl, fn)
        return fn

    return reg


@kernel(
    "fib",
    """
int fib(int n) { if (n < 2) return n; return fib(n - 1) + fib(n - 2); }
void main() { system_ltest0 = fib(22); }
""",
)
def py_fib():
    def fib(n):
        if n < 2:
            return n
        return fib(n - 1) + fib(n - 2)

    return fib(22)


@kernel(
    "sieve",
    """
char flags[60001];
void main() {
    int count = 0;
    for (int rep = 0; rep < 3; rep++) {
        count = 0;
        for (int i = 0; i <= 60000; i++) flags[i] = 1;
        for (int i = 2; i <= 60000; i++) {
            if (flags[i]) {
                count++;
                for (int k = i + i; k <= 60000; k += i) flags[k] = 0;
            }
        }
    }
    system_ltest0 = count;
}
""",
)
def py_sieve():
    count = 0
    flags = [0] * 60001
    for _rep in range(3):
        count = 0
        for i in range(60001):
            flags[i] = 1
        for i in range(2, 60001):
            if flags[i]:
                count += 1
                for k in range(i + i, 60001, i):
                    flags[k] = 0
    return count


@kernel(
    "bubble",
    """
int a[400];
void main() {
    int seed = 12345;
    for (int i = 0; i < 400; i++) { seed = seed * 1103515245 + 12345; a[i] = (seed >> 16) & 32767; }
    for (int i = 0; i < 400; i++) {
        for (int j = 0; j < 399 - i; j++) {
            if (a[j] > a[j + 1]) { int t = a[j]; a[j] = a[j + 1]; a[j + 1] = t; }
        }
    }
    system_ltest0 = a[0];
}
""",
)
def py_bubble():
    seed = 12345
    a = []
    for _i in range(400):
        seed = (seed * 1103515245 + 12345) & 0xFFFFFFFF
        if seed >= 2**31:
            seed -= 2**32
        a.append((seed >> 16) & 32767)
    for i in range(400):
        for j in range(399 - i):
            if a[j] > a[j + 1]:
                a[j], a[j + 1] = a[j + 1], a[j]
    return a[0]


@kernel(
    "strings",
    """
char buf[512];
char part[64];
void main() {
    int total = 0;
    for (int rep = 0; rep < 400; rep++) {
        buf[0] = 0;
        for (int i = 0; i < 20; i++) {
            StringPrint(part, "%d,", i * rep);
            StringCat(buf, part);
        }
        total += StringLen(buf);
    }
    system_ltest0 = total;
}
""",
)
def py_strings():
    # the same algorithm on byte arrays: sprintf into `part` with its NUL, strcat finds
    # the end of `buf` and copies `part` up to and with its NUL, strlen finds the NUL
    buf = bytearray(512)
    part = bytearray(64)
    total = 0
    for rep in range(400):
        buf[0] = 0
        for i in range(20):
            text = b"%d," % (i * rep)  # noqa: UP031 - the same format as the HMPL side
            part[: len(text) + 1] = text + b"\0"
            end = buf.index(0)
            n = part.index(0)
            buf[end : end + n + 1] = part[: n + 1]
        total += buf.index(0)
    return total


@kernel(
    "float",
    """
void main() {
    double x = 0.0, v = 1.0, k = 0.001, dt = 0.001, e = 0.0;
    for (int i = 0; i < 200000; i++) {
        double a = -k * x - 0.01 * v;
        v = v + a * dt;
        x = x + v * dt;
        e = e + 0.5 * v * v;
    }
    system_dtest0 = e;
}
""",
)
def py_float():
    x, v, k, dt, e = 0.0, 1.0, 0.001, 0.001, 0.0
    for _i in range(200000):
        a = -k * x - 0.01 * v
        v = v + a * dt
        x = x + v * dt
        e = e + 0.5 * v * v
    return e


@kernel(
    "pointers",
    """
int data[1000];
int sum_ptr(int *p, int n) {
    int s = 0;
    int *end = p + n;
    while (p < end) { s += *p; p++; }
    return s;
}
void main() {
    for (int i = 0; i < 1000; i++) data[i] = i;
    int total = 0;
    for (int rep = 0; rep < 100; rep++) total += sum_ptr(data, 1000);
    system_ltest0 = total;
}
""",
)
def py_pointers():
    data = list(range(1000))

    def sum_ptr(arr, n):
        s = 0
        p = 0
        while p < n:
            s += arr[p]
            p += 1
        return s

    total = 0
    for _rep in range(100):
        total += sum_ptr(data, 1000)
    return total


def run_hmpl(src: str) -> tuple[float, object]:
    """(CPU time [s] of running the program to its end, compile excluded; its result:
    system_ltest0, or system_dtest0 when the program sets that)."""
    sink = DiagnosticSink()
    prog, mem = compile_tasks([TaskFile(0, "<bench>.hmpl", src)], sink)
    if prog is None:
        for d in sink.items:
            print(render_diagnostic(d), file=sys.stderr)
        raise SystemExit(2)
    ctl = Controller(0.001)
    lines: list[str] = []
    rt = HmplRuntime(
        ctl,
        prog,
        mem,
        emit=lines.append,
        report=lambda s: print(s, file=sys.stderr),
        data_dir=".",
        task_slice=1_000_000,
    )
    ctl.clients.append(rt)
    t0 = time.process_time()
    rt.boot()
    ctl.run()
    t = time.process_time() - t0
    kind = "f64" if "system_dtest0" in src else "i32"
    var = "system_dtest0" if kind == "f64" else "system_ltest0"
    result = mem.load(prog.sysvars[var].addr, kind)
    rt.close()
    return t, result


def run_python(fn) -> tuple[float, object]:
    """(CPU time [s] of one call of `fn`, its result)."""
    t0 = time.process_time()
    result = fn()
    return time.process_time() - t0, result


def generated_program() -> str:
    """A 4,000-line program of 250 similar functions (loops, switch, strings, floats)."""
    funcs = []
    for i in range(250):
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
    return "".join(funcs) + "void main() { system_ltest0 = f1(3, 4); }\n"


def compile_throughput() -> tuple[float, int]:
    """Lines per CPU second compiling the generated program (the median of REPEAT runs)."""
    src = generated_program()
    nlines = src.count("\n")

    def comp():
        sink = DiagnosticSink()
        t0 = time.process_time()
        prog, _ = compile_tasks([TaskFile(0, "<gen>.hmpl", src)], sink)
        t = time.process_time() - t0
        assert prog is not None, [d.headline() for d in sink.items]
        return t

    comp()  # warm-up: imports and caches
    t = statistics.median(comp() for _ in range(REPEAT))
    return nlines / t, nlines


def main() -> None:
    ratios = {}
    print(f"{'kernel':<10} {'HMPL [ms]':>10} {'Python [ms]':>12} {'ratio':>7}")
    for name, (src, pyfn) in KERNELS.items():
        # interleave the two sides so a busy machine slows both alike; the median of each
        run_hmpl(src), run_python(pyfn)  # warm-up
        th_all, tp_all = [], []
        for _ in range(REPEAT):
            th, rh = run_hmpl(src)
            tp, rp = run_python(pyfn)
            if isinstance(rp, float):
                assert abs(rh - rp) <= 1e-9 * abs(rp), (name, rh, rp)
            else:
                assert rh == rp, (name, rh, rp)
            th_all.append(th)
            tp_all.append(tp)
        th, tp = statistics.median(th_all), statistics.median(tp_all)
        ratios[name] = th / tp
        print(f"{name:<10} {th * 1e3:>10.1f} {tp * 1e3:>12.1f} {th / tp:>7.2f}")
    med = statistics.median(ratios.values())
    worst = max(ratios.values())
    lps, nlines = compile_throughput()
    print(f"median ratio {med:.2f}, max {worst:.2f}; compile {lps:,.0f} lines/s ({nlines} lines)")
    for name, r in ratios.items():
        print(f"RESULT lang_ratio_{name}={r:.2f}")
    print(f"RESULT lang_median_ratio={med:.2f}")
    print(f"RESULT lang_max_ratio={worst:.2f}")
    print(f"RESULT compile_lines_per_s={lps:.1f}")


if __name__ == "__main__":
    main()
