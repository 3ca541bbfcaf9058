"""The end of a move and the settle into position are jumped over in closed form: the
same output as stepping, one computed cycle per move where nobody watches `IsMoving`.

Random programs of two tasks move three axes and wait on their status (in position, not
moving, moving, a time), printing the move and settling times and the feedback with
`--stamp` times, on random machines: in-position radius and debounce time, motor delay,
counts per mm, cycle time. Each runs skipping and stepping; the outputs and the final
state of every axis must be identical.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from skip_util import machine_file, outcome

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile

settings.register_profile("settle-ci", max_examples=20, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("settle-thorough", max_examples=300, derandomize=True,
                          deadline=None, suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("settle-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

AXES = 3
axis = st.integers(0, AXES - 1)


def _print(a: int) -> str:
    return (f'Print("%d a{a} %.9f %.9f %d %d %.3f %.3f", system_timeInMs, GetPosFb({a}), '
            f"GetRefPos({a}), IsInPos({a}), IsMoving({a}), GetMoveTime({a}), "
            f"GetSettlingTime({a}));")  # fmt: skip


statement = st.one_of(
    st.builds(
        lambda a, p: f"MoveAbs({a}, {p});",
        axis,
        st.floats(-300.0, 300.0).map(lambda x: round(x, 4)),
    ),  # fmt: skip
    st.builds(lambda a, d: f"MoveRel({a}, {d});", axis, st.sampled_from([0.0001, 2.5, -40.0])),
    st.builds(lambda a: f"Till(IsInPos({a}));", axis),
    st.builds(lambda a: f"Till(!IsMoving({a}));", axis),
    st.builds(lambda a: f"Till(IsMoving({a}) || IsInPos({a}));", axis),
    st.builds(lambda a, b: f"Till(IsInPos({a}) && !IsMoving({b}));", axis, axis),
    st.builds(lambda t: f"Sleep({t});", st.integers(0, 150)),
    st.builds(_print, axis),
)

axis_table = st.fixed_dictionaries({
    "inpos_radius": st.sampled_from([0.01, 1e-9, 0.5]),
    "inpos_debounce_ms": st.sampled_from([0.0, 1.0, 5.0]),
    "counts_per_unit": st.sampled_from([10000.0, 3.0]),
    "delay": st.sampled_from([0, 1, 3]),
})  # fmt: skip
machine = st.tuples(st.sampled_from([1.0, 0.5]), st.lists(axis_table, min_size=AXES,
                                                        max_size=AXES))  # fmt: skip


def _task(body: list[str], first: bool) -> str:
    lines = ["void main() {"]
    if first:
        lines += ["    StartTask(1);"]
        lines += [f"    Enable({a}); Till(IsEnabled({a}));" for a in range(AXES)]
    else:
        lines += ["    Till(IsEnabled(2));"]
    lines += [f"    {s}" for s in body]
    lines += [f"    Till(!IsMoving({a})); {_print(a)}" for a in range(AXES)]
    return "\n".join([*lines, "}"]) + "\n"


@PROFILE
@given(machine, st.lists(statement, min_size=1, max_size=8), st.lists(statement, max_size=6))
def test_random_settles_give_the_same_run(tmp_path_factory, spec, body_0, body_1):
    tmp = tmp_path_factory.mktemp("settle")
    machine = machine_file(tmp, spec, AXES)
    sources = [_task(body_0, True), _task(body_1, False)]
    assert outcome(tmp, sources, True, machine, 20.0) == outcome(tmp, sources, False, machine, 20.0)


MOVER = """
void main() {
    int k;
    Enable(0); Till(IsEnabled(0));
    for (k = 0; k < 10; k++) {
        MoveAbs(0, k % 2 ? 0.0 : 100.0);
        Till(IsInPos(0));
    }
    Print("at %.6f, %.1f ms, settled in %.1f ms", GetPosFb(0), GetMoveTime(0),
          GetSettlingTime(0));
}
"""


def _wait_run(source: str, skip: bool):
    sim = Simulation([TaskFile(0, "t.hmpl", source)], skip=skip, stamp=True)
    sim.run(timeout=30.0)
    return (sim.messages, sim.time), sim.controller


def test_a_wait_on_in_position_jumps_from_move_to_move():
    jumped, ctl = _wait_run(MOVER, True)
    stepped, _ = _wait_run(MOVER, False)
    assert jumped == stepped
    # 10 moves of 0.2 s: per move the cycle that commands it, one jump to the cycle in
    # which the axis is in position (before: two more, the end of region I and the
    # settle, each a cycle of its own)
    assert ctl.cycles_computed <= 10 + 4
    assert ctl.jumps.jumps <= 10 + 10


def test_a_wait_on_not_moving_ends_the_jump_where_region_i_ends():
    source = MOVER.replace("Till(IsInPos(0));", 'Till(!IsMoving(0)); Print("%d", IsInPos(0));')
    jumped, _ = _wait_run(source, True)
    stepped, _ = _wait_run(source, False)
    assert jumped == stepped
    assert any(line.endswith("0") for line in jumped[0])  # polled before in position
