"""The controller's per-cycle client hooks: which it calls, in what order, and when a
client added mid-run starts being called."""

from __future__ import annotations

from motionvm.runtime.clients import PassiveClient, active_hooks
from motionvm.sim.controller import Controller


class Logger(PassiveClient):
    def __init__(self, name: str, calls: list) -> None:
        self.name, self.calls = name, calls

    def begin_cycle(self) -> None:
        self.calls.append(("begin", self.name))

    def end_cycle(self) -> None:
        self.calls.append(("end", self.name))


class EndOnly(PassiveClient):
    def __init__(self, calls: list) -> None:
        self.calls = calls

    def end_cycle(self) -> None:
        self.calls.append(("end", "end-only"))


def test_active_hooks_leave_out_the_passive_no_ops_and_keep_the_order():
    calls: list = []
    a, quiet, b, e = Logger("a", calls), PassiveClient(), Logger("b", calls), EndOnly(calls)
    assert active_hooks([a, quiet, b, e], "begin_cycle") == [a.begin_cycle, b.begin_cycle]
    assert active_hooks([a, quiet, b, e], "end_cycle") == [a.end_cycle, b.end_cycle, e.end_cycle]
    quiet.begin_cycle = lambda: calls.append(("begin", "instance"))  # set on the instance
    assert active_hooks([quiet], "begin_cycle") == [quiet.begin_cycle]


def test_the_standard_clients_cost_no_call_where_they_do_nothing():
    ctl = Controller()
    ctl.step()
    assert ctl.triggers.begin_cycle not in ctl._begin_hooks
    assert ctl.comm.end_cycle not in ctl._end_hooks
    assert ctl.io.begin_cycle in ctl._begin_hooks and ctl.triggers.end_cycle in ctl._end_hooks


def test_a_client_added_between_or_within_cycles_is_called_as_in_the_list():
    calls: list = []
    ctl = Controller()
    ctl.clients.append(Logger("a", calls))
    ctl.step()
    assert calls == [("begin", "a"), ("end", "a")]
    calls.clear()

    class Adder(PassiveClient):  # adds a client while the tasks run, once (as a task could)
        added = False

        def begin_cycle(self) -> None:
            if not self.added:
                self.added = True
                ctl.kernel.run_cycle = adding

    plain_run_cycle = ctl.kernel.run_cycle

    def adding() -> None:
        plain_run_cycle()
        ctl.add_client(Logger("b", calls))
        ctl.kernel.run_cycle = plain_run_cycle

    ctl.add_client(Adder())
    ctl.step()  # b came during the tasks: its end_cycle runs in this very cycle
    assert calls == [("begin", "a"), ("end", "a"), ("end", "b")]
    calls.clear()
    ctl.clients.remove(ctl.clients[-3])  # Logger a leaves
    ctl.step()
    assert calls == [("begin", "b"), ("end", "b")]


def test_a_run_asks_no_busy_while_a_task_runs_and_the_task_is_resumed_each_cycle():
    from motionvm.api import Simulation

    sim = Simulation.from_source("void main() { for (;;) RunScheduler(); }", skip=False)
    ctl = sim.controller
    asked = []
    real_busy = ctl.busy
    ctl.busy = lambda: asked.append(ctl.cycle) or real_busy()
    resumed = []
    before_resume = ctl.kernel.before_resume
    ctl.kernel.before_resume = lambda t: resumed.append(ctl.cycle) or before_resume(t)
    sim.run(until=0.05)
    assert asked == []  # the running task keeps the run going: nothing else is asked
    assert resumed == list(range(50))
    sim.close()
