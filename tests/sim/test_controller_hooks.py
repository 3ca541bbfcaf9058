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
    # idle: no wire, sensor, binding or I/O slave, no request, no PT armed
    assert ctl._begin_hooks == [] and ctl._end_hooks == []


def _count_calls(ctl: Controller, client, calls: list, *names: str) -> None:
    """Record `(cycle, client class, hook)` for each call of the hooks `names` of `client`
    (instance attributes: the controller takes them as the client's hooks)."""
    for name in names:
        real = getattr(client, name)

        def hook(real=real, name=name) -> None:
            calls.append((ctl.cycle, type(client).__name__, name))
            real()

        setattr(client, name, hook)


def test_an_idle_run_calls_no_hook_of_the_io_comm_agent_or_triggers():
    from motionvm.api import Simulation

    sim = Simulation.from_source("void main() { int i; for (i = 0; i < 30; i++) Sleep(1); }")
    ctl = sim.controller
    ctl.skip = False
    calls: list = []
    for c in (ctl.io, ctl.comm, ctl.triggers, sim.session.side("HMPL").comm):
        _count_calls(ctl, c, calls, "begin_cycle", "end_cycle")
    sim.run()
    assert ctl.cycles_computed >= 30 and calls == []
    sim.close()


def test_work_that_appears_makes_its_hook_run_in_the_same_cycle_as_before():
    from motionvm.io.trigger_commands import TriggerCommands
    from motionvm.motion.commands import MotionCommands

    ctl = Controller()
    calls: list = []
    _count_calls(ctl, ctl.triggers, calls, "end_cycle")
    _count_calls(ctl, ctl.comm, calls, "begin_cycle")
    m, pt = MotionCommands(ctl.motion), TriggerCommands(ctl.motion, ctl.triggers)
    m.Enable(0)
    while not m.IsEnabled(0):
        ctl.step()
    m.SetHomedStatus(0, 1)
    ctl.step()
    assert calls == []
    # a PT armed between cycles: sampled from the next cycle on
    assert pt.SetPT_StartPos(0, 1) == pt.SetPT_Interval(0, 1) == pt.SetPT_EndPos(0, 2) == 0
    assert pt.EnablePT(0) == 0
    start = ctl.cycle
    ctl.step()
    ctl.step()
    assert calls == [
        (start, "PositionTriggers", "end_cycle"),
        (start + 1, "PositionTriggers", "end_cycle"),
    ]
    # disarmed: no call from the next cycle on
    pt.DisablePT(0)
    calls.clear()
    ctl.step()
    assert calls == []
    # a PT armed while the tasks run: sampled in that very cycle
    plain = ctl.kernel.run_cycle

    def arming() -> None:
        plain()
        assert pt.EnablePT(0) == 0
        ctl.kernel.run_cycle = plain

    ctl.kernel.run_cycle = arming
    armed_in = ctl.cycle
    ctl.step()
    assert calls == [(armed_in, "PositionTriggers", "end_cycle")]
    pt.DisablePT(0)
    calls.clear()
    # a request posted between cycles runs at the next cycle's start, then the hub idles
    ran: list = []
    fut = ctl.comm.post(lambda: ran.append(ctl.cycle) or 7)
    posted_in = ctl.cycle
    ctl.step()
    assert ran == [posted_in] and fut.result() == 7
    ctl.step()
    assert calls == [(posted_in, "CommHub", "begin_cycle")]
    # servers listening: the hub is called every cycle
    calls.clear()
    ctl.comm.serving = True
    ctl.step()
    ctl.step()
    ctl.comm.serving = False
    ctl.step()
    assert [c for c, _, _ in calls] == [posted_in + 2, posted_in + 3]


def test_a_request_posted_by_another_thread_runs_at_the_next_cycle():
    import threading

    ctl = Controller()
    ctl.step()
    futures: list = []
    t = threading.Thread(target=lambda: futures.append(ctl.comm.post(lambda: ctl.cycle)))
    t.start()
    t.join()
    at = ctl.cycle
    ctl.step()
    assert futures[0].result(timeout=0) == at


def test_a_wire_keeps_the_io_hooks_called_every_cycle():
    from dataclasses import replace

    from motionvm.io.config import IOConfig, WireSpec, parse_endpoint
    from motionvm.sim.machine import DEFAULT_MACHINE

    wire = WireSpec(parse_endpoint("gpo1"), parse_endpoint("gpi1"), delay_ms=2)
    ctl = Controller(machine=replace(DEFAULT_MACHINE, io=IOConfig(wires=(wire,))))
    calls: list = []
    _count_calls(ctl, ctl.io, calls, "begin_cycle", "end_cycle")
    ctl.step()
    ctl.io.gpio.set_output(1, 1)
    levels = []
    for _ in range(4):
        ctl.step()
        levels.append(ctl.io.gpio.input(1))
    assert levels == [0, 0, 0, 1]  # set before cycle 1: the input has it from cycle 4 on
    assert [c for c, _, _ in calls] == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4]


def test_a_line_for_the_ascii_agent_starts_in_the_cycle_the_hub_receives_it():
    import concurrent.futures

    from motionvm.api import Simulation

    program = """
    void First(char *cmd, char *res) { res[0] = cmd[0]; res[1] = 0; }
    void main() { START_ASCII_AGENT(First); for (;;) RunScheduler(); }
    """
    sim = Simulation.from_source(program, skip=False)
    ctl, agent = sim.controller, sim.session.side("HMPL").comm
    ctl.step()  # main starts the agent
    assert agent.begin_cycle in ctl._begin_hooks
    reply: concurrent.futures.Future = concurrent.futures.Future()
    ctl.comm.post(lambda: agent.accept("hello", reply))
    ctl.step()  # the hub hands the line over, the agent's parser answers: one cycle
    assert reply.done() and reply.result() == "h"
    sim.close()


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
