"""Plant wiring and sensors of the machine file: delays exact to the cycle (stepping and
skipping alike), output inversion on the pin, analog gain and offset, position sensors,
and every kind of bad key reported at its place."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.session import SessionError
from motionvm.sim.machine import MachineFileError, load_machine

TIMING = """void main() {
    int t0;
    Sleep(3);
    SetGPO(3, 1);
    t0 = system_fclk;
    while (!GetGPI(4)) {}
    Print("on after %d cycles", system_fclk - t0);
    SetGPO(3, 0);
    t0 = system_fclk;
    Till(!GetGPI(4));
    Print("off after %d cycles", system_fclk - t0);
}"""


@pytest.mark.parametrize("skip", [True, False])
@pytest.mark.parametrize(
    ("cycle_ms", "delay_ms", "cycles"),
    [(1.0, 0, 1), (1.0, 5, 6), (1.0, 4.5, 6), (0.5, 5, 11), (2.0, 5, 4), (1.0, 1000, 1001)],
)
def test_a_wire_delivers_exactly_one_cycle_plus_its_delay_later(
    write_file, skip, cycle_ms, delay_ms, cycles
):
    m = write_file(
        "m.toml",
        f"axes = 1\n[controller]\ncycle_time_ms = {cycle_ms}\n"
        f'[[wire]]\nfrom = "gpo3"\nto = "gpi4"\ndelay_ms = {delay_ms}\n',
    )
    sim = Simulation.from_source(TIMING, machine=m, skip=skip)
    sim.run(until=10.0)
    assert sim.messages == [f"on after {cycles} cycles", f"off after {cycles} cycles"]


def test_a_delayed_change_is_not_jumped_over_while_every_task_sleeps(write_file):
    m = write_file("m.toml", 'axes = 1\n[[wire]]\nfrom = "gpo1"\nto = "gpi2"\ndelay_ms = 250\n')
    sim = Simulation.from_source(
        'void main() { SetGPO(1, 1); Sleep(1000); Print("%d", GetGPI(2)); }', machine=m
    )
    rec = sim.scope(["gpi2"])
    sim.run()
    assert sim.messages == ["1"]
    times = rec.as_dict()["time"]
    first_on = times[rec.as_dict()["gpi2"].index(1)]
    assert first_on == pytest.approx(0.251)


def test_output_inversion_acts_on_the_pin_a_wire_carries(write_file):
    m = write_file("m.toml", 'axes = 1\n[[wire]]\nfrom = "gpo2"\nto = "gpi1"\n')
    sim = Simulation.from_source(
        """void main() {
            SetGPOInvert(2, 1); Sleep(2);
            Print("%d %d", GetGPO(2), GetGPI(1));
            SetGPO(2, 1); Sleep(2);
            Print("%d %d", GetGPO(2), GetGPI(1));
        }""",
        machine=m,
    )
    sim.run()
    assert sim.messages == ["0 1", "1 0"]


def test_slave_wires_and_analog_gain_offset(write_file):
    m = write_file(
        "m.toml",
        """axes = 1
[[slave]]
kind = "digital"
inputs = 2
outputs = 2
[[slave]]
kind = "analog"
ai = 1
ao = 1
[[wire]]
from = "slv1.do2"
to = "gpi5"
[[wire]]
from = "gpo6"
to = "slv1.di1"
[[wire]]
from = "slv2.ao1"
to = "slv2.ai1"
gain = 0.5
offset = 100
""",
    )
    sim = Simulation.from_source(
        """void main() {
            SetSlvGPO(1, 2, 1); SetGPO(6, 1); SetSlvAORaw(2, 1, 1000); Sleep(2);
            Print("%d %d %d", GetGPI(5), GetSlvGPI(1, 1), GetSlvAIRaw(2, 1));
        }""",
        machine=m,
    )
    sim.run()
    assert sim.messages == ["1 1 600"]


def test_an_analog_wire_scales_signed_values_with_their_sign(write_file):
    """Gain and offset act on the raw values as programs read them: two's complement on
    an HMPL_DAC_SIGNED channel. The result is clamped to what the input's type holds."""
    m = write_file(
        "m.toml",
        """axes = 1
[[slave]]
kind = "analog"
ai = 2
ao = 2
[[wire]]
from = "slv1.ao1"
to = "slv1.ai1"
gain = 2
[[wire]]
from = "slv1.ao2"
to = "slv1.ai2"
""",
    )
    sim = Simulation.from_source(
        """void main() {
            int signed10 = HMPL_DAC_SIGNED | HMPL_DAC_N10_P10;
            SetSlvAOType(1, 1, signed10); SetSlvAIType(1, 1, signed10);
            SetSlvAOType(1, 2, signed10); SetSlvAIType(1, 2, HMPL_DAC_N10_P10);
            SetSlvAO(1, 1, 2.5); Sleep(2);
            Print("%.3f %d", GetSlvAI(1, 1), GetSlvAIRaw(1, 1));
            SetSlvAO(1, 1, -1.25); Sleep(2);
            Print("%.3f %d", GetSlvAI(1, 1), GetSlvAIRaw(1, 1));
            SetSlvAO(1, 1, -7.5); SetSlvAO(1, 2, -5); Sleep(2);
            Print("%.3f %d / %d", GetSlvAI(1, 1), GetSlvAIRaw(1, 1), GetSlvAIRaw(1, 2));
            SetSlvAO(1, 1, 7.5); Sleep(2);
            Print("%.3f %d", GetSlvAI(1, 1), GetSlvAIRaw(1, 1));
        }""",
        machine=m,
    )
    sim.run()
    assert sim.messages == [
        "5.000 16384",
        "-2.500 -8192",
        "-10.000 -32768 / 0",  # clamped: signed low end; unsigned input: 0 (its low end)
        "10.000 32767",
    ]


def test_a_sensor_follows_the_axis_feedback(write_file):
    m = write_file(
        "m.toml",
        """axes = 1
[[sensor]]
input = "gpi2"
axis = 0
from = 10.0
to = 20.0
[[sensor]]
input = "gpi3"
axis = 0
from = 10.0
to = 20.0
invert = true
""",
    )
    sim = Simulation.from_source(
        """void main() {
            Enable(0); Till(IsEnabled(0));
            Print("%d %d", GetGPI(2), GetGPI(3));
            MoveAbs(0, 15); Till(IsInPos(0)); Print("%d %d", GetGPI(2), GetGPI(3));
            MoveAbs(0, 30); Till(GetPosFb(0) > 20.0001); Sleep(1); Print("%d", GetGPI(2));
        }""",
        machine=m,
    )
    rec = sim.scope(["axis0.pos_fb", "gpi2"])
    sim.run()
    assert sim.messages == ["0 1", "1 0", "0"]
    data = rec.as_dict()
    for k in range(1, len(data["time"])):  # the input of cycle k is the position after k - 1
        assert data["gpi2"][k] == (10.0 <= data["axis0.pos_fb"][k - 1] <= 20.0)


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ('[[wire]]\nfrom = "gpo3"\nto = "gpi4"\ncolour = 1\n', "4:1", "unknown key 'colour'"),
        ('[[wire]]\nfrom = "gpi3"\nto = "gpi4"\n', "2:1", "from = 'gpi3' is an input"),
        ('[[wire]]\nfrom = "gpo3"\nto = "gpo4"\n', "3:1", "to = 'gpo4' is an output"),
        ('[[wire]]\nfrom = "gpo9"\nto = "gpi4"\n', "2:1", "the controller has gpo1..gpo8"),
        ('[[wire]]\nfrom = "slv0.do1"\nto = "gpi4"\n', "2:1", "slave 0 is the drive of axis 0"),
        ('[[wire]]\nfrom = "slv5.do1"\nto = "gpi4"\n', "2:1", "there is no slave 5"),
        ('[[wire]]\nfrom = "gpo3"\nto = "gpi4"\ndelay_ms = -1\n', "4:1", "delay_ms = -1"),
        (
            '[[wire]]\nfrom = "gpo3"\nto = "gpi4"\ngain = 2\n',
            "4:1",
            "gain applies to analog wires only",
        ),
        ('[[wire]]\nfrom = "gpo3"\n', "1:1", "missing 'to'"),
        (
            '[[wire]]\nfrom = "gpo3"\nto = "gpi4"\n[[wire]]\nfrom = "gpo2"\nto = "gpi4"\n',
            "6:1",
            "gpi4 is already driven by [[wire]] 0",
        ),
        (
            '[[wire]]\nfrom = "gpx"\nto = "gpi4"\n[[wire]]\nfrom = "gpo1"\nto = "gpi5"\n'
            '[[sensor]]\ninput = "gpi5"\naxis = 0\nfrom = 0\nto = 1\n',
            "8:1",
            "[[sensor]] 0: gpi5 is already driven by [[wire]] 1",
        ),
        (
            '[[wire]]\nfrom = "gpo1"\nto = "gpi5"\n[[wire]]\nfrom = "gpx"\nto = "gpi4"\n'
            '[[sensor]]\ninput = "gpi5"\naxis = 0\nfrom = 0\nto = 1\n',
            "8:1",
            "[[sensor]] 0: gpi5 is already driven by [[wire]] 0",
        ),
        ('[[sensor]]\ninput = "gpi1"\naxis = 3\nfrom = 0\nto = 1\n', "3:1", "axis = 3"),
        (
            '[[sensor]]\ninput = "gpi1"\naxis = 0\nfrom = 5\nto = 1\n',
            "5:1",
            "to = 1 is below from = 5",
        ),
        (
            '[[sensor]]\ninput = "gpi1"\naxis = 0\nfrom = 0\nto = 1\ninvert = 1\n',
            "6:1",
            "invert = 1",
        ),
        ('[[slave]]\nkind = "servo"\n', "2:1", "kind = 'servo'"),
        ('[[slave]]\nkind = "digital"\nai = 2\n', "3:1", "unknown key 'ai' for a digital slave"),
        ('[[slave]]\nkind = "analog"\nbits = 64\n', "3:1", "bits = 64"),
        ("[io]\ninputs = 0\n", "2:1", "inputs = 0"),
        ("[io]\nestop_input = 9\n", "2:1", "estop_input = 9"),
        ("[io]\nleds = 2\n", "2:1", "unknown key 'leds' in [io]"),
    ],
)
def test_bad_io_tables_are_machine_file_errors(write_file, error_at, text, where, message):
    path = write_file("m.toml", "axes = 1\n" + text)
    with pytest.raises(MachineFileError) as err:
        load_machine(path)
    line, col = where.split(":")
    error_at(err.value.messages, path, f"{int(line) + 1}:{col}", message)


def test_the_cli_reports_a_bad_wire_with_exit_3(tmp_path, write_file, capsys):
    from motionvm.cli import main

    m = write_file("m.toml", 'axes = 1\n[[wire]]\nfrom = "gpo3"\nto = "slv1.di1"\n')
    (tmp_path / "p.hmpl").write_text("void main() { }\n")
    assert main(["run", "--machine", m, str(tmp_path / "p.hmpl")]) == 3
    assert "m.toml:4:1: error: [[wire]] 0: to = 'slv1.di1'" in capsys.readouterr().err


def test_a_session_error_for_the_api(write_file):
    m = write_file("m.toml", 'axes = 1\n[[sensor]]\ninput = "gpi1"\n')
    with pytest.raises(SessionError):
        Simulation.from_source("void main() { }", machine=m)


def test_the_run_lasts_until_a_change_has_gone_through_its_wire(write_file):
    m = write_file("m.toml", 'axes = 1\n[[wire]]\nfrom = "gpo1"\nto = "gpi2"\ndelay_ms = 50\n')
    sim = Simulation.from_source("void main() { SetGPO(1, 1); }", machine=m)
    result = sim.run()
    assert result.finished and sim.read("gpi2") == 1 and result.sim_time == pytest.approx(0.052)
    sim = Simulation.from_source("void main() { SetGPO(1, 1); }", machine=m)
    result = sim.run(until=0.02)
    assert [w.who for w in result.still_running] == ["wire gpo1 -> gpi2"]
