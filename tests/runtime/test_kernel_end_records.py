"""`Kernel.end_records`: a task that can never again poll a status keeps no record of
the status flags it reads from its next slice on, until it is started again."""

from __future__ import annotations

from types import SimpleNamespace

from motionvm.runtime.kernel import STATUS_POLL, Kernel


def _task(kernel: Kernel, recorder, seen: list, end_at: int):
    k = 0
    while True:
        seen.append(recorder.reads)
        k += 1
        if k == end_at:
            kernel.end_records()
        yield None


def test_slices_after_end_records_have_no_reads_list_until_a_restart():
    kernel = Kernel()
    recorder = SimpleNamespace(reads=None)
    kernel.recorder = recorder
    seen: list = []
    kernel.start(0, _task(kernel, recorder, seen, end_at=2))
    for _ in range(4):
        kernel.run_cycle()
        kernel.clock.cycle += 1
    assert [type(x).__name__ for x in seen] == ["list", "list", "NoneType", "NoneType"]
    assert recorder.reads is None  # (between slices, as ever)
    kernel.stop(0)
    seen.clear()
    kernel.start(0, _task(kernel, recorder, seen, end_at=0))
    kernel.run_cycle()
    assert type(seen[0]) is list  # a task started again records again


def test_a_task_that_still_records_keeps_its_status_poll_record():
    kernel = Kernel()
    flag = SimpleNamespace(in_pos=False)
    recorder = SimpleNamespace(reads=None)
    kernel.recorder = recorder

    def poll():
        while True:
            recorder.reads.append((flag, "in_pos", flag.in_pos))
            yield STATUS_POLL

    kernel.start(0, poll())
    kernel.run_cycle()
    assert kernel.tasks[0].record == [(flag, "in_pos", False)]
    assert kernel.tasks[0].record_holds()
    assert not kernel.unrecorded_waits


def test_end_records_outside_a_slice_changes_no_task():
    kernel = Kernel()
    kernel.start(0, iter(()))
    kernel.end_records()
    assert kernel.tasks[0].records
