"""Accesses through pointers keep C's object bounds exactly, whatever path they take
(inline fast path, helper, misaligned): a walk reads and writes every element of its
object, the first access past the end is a runtime error, and so are accesses through
a pointer into a finished function's frame. Objects longer and shorter than the 255
bytes a shadow byte counts are both covered."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.cmemory import SHADOW_CAP, Memory, TaskStack, shadow_pattern
from motionvm.runtime.errors import RuntimeFault


def _run(src: str) -> tuple[list[str], list[str]]:
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        return list(sim.messages), list(sim.faults)


@pytest.mark.parametrize("ctype", ["char", "short", "int", "double"])
@pytest.mark.parametrize("n", [1, 63, 64, 65, 300])
@pytest.mark.parametrize("where", ["global", "local"])
def test_a_walk_covers_the_object_and_one_step_past_its_end_faults(ctype, n, where):
    decl = f"{ctype} a[{n}];"
    src = f"""
{decl if where == "global" else ""}
void main() {{
    {decl if where == "local" else ""}
    {ctype} *p = a;
    {ctype} *end = a + {n};
    int k = 0;
    while (p < end) {{ *p = ({ctype})(k % 100); p++; k++; }}
    int s = 0;
    for (p = a; p < end; p++) s += (int)*p;
    Print("%d", s);
    *p = 1;
    Print("not reached");
}}
"""
    messages, faults = _run(src)
    assert messages == [str(sum(k % 100 for k in range(n)))]
    assert len(faults) == 1 and "points outside its object" in faults[0], faults


@pytest.mark.parametrize("kind", ["load", "store"])
def test_reading_before_the_start_faults(kind):
    access = "int x = p[-1];" if kind == "load" else "p[-1] = 5;"
    messages, faults = _run(f"""
int a[10];
void main() {{ int *p = a; {access} Print("not reached"); }}
""")
    assert messages == [] and len(faults) == 1, faults
    assert "points outside its object" in faults[0], faults


def test_misaligned_int_pointers_read_the_bytes_and_fault_past_the_end():
    messages, faults = _run("""
char b[8] = {1, 0, 0, 0, 2, 0, 0, 0};
void main() {
    int *p = (int *)(b + 1);
    Print("%d", *p);
    *p = 258;
    Print("%d %d %d", b[1], b[2], b[3]);
    p = (int *)(b + 5);
    Print("%d", *p);
}
""")
    assert messages == ["33554432", "2 1 0"]
    assert len(faults) == 1 and "points outside its object" in faults[0], faults


def test_a_pointer_into_a_finished_frame_faults():
    messages, faults = _run("""
int *Leak() { int x[4]; x[0] = 7; return x; }
void main() { int *p = Leak(); Print("before"); *p = 1; Print("not reached"); }
""")
    assert messages == ["before"]
    assert len(faults) == 1 and "points outside its object" in faults[0], faults


def test_char_copy_loop_with_post_increments():
    messages, faults = _run("""
char src[300];
char dst[300];
void main() {
    int i;
    for (i = 0; i < 299; i++) src[i] = 'a' + i % 26;
    char *s = src; char *d = dst;
    while (*s) *d++ = *s++;
    *d = 0;
    Print("%d %c %c", StringLen(dst), dst[0], dst[298]);
    d = dst + 299;
    *d++ = 0;
    *d++ = 0;
}
""")
    assert messages == ["299 a m"]
    assert len(faults) == 1 and "points outside its object" in faults[0], faults


@pytest.mark.parametrize("size", [1, 2, 8, SHADOW_CAP - 1, SHADOW_CAP, SHADOW_CAP + 1, 1000])
def test_extent_and_checks_for_short_and_long_objects(size):
    mem = Memory(1 << 16)
    a = mem.alloc_static(size)
    assert len(shadow_pattern(size)) == size and 0 not in shadow_pattern(size)
    for off in range(size):
        assert mem.extent(a + off) == size - off
    assert mem.extent(a + size) == 0 and mem.extent(a - 1) == 0
    mem.check(a + size - 1, 1)
    with pytest.raises(RuntimeFault, match="points outside its object"):
        mem.check(a + size - 1, 2)


def test_stack_frames_shadow_their_objects_and_release_them():
    mem = Memory(1 << 16)
    base = mem.alloc_static(4096, "stack")
    mem.shadow[base : base + 4096] = bytes(4096)
    stack = TaskStack(mem, base, 4096)
    fp = stack.push(600, shadow_pattern(300) + bytes(8) + shadow_pattern(292))
    assert mem.extent(fp) == 300 and mem.extent(fp + 308) == 292
    assert mem.extent(fp + 300) == 0
    stack.pop(fp)
    assert mem.extent(fp) == 0 and mem.extent(fp + 308) == 0
