"""PDL drive scheduling: phase clock, task_prior weights, sleep vs wait, lock, host control.

The reference model is the manual's §1.1.1: runnable tasks take turns in
task order, task n keeping max(task_prior[n], 1) consecutive phases; sleeping tasks
are not runnable, waiting ones are and burn their phases.
"""

from __future__ import annotations

import pytest

from motionvm.lang.pdl.drive_rt import Drive, DriveConfig
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source import DiagnosticSink, render_diagnostic

COUNTERS = """
#long c0, c1, c2, c3;
#task/0;
PRIOR0
l0: c0++; goto l0;
#task/1;
PRIOR1
l1: c1++; goto l1;
#task/2;
PRIOR2
l2: c2++; goto l2;
"""


def drive_of(text: str, **config: object) -> Drive:
    sink = DiagnosticSink()
    program = compile_pdl("mem/timing.pdl", sink=sink, text=text)
    assert program is not None, "\n".join(render_diagnostic(d) for d in sink.items)
    out: list[str] = []
    drive = Drive(
        program, DriveConfig(**config), on_message=lambda m: out.append(m.text), on_fault=out.append
    )  # type: ignore[arg-type]
    drive.out = out  # type: ignore[attr-defined]
    return drive


def counters(prior: tuple[str, str, str], seconds: float = 1.0, **config: object) -> list[int]:
    text = COUNTERS
    for k, p in enumerate(prior):
        text = text.replace(f"PRIOR{k}", p)
    d = drive_of(text, **config)
    d.run(seconds)
    return [int(d.read(f"c{k}")) for k in range(3)]


def test_equal_priorities_share_the_phases_equally() -> None:
    c = counters(("", "", ""))
    assert max(c) - min(c) <= 1
    # 15000 phases, 3 tasks, 2 statements (c++ and goto) per pass at 1 statement per phase
    assert sum(c) == pytest.approx(15000 / 2, abs=3)


def test_task_prior_gives_consecutive_phases_w1() -> None:
    # W1: task_prior = {5, 0, 1} -> T = 7; task 0 gets 5/7 of the phases.
    c = counters(("task_prior[task_num]=5;", "task_prior[task_num]=0;", "task_prior[task_num]=1;"))
    assert c[0] / c[1] == pytest.approx(5, rel=0.01)
    assert c[1] == pytest.approx(c[2], abs=2)
    assert c[0] * 2 == pytest.approx(15000 * 5 / 7, rel=0.01)


def test_scheduling_does_not_depend_on_the_budget_unit() -> None:
    a = counters(("task_prior[task_num]=3;", "", ""), budget=1)
    b = counters(("task_prior[task_num]=3;", "", ""), budget=10)
    assert a[0] / a[1] == pytest.approx(3, rel=0.02)
    assert b[0] / b[1] == pytest.approx(3, rel=0.02)


SLEEP_VS_WAIT = """
#long c0, c1;
#task/0;
l0: c0++; goto l0;
#task/1;
l1: c1++; DELAY; goto l1;
"""


def test_sleep_releases_the_cpu_and_wait_does_not() -> None:
    sleeper = drive_of(SLEEP_VS_WAIT.replace("DELAY", "sleep 10"))
    waiter = drive_of(SLEEP_VS_WAIT.replace("DELAY", "wait 200"))  # 200 x 50 us = 10 ms
    sleeper.run(1.0)
    waiter.run(1.0)
    # both pause task 1 for 10 ms per pass
    assert sleeper.read("c1") == pytest.approx(100, abs=2)
    assert waiter.read("c1") == pytest.approx(100, abs=2)
    # while sleeping, task 1 leaves every phase to task 0; while waiting it burns half of them
    assert sleeper.read("c0") == pytest.approx(7400, rel=0.01)
    assert waiter.read("c0") == pytest.approx(3750, rel=0.02)


def test_lock_gives_every_phase_to_the_locked_task() -> None:
    d = drive_of("""
#long c0, c1, got;
#task/0;
sleep 1;
lock;
got=c1;
loop(1000) do c0++; end;
if (c1 = got) printl("nobody ran while locked");
unlock;
sleep 100;
if (c1 > got) printl("task 1 runs again");
halt;
#task/1;
l1: c1++; goto l1;
""")
    d.run(1.0)
    assert d.out == ["nobody ran while locked", "task 1 runs again"]  # type: ignore[attr-defined]


def test_fclk_wraps_as_signed_32_bit() -> None:
    d = drive_of("#long a;\n#task/0;\nsleep 1000;\nhalt;\n", fclk_start=2**31 - 10)
    d.run(0.001)
    assert d.fclk == -(2**31) + 5
    assert d.run(2.0)  # the task ends after its sleep: the run stops there
    assert d.phase == 15000 + 1


def test_sleeping_drive_skips_ahead_exactly() -> None:
    d = drive_of(
        '#long t0, d;\n#task/0;\nt0=fclk;\nsleep 30000;\nd=fclk-t0;\nprintl("%ld", d);\nhalt;\n'
    )
    assert d.run(40.0)
    assert d.out == ["450001"]  # type: ignore[attr-defined]


def test_kill_and_host_control() -> None:
    d = drive_of("""
#long c1;
#task/0;
sleep 10;
kill 1;
printl("killed 1");
kill 0;
printl("never");
_b1:
l1: c1++; goto l1;
_ends:
ret;
""")
    assert d.start("_b1") == 1
    with pytest.raises(ValueError, match="still running"):
        d.start("_b1")
    with pytest.raises(ValueError, match="starting with '_'"):
        d.start("l1")
    d.run(1.0)
    assert d.out == ["killed 1"]  # type: ignore[attr-defined]
    assert not d.busy
    n = d.start("_b1")
    d.run(1.5)
    d.kill(n)
    assert d.start("_b1") == n
    assert d.start("_ends") == 1


def test_till_is_rechecked_every_phase_of_the_task() -> None:
    d = drive_of("""
#long flag, t0, d;
#task/0;
t0=fclk;
till(flag=1);
d=fclk-t0;
printl("%ld", d);
halt;
#task/1;
sleep 100;
flag=1;
halt;
""")
    d.run(1.0)
    [text] = d.out  # type: ignore[attr-defined]
    assert 1500 <= int(text) <= 1505


def test_host_writes_honour_ro_and_lp_w44() -> None:
    d = drive_of("#float _ro v1;\n#float _lp(-0.5, 0.5) pgain;\n#task/0;\npgain=0.7;\nhalt;\n")
    with pytest.raises(ValueError, match="read-only"):
        d.write("v1", 1.0)
    with pytest.raises(ValueError, match="outside the _lp limits"):
        d.write("pgain", 0.7)
    d.write("pgain", 0.25)
    assert d.read("pgain") == 0.25
    d.run(1.0)
    assert d.read("pgain") == pytest.approx(0.7)  # PDL code itself may write it


def test_promoted_loop_shares_globals_at_every_yield() -> None:
    # task 0 counts in a loop whose scalars live in Python locals; task 1 must see them
    d = drive_of("""
#long c, seen;
#task/0;
loop(0) do c++; end;
halt;
#task/1;
sleep 10;
seen = c;
printl("%ld", seen);
halt;
""")
    d.run(0.1)
    [text] = d.out  # type: ignore[attr-defined]
    assert 70 <= int(text) <= 80  # 150 phases, half of them task 0's, 2 statements per pass
