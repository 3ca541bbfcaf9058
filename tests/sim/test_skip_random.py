"""Random move sequences with random waits print the same, skipping or stepping.

Each example is an HMPL program of two tasks on three axes: moves (absolute, relative,
jogs, buffered moves), stops, speed changes, smoothing, velocity scales, SetPos,
rollover, disabling and resetting, ignored software limits, and waits of every kind
(Till on an axis event, on a time, on a position, Sleep), with the axes' feedback and reference
printed at random points, on a random machine (cycle time, motor delay, counts per mm,
limit switches and software limits within reach, a tight position error limit). It
runs with skipping and with `--no-skip`; the outputs (with `--stamp` times) and the
final state of every axis must be identical.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from skip_util import machine_file, outcome

settings.register_profile("skip-ci", max_examples=25, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("skip-thorough", max_examples=300, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("skip-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

AXES = 3

position = st.floats(-900.0, 900.0).map(lambda x: round(x, 3))
axis = st.integers(0, AXES - 1)


def _print(a: int) -> str:
    return (f'Print("%d a{a} %.9f %.9f %.9f %d %d", system_timeInMs, GetPosFb({a}), '
            f"GetVelFb({a}), GetRefPos({a}), IsInPos({a}), IsMoving({a}));")  # fmt: skip


def _position_wait(a: int, p: float, f: float, strict: bool) -> str:
    """A move and a wait until the feedback passes the fraction `f` of its way (or the
    axis stops short of it), the time and position printed."""
    up, down = (">", "<") if strict else (">=", "<=")
    way = f"p_0 + (p_1 - p_0) * {f!r}"
    return (f"p_1 = {p}; p_0 = GetPosFb({a}); MoveAbs({a}, p_1); "
            f"if (p_1 > p_0) Till(GetPosFb({a}) {up} {way} || !IsMoving({a})); "
            f"else Till({way} {up.replace('>', '<')} GetPosFb({a}) || !IsMoving({a})); "
            f'Print("%d at a{a} %.9f", system_timeInMs, GetPosFb({a}));')  # fmt: skip


statement = st.one_of(
    st.builds(lambda a, p: f"MoveAbs({a}, {p});", axis, position),
    st.builds(
        lambda a, d: f"MoveRel({a}, {d});", axis, st.floats(-200, 200).map(lambda x: round(x, 2))
    ),
    st.builds(
        lambda a, v, t: f"MoveVel({a}, {v}); Sleep({t}); Stop({a});",
        axis,
        st.sampled_from([-300.0, -50.0, 80.0, 400.0]),
        st.integers(0, 200),
    ),
    st.builds(lambda a: f"Till(IsInPos({a}));", axis),
    st.builds(lambda a: f"Till(!IsMoving({a}));", axis),
    st.builds(lambda a, b: f"Till(IsInPos({a}) && IsInPos({b}));", axis, axis),
    st.builds(_position_wait, axis, position, st.floats(0.0, 1.0), st.booleans()),
    st.builds(lambda t: f"Sleep({t});", st.integers(0, 400)),
    st.builds(
        lambda t: f"t_end = system_timeInMs + {t}; Till(system_timeInMs >= t_end);",
        st.integers(0, 300),
    ),
    st.builds(lambda a, v: f"SetVel({a}, {v});", axis, st.sampled_from([50.0, 300.0, 1000.0])),
    st.builds(lambda a, v: f"SetAcc({a}, {v});", axis, st.sampled_from([500.0, 10000.0])),
    st.builds(lambda a, s: f"SetVelScale({a}, {s});", axis, st.sampled_from([0.0, 50.0, 100.0])),
    st.builds(
        lambda a, t: f"Till(!IsMoving({a})); SetSMTime({a}, {t});",
        axis,
        st.sampled_from([0.0, 0.0, 5.0, 30.0]),
    ),
    st.builds(lambda a: f"Stop({a});", axis),
    st.builds(lambda a, p: f"Till(!IsMoving({a})); SetPos({a}, {p});", axis, position),
    st.builds(lambda a: f"Disable({a}); Reset({a}); Enable({a}); Till(IsEnabled({a}));", axis),
    st.builds(
        lambda a, r: f"Till(!IsMoving({a})); SetRollover({a}, {r});",
        axis,
        st.sampled_from([0.0, 360.0]),
    ),
    st.builds(lambda a, on: f"IgnoreSWL({a}, {on});", axis, st.sampled_from([0, 1])),
    st.builds(lambda a, m: f"SetBufferMode({a}, {m});", axis, st.sampled_from([0, 1])),
    st.builds(_print, axis),
)


def _task(body: list[str], first: bool) -> str:
    lines = ["int t_end;", "double p_0, p_1;", "void main() {"]
    if first:
        lines += ["    StartTask(1);"] + [
            f"    Enable({a}); Till(IsEnabled({a}));" for a in range(AXES)
        ]
    else:
        lines += ["    Till(IsEnabled(2));"]
    lines += [f"    {s}" for s in body]
    lines += [f"    SetVelScale({a}, 100); Till(!IsMoving({a})); {_print(a)}" for a in range(AXES)]
    lines += ["}"]
    return "\n".join(lines) + "\n"


axis_table = st.fixed_dictionaries({
    "counts_per_unit": st.sampled_from([10000.0, 1000.0, 364.0888]),
    "hw_right": st.sampled_from([1050.0, 450.0]),
    "sw_right": st.sampled_from([1000.0, 600.0, 300.0]),
    "max_pos_err": st.sampled_from([10.0, 0.8]),
    "start_position": st.sampled_from([0.0, 12.34]),
    "delay": st.sampled_from([0, 1, 3]),
})  # fmt: skip
machine = st.tuples(st.sampled_from([1.0, 0.5, 2.0]), st.lists(axis_table, min_size=AXES,
                                                             max_size=AXES))  # fmt: skip


@PROFILE
@given(st.lists(statement, min_size=1, max_size=12), st.lists(statement, max_size=8))
def test_random_moves_and_waits_give_the_same_run(tmp_path_factory, body_0, body_1):
    tmp = tmp_path_factory.mktemp("prog")
    sources = [_task(body_0, True), _task(body_1, False)]
    assert outcome(tmp, sources, True) == outcome(tmp, sources, False)


@PROFILE
@given(machine, st.lists(statement, min_size=1, max_size=10), st.lists(statement, max_size=6))
def test_random_machines_give_the_same_run(tmp_path_factory, spec, body_0, body_1):
    tmp = tmp_path_factory.mktemp("machine")
    machine = machine_file(tmp, spec, AXES)
    sources = [_task(body_0, True), _task(body_1, False)]
    assert outcome(tmp, sources, True, machine) == outcome(tmp, sources, False, machine)
