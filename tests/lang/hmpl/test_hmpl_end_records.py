"""A loop its task never leaves, with no status wait in it, ends the task's records of
the status flags it reads (lower_records.py, `Kernel.end_records`); any way out of the
loop, or a status wait that may be reached in it, keeps them."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink

ENDS = [
    "for (;;) { if (IsInPos(0)) MoveAbs(0, 1.0); RunScheduler(); }",
    "while (1) { if (IsInPos(0)) MoveAbs(0, 1.0); Sleep(2); }",
    "for (;;) { for (int i = 0; i < 4; i++) { if (IsMoving(i)) break; } RunScheduler(); }",
    "for (;;) { Till(system_timeInMs >= g); g += 5; }",
    "for (;;) { switch (a) { case 1: a = 0; break; default: a = 1; } RunScheduler(); }",
    "Till(IsEnabled(0)); for (;;) { a = IsInPos(0); RunScheduler(); }",
]
KEEPS = [
    "for (;;) { Till(IsInPos(0)); MoveAbs(0, 1.0); }",  # a status wait in the loop
    "for (;;) { while (!IsInPos(0)); MoveAbs(0, 1.0); }",  # the same as a busy wait
    "for (;;) { if (IsInPos(0)) break; RunScheduler(); } Till(IsMoving(0));",
    "for (;;) { if (IsInPos(0)) return; RunScheduler(); }",
    "for (;;) { if (IsInPos(0)) goto out; RunScheduler(); } out: a = 1;",
    "for (;;) { w(); }",  # a user's function that may block
    "while (a < 3) { a = IsInPos(0); RunScheduler(); }",  # not forever
]
WAITER = "void w() { Till(IsInPos(0)); }\n"


def _python_with_waiter(body: str) -> str:
    src = f"int g;\n{WAITER}void main() {{\n int a = 0;\n {body}\n}}\n"
    sink = DiagnosticSink()
    prog, _mem = compile_tasks([TaskFile(0, "p.hmpl", src)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog.python_source()


@pytest.mark.parametrize("body", ENDS)
def test_a_loop_never_left_without_a_status_wait_ends_the_records(body):
    assert "_end_records()" in _python_with_waiter(body)


@pytest.mark.parametrize("body", KEEPS)
def test_a_loop_that_may_be_left_or_may_poll_a_status_keeps_them(body):
    assert "_end_records()" not in _python_with_waiter(body)


LOOP = """
int seed = 7;
void main() {
    int i;
    for (i = 0; i < 2; i++) Enable(i);
    for (i = 0; i < 2; i++) Till(IsEnabled(i));
    for (;;) {
        for (i = 0; i < 2; i++) {
            if (IsInPos(i)) {
                seed = seed * 1103515245 + 12345;
                MoveAbs(i, ((seed >> 8) & 255) / 4.0);
            }
        }
        RunScheduler();
    }
}
"""


def _end(skip: bool):
    sim = Simulation([TaskFile(0, "loop.hmpl", LOOP)], skip=skip)
    sim.run(until=0.3)
    axes = sim.controller.motion.axes[:2]
    return sim, [(a.pos_fb, a.in_pos, a.moving) for a in axes]


def test_the_task_in_such_a_loop_records_nothing_and_runs_as_before():
    sim, stepped = _end(skip=False)
    kernel = sim.controller.kernel
    assert kernel.tasks[0].running and not kernel.tasks[0].records
    lists = []

    class Recorder:  # what the kernel hands the status flags around a slice
        def __setattr__(self, k, v):
            lists.append(v)

    kernel.recorder = Recorder()
    kernel.run_cycle()
    assert lists == [None, None]  # the slice ran with no list to record into
    assert stepped == _end(skip=True)[1]
