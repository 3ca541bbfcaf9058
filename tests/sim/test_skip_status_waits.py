"""A task waiting on axis status flags alone is passed over while those flags answer the
same, whatever other tasks do: fewer computed cycles, the same output as stepping.

Each program runs skipping and stepping (with `--stamp` times); the printed lines, the
end time and the axes' end states must be equal, and the skipping run must compute
only a few cycles per move where that is the point.
"""

from __future__ import annotations

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.runtime.kernel import STATUS_POLL, STATUS_WAIT, Kernel


def _run(sources: list[str], skip: bool):
    tasks = [TaskFile(i, f"t{i}.hmpl", s) for i, s in enumerate(sources)]
    sim = Simulation(tasks, skip=skip, stamp=True)
    sim.run(timeout=30.0)
    axes = sim.controller.motion.axes
    state = [(a.pos_fb, a.ref_pos, a.in_pos, a.moving, a.move_time_ms) for a in axes]
    return (sim.messages, sim.time, state, sim.faults), sim.controller.cycles_computed


def _same(sources: list[str]) -> int:
    """Cycles computed skipping; asserts the run equals the stepped one."""
    jumped, computed = _run(sources, True)
    stepped, _ = _run(sources, False)
    assert jumped == stepped
    assert not jumped[3], jumped[3]
    return computed


MOVER = """
void main() {
    int k;
    START
    Enable(AXIS); Till(IsEnabled(AXIS));
    for (k = 0; k < 5; k++) {
        MoveAbs(AXIS, k % 2 ? 0.0 : 40.0 + 10.0 * AXIS);
        Till(IsInPos(AXIS));
        Print("axis %d move %d at %.6f", AXIS, k, GetPosFb(AXIS));
    }
}
"""


def test_tasks_waiting_on_their_own_axes_compute_one_cycle_per_move():
    sources = [
        MOVER.replace("START", "StartTask(1); StartTask(2);" if i == 0 else "").replace(
            "AXIS", str(i)
        )
        for i in range(3)
    ]
    computed = _same(sources)
    # 3 axes x 5 moves of different lengths: each move ends in its own cycle, where
    # its task acts (the others are passed over); a few more to start and enable
    assert computed <= 3 * 5 + 12


def test_a_wait_on_an_axis_another_task_commands_sees_every_change():
    watcher = """
void main() {
    StartTask(1);
    Till(IsMoving(1));
    Print("moving at %d", system_timeInMs);
    Till(IsInPos(1) && !IsMoving(1));
    Print("in position at %d, %.6f", system_timeInMs, GetPosFb(1));
    Till(IsMoving(1) || IsErrorStop(1));
    Print("moving again at %d", system_timeInMs);
    Till(IsInPos(1));
    Print("done at %d", system_timeInMs);
}
"""
    commander = """
void main() {
    Enable(1); Till(IsEnabled(1));
    Sleep(37);
    MoveAbs(1, 25.0);
    Till(IsInPos(1));
    Sleep(11);
    MoveRel(1, -5.0);
}
"""
    _same([watcher, commander])


def test_a_command_in_the_same_cycle_as_the_poll_is_seen():
    # task 1 moves axis 0 in the cycle task 0 starts waiting on it (after task 0 polled)
    waiter = """
void main() {
    StartTask(1);
    Enable(0); Till(IsEnabled(0));
    RunScheduler();
    Till(IsMoving(0));
    Print("axis 0 moves at %d", system_timeInMs);
}
"""
    mover = """
void main() {
    Till(IsEnabled(0));
    RunScheduler();
    MoveAbs(0, 3.0);
    Till(IsInPos(0));
    Print("axis 0 in position at %d", system_timeInMs);
}
"""
    _same([waiter, mover])


def test_a_wait_on_a_global_another_task_writes_is_polled_again():
    waiter = """
int go;
void main() {
    StartTask(1);
    Till(go && IsInPos(0));
    Print("go at %d", system_timeInMs);
}
"""
    setter = """
extern int go;
void main() {
    Enable(0); Till(IsEnabled(0));
    Sleep(20);
    go = 1;
}
"""
    _same([waiter, setter])


def test_a_wait_on_a_bad_axis_id_keeps_its_error_as_stepping_does():
    src = """
void main() {
    int bad = 99;
    StartTask(1);
    Till(IsInPos(bad) || IsMoving(0));
    Print("error %x at %d", GetSystemLastErr(), system_timeInMs);
}
"""
    other = """
void main() {
    Enable(0); Till(IsEnabled(0));
    Sleep(15);
    MoveAbs(0, 2.0);
}
"""
    _same([src, other])


def test_the_kernel_keeps_the_flags_a_status_poll_read():
    class Flags:
        in_pos = False

    class Recorder:
        reads = None

    flags, recorder = Flags(), Recorder()
    kernel = Kernel()
    kernel.recorder = recorder

    def task():
        recorder.reads.append((flags, "in_pos", flags.in_pos))
        yield STATUS_WAIT
        while True:
            recorder.reads.append((flags, "in_pos", flags.in_pos))
            yield STATUS_POLL

    kernel.start(0, task())
    kernel.run_cycle()
    t = kernel.tasks[0]
    assert t.record == [(flags, "in_pos", False)] and t.record_holds()
    assert recorder.reads is None  # nothing is recorded between slices
    flags.in_pos = True
    assert not t.record_holds()
