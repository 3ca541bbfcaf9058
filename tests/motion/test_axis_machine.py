"""Machine files with axes: [[axis]] tables, `axes = N`, the built-in machine, bad values."""

from __future__ import annotations

import subprocess
import sys

import pytest

from motionvm.drives.mechanics import ServoMechanics
from motionvm.sim.controller import Controller
from motionvm.sim.machine import DEFAULT_MACHINE, MachineConfig, MachineFileError, load_machine


def write(tmp_path, text: str):
    p = tmp_path / "m.toml"
    p.write_text(text)
    return p


def test_the_built_in_machine_has_eight_default_axes():
    ctl = Controller()
    assert len(ctl.axes) == 8 and len(DEFAULT_MACHINE.axes) == 8
    a = ctl.axes[0]
    assert (a.pg.v_max, a.pg.a_max, a.pg.d_max, a.kill_dec) == (1000.0, 10000.0, 10000.0, 100000.0)
    assert (a.sw_left, a.sw_right, a.cpu) == (-1000.0, 1000.0, 10000.0)
    s = a.drive.sensors
    assert (s.negative_limit, s.positive_limit) == (-1050 * 10000.0, 1050 * 10000.0)
    assert (s.home_low, s.home_high, s.index_spacing) == (0.0, 5 * 10000.0, 10 * 10000.0)
    assert a.drive.mechanics.delay_cycles == 1


def test_axis_tables_and_the_axes_shorthand(tmp_path):
    m = load_machine(
        write(
            tmp_path,
            """
axes = 3
[controller]
cycle_time_ms = 0.5

[[axis]]
type = "rotary"
counts_per_unit = 364.0
max_vel = 720.0
drive = { enable_cycles = 9, mechanics = { model = "servo", bandwidth = 40.0 } }
""",
        )
    )
    assert len(m.axes) == 3 and m.cycle_time == 0.0005
    ctl = Controller(m.cycle_time, machine=m)
    a0, a1 = ctl.axes[0], ctl.axes[1]
    assert a0.rotary and a0.cpu == 364.0 and a0.pg.v_max == 720.0
    assert isinstance(a0.drive.mechanics, ServoMechanics) and a0.drive.enable_cycles == 9
    assert a0.drive.sensors.positive_limit is None  # rotary: no limit switches by default
    assert not a1.rotary and a1.pg.v_max == 1000.0 and a1.dt == 0.0005


def test_axis_tables_alone_give_the_number_of_axes(tmp_path):
    m = load_machine(write(tmp_path, "[[axis]]\n[[axis]]\nhw_left = false\n"))
    assert len(m.axes) == 2 and m.axes[1].hw_left is None


def test_axes_zero_is_a_machine_without_axes(tmp_path):
    assert load_machine(write(tmp_path, "axes = 0\n")).axes == ()


@pytest.mark.parametrize(
    ("text", "place", "words"),
    [
        ("[[axis]]\nmax_vel = 0\n", "2:1", ["max_vel = 0: must be in 1e-06 <= max_vel <= 1e+12"]),
        ('[[axis]]\n\n[[axis]]\ntype = "spiral"\n', "4:1", ["[[axis]] 1", "type"]),
        ("[[axis]]\nspeed = 3\n", "2:1", ["unknown key 'speed'"]),
        ("[[axis]]\nsw_left = 5.0\nsw_right = -5.0\n", "3:1", ["sw_right"]),
        ("axes = 1\n[[axis]]\n[[axis]]\n", "1:1", ["axes = 1", "2 [[axis]]"]),
        ("axes = 65\n", "1:1", ["axes = 65"]),
        ('[[axis]]\ndrive = { mechanics = { model = "warp" } }\n', "2:25", ["model = 'warp'"]),
        ("[[axis]]\ndrive = { positive_limit = 3 }\n", "2:11", ["hw_left, hw_right"]),
        (
            "[[axis]]\nsmooth_time_ms = 600\n",
            "2:1",
            ["smooth_time_ms = 600: must be in 0 <= smooth_time_ms <= 500"],
        ),
    ],
)
def test_bad_axis_values_name_file_line_and_key(tmp_path, text, place, words):
    p = write(tmp_path, text)
    with pytest.raises(MachineFileError) as exc:
        load_machine(p)
    msg = str(exc.value)
    assert msg.startswith(f"{p}:{place}: error: "), msg
    for w in words:
        assert w in msg


def test_machine_config_stays_backward_compatible():
    m = MachineConfig(cycle_time=0.002, task_slice=10)
    assert (m.cycle_time, m.task_slice, m.data_dir, m.path, len(m.axes)) == (
        0.002,
        10,
        None,
        None,
        8,
    )


def test_the_cli_reports_a_bad_axis_with_exit_code_3(tmp_path):
    p = write(tmp_path, "[[axis]]\nkill_dec = -1\n")
    prog = tmp_path / "p.hmpl"
    prog.write_text("void main() { }\n")
    r = subprocess.run([sys.executable, "-m", "motionvm", "run", "--machine", str(p), str(prog)],
                       check=False, capture_output=True, text=True, timeout=60)  # fmt: skip
    assert r.returncode == 3
    assert f"{p}:2:1: error:" in r.stderr and "kill_dec" in r.stderr
