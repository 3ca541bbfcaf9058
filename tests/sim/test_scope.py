"""Scope recording: channels, sampling at the end of each cycle, .csv/.vcd/.png/.svg files, CLI."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from motionvm.api import Simulation
from motionvm.cli import main
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.scope import ScopeAxis
from motionvm.sim.controller import Controller
from motionvm.sim.scope import (
    ChannelRegistry,
    ScopeError,
    ScopeRecorder,
    ScopeRequest,
    parse_channel_list,
)
from motionvm.sim.scope_sources import AxisSource, registry_for
from motionvm.sim.scope_writers import write_csv

LOOP = """\
int count;
double table[4];
void main()
{
    int i;
    Print("start");
    for (i = 0; i < 5; i++) {
        system_dtest0 = i;
        system_ltest1 = i * 10;
        count = i;
        table[2] = i * 0.5;
        HIMC_GPO(3) = i % 2;
        Sleep(1);
    }
}
"""

LOOP_CSV = """\
time,system_timeInMs,system_dtest0,system_ltest1,count,table[2],gpo3
0.0,0,0.0,0,0,0.0,0
0.001,1,1.0,10,1,0.5,1
0.002,2,2.0,20,2,1.0,0
0.003,3,3.0,30,3,1.5,1
0.004,4,4.0,40,4,2.0,0
0.005,5,4.0,40,4,2.0,0
"""

LOOP_CHANNELS = "system_timeInMs,system_dtest0,system_ltest1,count,table[2],gpo3"


@pytest.fixture
def loop_file(tmp_path: Path) -> Path:
    p = tmp_path / "loop.hmpl"
    p.write_text(LOOP)
    return p


def run_cli(*argv) -> int:
    return main(["run", *map(str, argv)])


def recorded(
    source: str, channels: list[str], every: int = 1, until: float | None = None
) -> ScopeRecorder:
    sim = Simulation.from_source(source)
    rec = ScopeRecorder(
        registry_for(sim.controller, sim.runtime).resolve_all(channels),
        sim.controller.cycle_time,
        every,
    )
    rec.attach(sim.controller)
    sim.run(until)
    return rec


# ---------------------------------------------------------------- CSV and sampling


def test_csv_is_exact(loop_file, tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert run_cli("--scope", LOOP_CHANNELS, "--scope-out", out, loop_file) == 0
    assert out.read_text() == LOOP_CSV
    assert capsys.readouterr().out == "start\n"


def test_every_n_cycles(loop_file, tmp_path):
    out = tmp_path / "run.csv"
    assert (
        run_cli("--scope", "system_dtest0", "--scope-every", "2", "--scope-out", out, loop_file)
        == 0
    )
    assert out.read_text() == "time,system_dtest0\n0.0,0.0\n0.002,2.0\n0.004,4.0\n"


def test_full_precision_and_repeated_flags(tmp_path):
    prog = tmp_path / "p.hmpl"
    prog.write_text("void main() { system_dtest1 = 1.0 / 3.0; Sleep(1); }\n")
    out = tmp_path / "p.csv"
    assert (
        run_cli(
            "--scope",
            "system_dtest1",
            "--scope",
            " system_dtest1 ,system_fclk",
            "--scope-out",
            out,
            prog,
        )
        == 0
    )
    lines = out.read_text().splitlines()
    assert lines[0] == "time,system_dtest1,system_fclk"
    assert lines[1] == f"0.0,{1.0 / 3.0!r},0"
    assert lines[2] == f"0.001,{1.0 / 3.0!r},1"  # system_fclk counts controller cycles


def test_every_cycle_is_sampled_while_tasks_sleep():
    rec = recorded("void main() { Sleep(10); system_dtest0 = 1; }", ["system_dtest0"])
    assert rec.cycles == list(range(11))
    assert rec.columns[0] == [0.0] * 10 + [1.0]


def test_until_limits_the_recording():
    rec = recorded(
        "void main() { while (1) { system_ltest0++; Sleep(1); } }", ["system_ltest0"], until=0.004
    )
    assert rec.times == [0.0, 0.001, 0.002, 0.003]
    assert rec.columns[0] == [1, 2, 3, 4]


def test_end_cycle_runs_after_the_tasks_of_the_cycle():
    calls = []

    class Client(PassiveClient):
        def begin_cycle(self):
            calls.append(("begin", ctl.cycle))

        def end_cycle(self):
            calls.append(("end", ctl.cycle))

    class NoEnd(PassiveClient):
        pass

    ctl = Controller()
    ctl.clients += [Client(), NoEnd()]
    ctl.step()
    ctl.step()
    assert calls == [("begin", 0), ("end", 0), ("begin", 1), ("end", 1)]


def test_a_recorder_samples_every_cycle_a_jump_passes():
    src = """void main() {
    Enable(0); Till(IsEnabled(0)); Sleep(200); MoveAbs(0, 20.0); Sleep(300);
    Till(IsInPos(0)); Sleep(100); }"""
    channels = ["system_timeInMs", "system_fclk", "axis0.pos_fb", "axis0.ref_vel"]
    runs = []
    for skip in (True, False):
        sim = Simulation.from_source(src, skip=skip)
        rec = ScopeRecorder(registry_for(sim.controller, sim.runtime).resolve_all(channels),
                            sim.controller.cycle_time)  # fmt: skip
        rec.attach(sim.controller)
        sim.run()
        runs.append((rec.cycles, rec.columns, sim.controller.cycles_computed))
    (cycles, columns, computed), (cycles_stepped, columns_stepped, _) = runs
    assert cycles == cycles_stepped == list(range(len(cycles))) and columns == columns_stepped
    assert computed < 0.1 * len(cycles)  # the recorder did not stop the jumps


def test_a_recorder_of_every_nth_cycle_has_the_axes_coast_between_its_samples():
    """A jump stops only at the cycles an every-N recorder samples (`next_sample`): the
    axes are advanced in closed form between them, with the samples stepping gives."""
    src = """void main() {
    Enable(0); Till(IsEnabled(0)); MoveAbs(0, 300.0); Till(IsInPos(0));
    MoveAbs(0, -50.0); Sleep(700); Till(IsInPos(0)); Sleep(100); }"""
    channels = ["system_timeInMs", "axis0.pos_fb", "axis0.ref_vel", "axis0.pos_err"]
    runs = []
    for skip in (True, False):
        sim = Simulation.from_source(src, skip=skip)
        rec = ScopeRecorder(registry_for(sim.controller, sim.runtime).resolve_all(channels),
                            sim.controller.cycle_time, every=50)  # fmt: skip
        rec.attach(sim.controller)
        coasts = []
        coast = sim.controller.motion.coast
        sim.controller.motion.coast = lambda k, coasts=coasts, coast=coast: (
            coasts.append(k),
            coast(k),
        )[1]
        sim.run()
        runs.append((rec.cycles, rec.columns, sim.time, coasts))
    (cycles, columns, end, coasts), (cycles_stepped, columns_stepped, end_stepped, _) = runs
    assert cycles == cycles_stepped == list(range(0, cycles[-1] + 1, 50))
    assert columns == columns_stepped and end == end_stepped
    assert len(cycles) > 20 and max(coasts) > 40  # the axis coasted between the samples
    assert len(coasts) < len(cycles) * 3


# ---------------------------------------------------------------- channels


def test_globals_arrays_and_gpio():
    src = (
        "int n; double d[3]; int *p; int addr_taken; int *q = &addr_taken;\n"
        "void main() { n = 7; d[1] = 2.5; addr_taken = -3; Sleep(1); }\n"
    )
    sim = Simulation.from_source(src)
    reg = registry_for(sim.controller, sim.runtime)
    chans = reg.resolve_all(["n", "d[1]", "addr_taken", "system_mtest[9]", "gpi1", "himc_gpo_bits"])
    assert [c.unit for c in chans] == ["raw", "raw", "raw", "raw", "bool", "raw"]
    sim.set_input(1, True)
    sim.run()
    assert [c.getter() for c in chans] == [7, 2.5, -3, 0.0, 1, 0]
    assert reg.resolve("system_timeInMs").unit == "ms"


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("system_dtst0", "did you mean system_dtest0"),
        ("cuont", "did you mean count"),
        ("table", "is an array of 4; record one element, e.g. 'table[0]'"),
        ("table[4]", "index 4 is out of range for table[4] (0..3)"),
        ("count[1]", "'count' is not an array"),
        ("gpo9", "the controller has gpo1..gpo8"),
        ("nothing_like_it", "unknown scope channel 'nothing_like_it'"),
    ],
)
def test_bad_channels(name, message):
    sim = Simulation.from_source(LOOP)
    with pytest.raises(ScopeError) as err:
        registry_for(sim.controller, sim.runtime).resolve(name)
    assert message in str(err.value)


def test_bad_channel_stops_before_the_run(loop_file, tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert run_cli("--scope", "system_dtest0,cuont,gpo99", "--scope-out", out, loop_file) == 3
    cap = capsys.readouterr()
    assert cap.out == ""  # the program never ran
    assert "2 bad scope channels" in cap.err and "did you mean count" in cap.err
    assert not out.exists()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--scope", "count"], "--scope needs --scope-out"),
        (["--scope-out", "x.csv"], "--scope-out needs --scope"),
        (["--scope", "count", "--scope-out", "x.txt"], "unknown file type '.txt'"),
        (["--scope", "count", "--scope-out", "no/such/dir/x.csv"], "does not exist"),
        (
            ["--scope", "count", "--scope-out", "x.csv", "--scope-every", "0"],
            "--scope-every must be",
        ),
    ],
)
def test_bad_scope_flags(loop_file, argv, message, capsys):
    assert run_cli(*argv, loop_file) == 3
    assert message in capsys.readouterr().err


def test_channel_list_parsing():
    assert parse_channel_list(["a, b", "b,c[2]", ",,"]) == ["a", "b", "c[2]"]
    assert ScopeRequest.from_options([], [], None) is None


# ---------------------------------------------------------------- axes (stand-in for motion/axis.py)


class StandInAxis(ScopeAxis):
    """The axis layer's interface as the scope uses it: variable(name), variable_names()."""

    def __init__(self, rotary: bool = False) -> None:
        self.rotary = rotary
        self.values = {
            "ref_pos": 0.0,
            "ref_vel": 0.0,
            "ref_acc": 0.0,
            "pos_fb": 0.0,
            "di_bit_HOME": 0,
        }

    def variable(self, name: str) -> float:
        return self.values[name]

    def variable_names(self) -> list[str]:
        return list(self.values)


class StandInMotion(PassiveClient):
    """Moves axis 0 by 1 mm per cycle, as the motion step of a cycle would."""

    def __init__(self, axis: StandInAxis) -> None:
        self.axis = axis

    def begin_cycle(self) -> None:
        self.axis.values["ref_pos"] += 1.0
        self.axis.values["di_bit_HOME"] = 1 if self.axis.values["ref_pos"] >= 3 else 0


class StandInController(Controller):
    """A controller whose axes are stand-ins, not the machine's."""

    axes = None  # an attribute in place of the property


def axis_controller() -> Controller:
    ctl = StandInController()
    ctl.axes = [StandInAxis(), StandInAxis(rotary=True)]
    ctl.clients.append(StandInMotion(ctl.axes[0]))
    return ctl


def test_axis_channels_and_units():
    ctl = axis_controller()
    chans = registry_for(ctl).resolve_all(
        ["axis0.ref_pos", "axis0.ref_acc", "axis1.ref_vel", "axis0.di_bit_HOME"]
    )
    assert [c.unit for c in chans] == ["mm", "mm/s²", "deg/s", "bool"]
    rec = ScopeRecorder(chans, ctl.cycle_time)
    rec.attach(ctl)
    for _ in range(4):
        ctl.step()
    assert rec.columns[0] == [1.0, 2.0, 3.0, 4.0]  # the state after the cycle's motion
    assert rec.columns[3] == [0, 0, 1, 1]


def test_no_axes():
    with pytest.raises(ScopeError, match="this controller has no axes"):
        ChannelRegistry([AxisSource(SimpleNamespace(axes=None))]).resolve("axis0.ref_pos")


def test_axis_without_variable_names_offers_the_manuals_variables():
    class Minimal(ScopeAxis):
        def variable(self, name):
            return 1.5

    reg = ChannelRegistry([AxisSource(SimpleNamespace(axes=[Minimal()]))])
    assert reg.resolve("axis0.settlingtime").unit == "ms"
    assert reg.resolve("axis0.coe_vel_fb").getter() == 1.5
    with pytest.raises(ScopeError, match="did you mean axis0.vel_fb"):
        reg.resolve("axis0.velfb")


def test_axis_channels_of_a_real_move(tmp_path):
    prog = tmp_path / "move.hmpl"
    prog.write_text(
        "void main() { Enable(0); Till(IsEnabled(0)); MoveAbs(0, 20.0); Till(IsInPos(0)); }\n"
    )
    out = tmp_path / "move.csv"
    assert run_cli("--scope", "axis0.ref_pos,axis0.pos_fb", "--scope-out", out, prog) == 0
    rows = [line.split(",") for line in out.read_text().splitlines()]
    assert rows[0] == ["time", "axis0.ref_pos", "axis0.pos_fb"]
    ref_pos = [float(r[1]) for r in rows[1:]]
    assert ref_pos == sorted(ref_pos) and ref_pos[-1] == 20.0


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("axis0.refpos", "did you mean axis0.ref_pos"),
        ("axis2.ref_pos", "no axis 2 on this machine (axes: axis0..axis1)"),
        ("axis0.bogus_thing", "axis variables are: ref_pos, ref_vel"),
        ("axis_0.ref_pos", "did you mean axis0.ref_pos"),
    ],
)
def test_bad_axis_channels(name, message):
    with pytest.raises(ScopeError) as err:
        registry_for(axis_controller()).resolve(name)
    assert message in str(err.value)


def test_a_client_offers_its_own_sources():
    class Source:
        def resolve(self, name):
            return (lambda: 42.0, "mm") if name == "drive0.torque" else None

        def channel_names(self):
            return ["drive0.torque"]

    class Client(PassiveClient):
        def scope_sources(self):
            return [Source()]

    ctl = Controller()
    reg = registry_for(ctl, Client())
    assert reg.resolve("drive0.torque").getter() == 42.0
    with pytest.raises(ScopeError, match="did you mean drive0.torque"):
        reg.resolve("drive0.torq")
    assert isinstance(reg, ChannelRegistry)


# ---------------------------------------------------------------- VCD


def test_vcd_structure_and_changes_only(tmp_path):
    ctl = axis_controller()
    chans = registry_for(ctl).resolve_all(["axis0.ref_pos", "axis0.di_bit_HOME", "axis1.ref_vel"])
    rec = ScopeRecorder(chans, ctl.cycle_time)
    rec.attach(ctl)
    for _ in range(4):
        ctl.step()
    out = tmp_path / "run.vcd"
    rec.save(out)
    text = out.read_text()
    head, _, body = text.partition("$enddefinitions $end\n")
    assert "$timescale 1 us $end" in head
    assert head.index("$scope module motionvm $end") < head.index("$scope module axis0 $end")
    assert "$var real 64 ! ref_pos $end" in head
    assert '$var wire 1 " di_bit_HOME $end' in head
    assert "$scope module axis1 $end\n$var real 64 # ref_vel $end\n$upscope $end" in head
    assert head.count("$scope") == head.count("$upscope") == 3
    # axis1.ref_vel never changes: it appears once, in $dumpvars
    assert body == (
        '#0\n$dumpvars\nr1.0 !\n0"\nr0.0 #\n$end\n#1000\nr2.0 !\n#2000\nr3.0 !\n1"\n#3000\nr4.0 !\n'
    )


def test_vcd_of_a_program(loop_file, tmp_path):
    out = tmp_path / "run.vcd"
    assert run_cli("--scope", "count,gpo3", "--scope-out", out, loop_file) == 0
    body = out.read_text().partition("$enddefinitions $end\n")[2]
    assert body.startswith('#0\n$dumpvars\nr0 !\n0"\n$end\n#1000\nr1 !\n1"\n')
    assert "#5000" not in body  # nothing changed in the last cycle


# ---------------------------------------------------------------- plots


@pytest.mark.parametrize("suffix", [".png", ".svg"])
def test_plot_files(loop_file, tmp_path, suffix):
    pytest.importorskip("matplotlib")
    out = tmp_path / f"run{suffix}"
    assert run_cli("--scope", LOOP_CHANNELS, "--scope-out", out, loop_file) == 0
    data = out.read_bytes()
    if suffix == ".png":
        assert data.startswith(b"\x89PNG\r\n\x1a\n")
    else:
        assert b"<svg" in data
        first = data
        assert run_cli("--scope", LOOP_CHANNELS, "--scope-out", out, loop_file) == 0
        assert out.read_bytes() == first  # deterministic: no dates, fixed ids


def test_plot_without_matplotlib(loop_file, tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # makes `import matplotlib` fail
    out = tmp_path / "run.png"
    assert run_cli("--scope", "count", "--scope-out", out, loop_file) == 3
    cap = capsys.readouterr()
    assert "pip install 'motionvm[plot]'" in cap.err
    assert cap.out == "" and not out.exists()


# ---------------------------------------------------------------- atomic writes


def test_failed_write_leaves_no_partial_file(tmp_path):
    rec = recorded(LOOP, ["count"])
    rec._columns[0][3] = "not a number"  # makes the writer fail half way (an unwritten sample)
    out = tmp_path / "run.csv"
    out.write_text("previous\n")
    with pytest.raises(ValueError):
        write_csv(out, rec)
    assert out.read_text() == "previous\n"
    assert os.listdir(tmp_path) == ["run.csv"]  # the temporary file is gone


def test_write_replaces_and_keeps_ordinary_permissions(tmp_path):
    rec = recorded(LOOP, ["count"])
    out = tmp_path / "run.csv"
    out.write_text("previous\n")
    rec.save(out)
    assert out.read_text().startswith("time,count\n")
    mask = os.umask(0)
    os.umask(mask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~mask
