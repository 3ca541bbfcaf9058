"""A 1 MB HMPL source is checked in bounded time and memory (a child process: its peak
RSS is the largest of this process's children so far). The limits are generous for a loaded CI machine; on an idle one
the check takes about 2.5 s and 150 MB."""

from __future__ import annotations

import os
import resource
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
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(
        [sys.executable, "-m", "motionvm", "check", str(src)],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        timeout=120,
    )
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert (r.returncode, r.stderr) == (0, "")
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    assert cpu < 20, cpu
    assert wall < 60, wall
    assert after.ru_maxrss < 500 * 1024, after.ru_maxrss  # [KB]
