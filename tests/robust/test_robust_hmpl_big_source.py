"""A 1 MB HMPL source is checked in bounded time and memory (in a child process, which
reports its own CPU time and peak RSS). The limits are generous for a loaded CI
machine; on an idle one the check takes about 2.5 s and 150 MB."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

FUNCTION = """int f{k}(int a, int b) {{
    int s = 0;
    for (int i = 0; i < a; i++) {{
        if (i % 3 == 0) s += i * b;
        else s -= b;
    }}
    double d = s * 0.5 + {k};
    char buf[32];
    StringPrint(buf, "%d", s);
    switch (a) {{
    case 1: s++; break;
    case 2: s--; break;
    default: s = s + {k};
    }}
    return s + (int)d;
}}
"""


def test_a_one_megabyte_source_checks_in_bounded_time_and_memory(tmp_path: Path):
    parts, size, k = [], 0, 0
    while size < 1_000_000:
        parts.append(FUNCTION.format(k=k))
        size += len(parts[-1])
        k += 1
    parts.append("void main() { system_ltest0 = f1(3, 4); }\n")
    src = tmp_path / "big.hmpl"
    src.write_text("".join(parts), encoding="utf-8")
    # the child reports its own CPU time and peak RSS: VmHWM of its own address space
    # (ru_maxrss would include this test process's size, inherited at the fork)
    probe = (
        "import resource, sys\n"
        "from motionvm.cli import main\n"
        "code = main(['check', sys.argv[1]])\n"
        "u = resource.getrusage(resource.RUSAGE_SELF)\n"
        "hwm = u.ru_maxrss\n"
        "try:\n"
        "    for line in open('/proc/self/status'):\n"
        "        if line.startswith('VmHWM:'):\n"
        "            hwm = int(line.split()[1])\n"
        "except OSError:\n"
        "    pass\n"
        "print(code, u.ru_utime + u.ru_stime, hwm)\n"
    )
    t0 = time.perf_counter()
    r = subprocess.run(
        [sys.executable, "-c", probe, str(src)],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        timeout=120,
    )
    wall = time.perf_counter() - t0
    assert r.stderr == ""
    code, cpu, rss_kb = r.stdout.split()
    assert code == "0"
    assert float(cpu) < 20, cpu
    assert wall < 60, wall
    assert int(rss_kb) < 500 * 1024, rss_kb
