"""Local arrays count against the task's 64 KB stack, however they are stored: deep
recursion with big local arrays stops with a stack overflow and memory stays bounded."""

import resource
import time

from motionvm.api import Simulation


def test_recursion_with_a_big_local_array_overflows_the_stack_quickly():
    rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    with Simulation.from_source("""
double Deep(int n) {
    double big[200000];
    big[n % 200000] = n;
    return Deep(n + 1) + big[0];
}
void main() { Print("%f", Deep(0)); }
""") as sim:
        sim.run(until=1.0)
        faults = list(sim.faults)
    assert len(faults) == 1 and "stack overflow" in faults[0], faults
    assert "64 KB" in faults[0] or "65536 bytes" in faults[0], faults
    assert time.perf_counter() - t0 < 10
    grown = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss_before) * 1024
    assert grown < 100_000_000, grown


def test_a_small_local_array_in_recursion_ten_deep_works():
    with Simulation.from_source("""
int Sum(int n) {
    int a[100];
    int i;
    for (i = 0; i < 100; i++) a[i] = n;
    if (n == 0) return 0;
    return a[99] + Sum(n - 1);
}
void main() { Print("%d", Sum(10)); }
""") as sim:
        sim.run(until=1.0)
        assert sim.faults == []
        assert sim.messages == ["55"]


def test_the_stack_limit_counts_local_arrays_bytes():
    # 20 frames of 4 KB of local array fit in 64 KB; 20 frames of 4 KB twice over do not
    prog = """
int F(int n) {{
    char a[{size}];
    a[0] = n;
    if (n == 0) return 0;
    return a[0] + F(n - 1);
}}
void main() {{ Print("%d", F(12)); }}
"""
    with Simulation.from_source(prog.format(size=4000)) as sim:
        sim.run(until=1.0)
        assert sim.faults == [] and sim.messages == ["78"]
    with Simulation.from_source(prog.format(size=8000)) as sim:
        sim.run(until=1.0)
        assert len(sim.faults) == 1 and "stack overflow" in sim.faults[0]
