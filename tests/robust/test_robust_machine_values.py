"""Machine-file values beyond what the simulation can use are exit 3, naming key,
value and range (they used to pass validation and overflow later: exit 4)."""

from __future__ import annotations

import pytest

PROGRAM = """void main() {
    Enable(0);
    while (!IsEnabled(0)) Sleep(1);
    MoveAbs(0, 10.0);
    Sleep(20);
}
"""


def run(cli, axis_table: str):
    return cli(
        "run", "--until", "0.05", "--machine", "m.toml", "a.hmpl",
        m__toml="[[axis]]\n" + axis_table + "\n", a__hmpl=PROGRAM,
    )  # fmt: skip


@pytest.mark.parametrize(
    ("table", "message"),
    [
        (
            "counts_per_unit = 1e308",
            "2:1: error: [[axis]] 0: counts_per_unit = 1e+308: "
            "must be in 0.001 <= counts_per_unit <= 1e+09",
        ),
        (
            "drive = { mechanics = 5 }",
            "2:11: error: [[axis]] 0: drive.mechanics = 5: must be a table",
        ),
        (
            'drive = { mechanics = { model = "servo", bandwidth = 1e300 } }',
            "2:42: error: [[axis]] 0: mechanics 'servo': bandwidth = 1e+300 is not a finite "
            "number > 0 and <= 10000",
        ),
        (
            "index_spacing = 1e-300",
            "2:1: error: [[axis]] 0: index_spacing = 1e-300 at counts_per_unit = 10000 is "
            "1e-296 counts: index pulses must be at least 1 count apart",
        ),
        (
            "counts_per_unit = 0.01",
            "2:1: error: [[axis]] 0: index_spacing = 10 (the default) at counts_per_unit = 0.01 "
            "is 0.1 counts: index pulses must be at least 1 count apart",
        ),
        (
            'drive = { mechanics = { model = "ideal", delay_cycles = 100000000 } }',
            "2:42: error: [[axis]] 0: mechanics 'ideal': delay_cycles = 100000000 is not an "
            "integer >= 0 and <= 10000",
        ),
        (
            "max_vel = 1e13",
            "2:1: error: [[axis]] 0: max_vel = 10000000000000.0: must be in 1e-06 <= max_vel <= 1e+12",
        ),
        (
            "sw_left = -1e10",
            "2:1: error: [[axis]] 0: sw_left = -10000000000.0: must be in -1e+09 <= sw_left <= 1e+09",
        ),
        (
            'drive = { mechanics = { model = "servo", inertia = 1e-300 } }',
            "inertia = 1e-300 is not a finite number >= 1e-09 and <= 1e+06",
        ),
        (
            'drive = { mechanics = { model = "servo", damping = 1e-300 } }',
            "damping = 1e-300 is not a finite number >= 0.01 and <= 100",
        ),
    ],
)
def test_out_of_range_values_are_exit_3_naming_key_value_and_range(cli, table, message):
    r = run(cli, table)
    assert r.code == 3
    assert r.stderr.startswith("m.toml:") and message in r.stderr, r.stderr


@pytest.mark.parametrize(
    "table",
    [
        "counts_per_unit = 1e9",
        "counts_per_unit = 0.1",
        "max_vel = 1e12\nmax_acc = 1e12\nmax_dec = 1e12",
        "sw_left = -1e9\nsw_right = 1e9\nhw_left = -1e9\nhw_right = 1e9",
        'drive = { mechanics = { model = "ideal", delay_cycles = 10000 } }',
        'drive = { mechanics = { model = "servo", bandwidth = 10000, damping = 0.01, '
        "inertia = 1e6, tuned_inertia = 1e-9, friction = 1e6 } }",
    ],
)
def test_the_ends_of_the_ranges_run(cli, table):
    assert run(cli, table).code == 0
