"""Random axis-group programs print the same, skipping or stepping.

Each example is an HMPL program of two tasks: one drives a 2-D group (axes 0, 1) on
lines, arcs and circles with look-ahead or another buffer mode, the other a 3-D group
(axes 2, 3, 4) on buffered lines and a helix; smoothing times, velocity scales, halts
and resumes, stops, and waits of every kind (IsGrpInPos, IsGrpMoving, a time, Sleep)
between them, the groups' feedback printed at random points, on a random machine
(cycle time, motor delay, counts per mm). It runs with skipping and with `--no-skip`;
the outputs (with `--stamp` times) and the final state of every axis must be identical.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from skip_util import machine_file, outcome

settings.register_profile("skip-groups-ci", max_examples=12, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("skip-groups-thorough", max_examples=200, derandomize=True,
                          deadline=None, suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("skip-groups-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

coord = st.integers(-60, 60).map(float)


def _print(g: int) -> str:
    axes = (0, 1) if g == 0 else (2, 3, 4)
    fmt = " ".join(["%.9f"] * len(axes))
    args = ", ".join(f"GetPosFb({a})" for a in axes)
    return (f'Print("%d g{g} {fmt} %d %d", system_timeInMs, {args}, IsGrpInPos({g}), '
            f"IsGrpMoving({g}));")  # fmt: skip


waits = [
    lambda g: f"Till(IsGrpInPos({g}));",
    lambda g: f"Till(!IsGrpMoving({g}));",
    lambda g: f"while (!IsGrpInPos({g})) RunScheduler();",
]


def _wait(g: int):
    return st.builds(lambda i, t: waits[i](g) if i < len(waits) else f"Sleep({t});",
                     st.integers(0, len(waits)), st.integers(0, 300))  # fmt: skip


plane = st.one_of(
    st.builds(lambda x, y: f"LineAbs2D(0, {x}, {y});", coord, coord),
    st.builds(lambda x, y: f"LineRel2D(0, {x}, {y});", coord, coord),
    st.builds(
        lambda cx, cy, a: f"ArcAngle2D(0, {cx}, {cy}, {a});",
        coord,
        coord,
        st.sampled_from([90.0, -180.0, 45.0, 370.0]),
    ),  # fmt: skip
    st.builds(lambda m: f"SetGrpBufferMode(0, {m});", st.sampled_from([0, 2, 5, 6, 6])),
    st.builds(
        lambda t: f"Till(!IsGrpMoving(0)); SetGrpSMTime(0, {t});", st.sampled_from([0.0, 5.0, 50.0])
    ),  # fmt: skip
    st.builds(lambda s: f"SetGrpVelScale(0, {s});", st.sampled_from([50.0, 100.0, 150.0])),
    st.builds(lambda t: f"HaltGroup(0); Sleep({t}); ResumeGroup(0);", st.integers(0, 200)),
    st.builds(lambda t: f"Sleep({t}); StopGroup(0); Till(!IsGrpMoving(0));", st.integers(0, 400)),
    _wait(0),
    st.just(_print(0)),
)
space = st.one_of(
    st.builds(lambda x, y, z: f"LineAbs3D(1, {x}, {y}, {z});", coord, coord, coord),
    st.builds(
        lambda z, t: f"CircleAbs(1, c, n, {t}, e, v, CS_MCS, BM_BUFF, TM_NONE, 0); e[2] = {z};",
        coord,
        st.sampled_from([1, 2]),
    ),  # fmt: skip
    st.builds(
        lambda t: f"Till(!IsGrpMoving(1)); SetGrpSMTime(1, {t});", st.sampled_from([0.0, 20.0])
    ),  # fmt: skip
    _wait(1),
    st.just(_print(1)),
)


def _task_0(body: list[str]) -> str:
    lines = ["void main() {", "    StartTask(1);", "    Enable(0); Enable(1);",
             "    Till(IsEnabled(0) && IsEnabled(1));", "    SetupGroup(0, 0, 1);",
             "    SetGrpBufferMode(0, BM_LOOKAHEAD);"]  # fmt: skip
    lines += [f"    {s}" for s in body]
    lines += ["    Till(IsGrpInPos(0));", f"    {_print(0)}", "}"]
    return "\n".join(lines) + "\n"


def _task_1(body: list[str]) -> str:
    lines = ["double c[3] = {0, 20, 0};", "double n[3] = {0, 0, 1};",
             "double e[6] = {0, 0, 10, 0, 0, 0};", "double v[4] = {100, 2000, 2000, 20};",
             "void main() {", "    Enable(2); Enable(3); Enable(4);",
             "    Till(IsEnabled(2) && IsEnabled(3) && IsEnabled(4));",
             "    SetupGroup(1, 2, 3, 4);", "    LineAbs3D(1, 0, 0, 0);"]  # fmt: skip
    lines += [f"    {s}" for s in body]
    lines += ["    Till(IsGrpInPos(1));", f"    {_print(1)}", "}"]
    return "\n".join(lines) + "\n"


axis_table = st.fixed_dictionaries({
    "counts_per_unit": st.sampled_from([10000.0, 1000.0, 364.0888]),
    "max_pos_err": st.sampled_from([10.0, 0.8]),
    "delay": st.sampled_from([0, 1, 3]),
})  # fmt: skip
machine = st.tuples(st.sampled_from([1.0, 0.5, 2.0]), st.lists(axis_table, min_size=5,
                                                             max_size=5))  # fmt: skip


@PROFILE
@given(st.lists(plane, min_size=1, max_size=10), st.lists(space, max_size=6))
def test_random_group_programs_give_the_same_run(tmp_path_factory, body_0, body_1):
    tmp = tmp_path_factory.mktemp("groups")
    sources = [_task_0(body_0), _task_1(body_1)]
    assert outcome(tmp, sources, True) == outcome(tmp, sources, False)


@PROFILE
@given(machine, st.lists(plane, min_size=1, max_size=8), st.lists(space, max_size=5))
def test_random_group_machines_give_the_same_run(tmp_path_factory, spec, body_0, body_1):
    tmp = tmp_path_factory.mktemp("groups_machine")
    machine = machine_file(tmp, spec, 5)
    sources = [_task_0(body_0), _task_1(body_1)]
    assert outcome(tmp, sources, True, machine) == outcome(tmp, sources, False, machine)
