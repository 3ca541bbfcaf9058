"""Scope channels of PDL drives (machine and standalone runs), GDL refusal, SetHMIScope gating."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.lang.pdl.drive_rt import Drive
from motionvm.lang.pdl.drive_scope import PdlDriveSource
from motionvm.lang.pdl.program import compile_pdl
from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, ChannelRegistry, ScopeError, ScopeRecorder
from motionvm.source.diagnostics import DiagnosticSink

MOVER = """\
#long p;
#long tab[3];
#task/0;
X_trg=20000;
till(~x_run);
p=x_ref_pos;
tab[1]=7;
halt;
"""

COUNTER = """\
#long n;
#task/0;
loop(4) do
  n++;
  sleep 1;
end;
halt;
"""

MACHINE = """\
axes = 3

[[axis]]

[[axis]]
max_vel = 100.0
max_acc = 10000.0
pdl = "mover.pdl"

[[axis]]
pdl = "counter.pdl"
"""


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


def run_cli(*argv) -> int:
    return main(["run", *map(str, argv)])


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    rows = list(csv.reader(path.read_text().splitlines()))
    return rows[0], rows[1:]


@pytest.fixture
def machine(tmp_path: Path) -> Path:
    write(tmp_path, "mover.pdl", MOVER)
    write(tmp_path, "counter.pdl", COUNTER)
    return write(tmp_path, "m.toml", MACHINE)


def drive_of(tmp_path: Path, text: str) -> Drive:
    sink = DiagnosticSink()
    program = compile_pdl(str(write(tmp_path, "d.pdl", text)), sink=sink)
    assert program is not None, sink.items
    return Drive(program)


# ---------------------------------------------------------------- the source


def test_drive_channels_units_and_values(tmp_path):
    drive = drive_of(tmp_path, MOVER)
    reg = ChannelRegistry([PdlDriveSource({1: drive})])
    chans = {
        c.name: c
        for c in reg.resolve_all(
            [
                "drive1.x_ref_pos",
                "drive1.X_vel_max",
                "drive1.x_acc",  # any case, as the drive's compiler reads names
                "drive1.fclk",
                "drive1.x_run",
                "drive1.ref_pos[0]",
                "drive1.p",
                "drive1.tab[1]",
                "drive1.IN3",
            ]
        )
    }
    units = {n: c.unit for n, c in chans.items()}
    assert units == {
        "drive1.x_ref_pos": "count",
        "drive1.X_vel_max": "count/s",
        "drive1.x_acc": "count/s²",
        "drive1.fclk": RAW_UNIT,
        "drive1.x_run": BIT_UNIT,
        "drive1.ref_pos[0]": "count",
        "drive1.p": RAW_UNIT,
        "drive1.tab[1]": RAW_UNIT,
        "drive1.IN3": BIT_UNIT,
    }
    drive.run()
    got = {n: c.getter() for n, c in chans.items()}
    assert got["drive1.x_ref_pos"] == got["drive1.p"] == 20000
    assert got["drive1.ref_pos[0]"] == 20000.0
    assert got["drive1.tab[1]"] == 7
    assert got["drive1.x_run"] == 0
    assert got["drive1.fclk"] == drive.fclk > 0
    drive.set_input("IN3", 1)
    assert chans["drive1.IN3"].getter() == 1


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("drive3.x_ref_pos", "no PDL drive 3 (PDL drives: drive1"),
        ("drive1.ref_pos", "is an array of 4; record one element, e.g. 'drive1.ref_pos[0]'"),
        ("drive1.ref_pos[4]", "index 4 is out of range for ref_pos[4] (0..3)"),
        ("drive1.tab[3]", "index 3 is out of range for tab[3]"),
        ("drive1.x_run[1]", "state 'x_run' is one bit"),
        ("drive1.x_ref_po", "did you mean drive1.x_ref_pos"),
        ("drive1.zzzz", "drive channels are a PDL system variable, state or global"),
    ],
)
def test_bad_drive_channels(tmp_path, name, message):
    reg = ChannelRegistry([PdlDriveSource({1: drive_of(tmp_path, MOVER)})])
    with pytest.raises(ScopeError, match=None) as info:
        reg.resolve(name)
    assert message in str(info.value)


def test_drive_channel_without_drives_says_what_is_needed():
    with pytest.raises(ScopeError, match="need a PDL program on axis N's drive"):
        ChannelRegistry().resolve("drive1.x_ref_pos")


def test_bare_names_belong_to_the_standalone_drive(tmp_path):
    drive = drive_of(tmp_path, MOVER)
    reg = ChannelRegistry([PdlDriveSource({0: drive}, bare=0)])
    assert reg.resolve("x_ref_pos").unit == "count"
    assert reg.resolve("p").getter() == 0
    with pytest.raises(ScopeError, match="did you mean x_ref_pos"):
        reg.resolve("x_ref_po")


# ---------------------------------------------------------------- machine runs


def test_machine_run_records_drive_channels(machine, tmp_path, capsys):
    out = tmp_path / "r.csv"
    channels = "drive1.x_ref_pos,drive1.X_trg,drive1.x_run,drive1.p,drive2.n,drive2.fclk"
    assert run_cli("--machine", machine, "--scope", channels, "--scope-out", out) == 0
    header, rows = read_csv(out)
    assert header == ["time", *channels.split(",")]
    assert rows[0][0] == "0.0" and rows[0][1:3] == ["0", "0"]  # no phase has run at 0 ms
    assert rows[1][0] == "0.001" and rows[1][2] == "20000"
    assert 0 < int(rows[1][1]) < 20000  # 15 phases into the move at 1 ms
    pos = [int(r[1]) for r in rows]
    assert pos == sorted(pos) and pos[-1] == 20000
    assert rows[-1][3:5] == ["0", "20000"]
    # drive 2 sleeps 1 ms (15 phases) per count: the same in every cycle as standalone
    assert [r[5] for r in rows[:6]] == ["0", "1", "2", "3", "4", "4"]
    assert [r[6] for r in rows[:3]] == ["0", "15", "30"]


def test_machine_run_bad_drive_channel_is_exit_3(machine, tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert run_cli("--machine", machine, "--scope", "drive0.x_ref_pos", "--scope-out", out) == 3
    assert "no PDL drive 0 (PDL drives: drive1, drive2" in capsys.readouterr().err
    assert not out.exists()


# ---------------------------------------------------------------- standalone PDL runs


COUNTER_CSV = """\
time,n,drive0.fclk
0.0,0,0
0.001,1,15
0.002,2,30
0.003,3,45
0.004,4,60
0.005,4,70
"""


def test_standalone_pdl_samples_each_ms(tmp_path, capsys):
    prog = write(tmp_path, "c.pdl", COUNTER)
    out = tmp_path / "c.csv"
    assert run_cli(prog, "--scope", "n,drive0.fclk", "--scope-out", out) == 0
    # the last slice ends when the drive goes idle (the 'halt' after the last sleep)
    assert out.read_text() == COUNTER_CSV


def test_standalone_pdl_matches_the_machine_run(machine, tmp_path, capsys):
    mach, alone = tmp_path / "m.csv", tmp_path / "a.csv"
    assert run_cli("--machine", machine, "--scope", "drive2.n", "--scope-out", mach) == 0
    assert run_cli(tmp_path / "counter.pdl", "--scope", "n", "--scope-out", alone) == 0
    _, m_rows = read_csv(mach)
    _, a_rows = read_csv(alone)
    assert a_rows == m_rows[: len(a_rows)]


def test_standalone_pdl_until_and_every(tmp_path, capsys):
    prog = write(tmp_path, "m.pdl", MOVER)
    out = tmp_path / "m.csv"
    argv = ["--scope", "x_ref_pos", "--scope-out", out, "--until", "0.0105"]
    assert run_cli(prog, *argv, "--scope-every", "5") == 0
    header, rows = read_csv(out)
    assert [r[0] for r in rows] == ["0.0", "0.005", "0.01"]


def test_standalone_pdl_vcd(tmp_path, capsys):
    prog = write(tmp_path, "c.pdl", COUNTER)
    out = tmp_path / "c.vcd"
    assert run_cli(prog, "--scope", "drive0.n,drive0.x_run", "--scope-out", out) == 0
    text = out.read_text()
    assert "$timescale 1 us $end" in text
    assert "$scope module drive0 $end" in text and "$var wire 1" in text
    assert "#3000\n" in text


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--scope", "nn", "--scope-out", "{out}"], "unknown scope channel 'nn'; did you mean n"),
        (["--scope", "n"], "--scope needs --scope-out"),
        (["--scope", "n", "--scope-out", "{dir}/x.txt"], "unknown file type"),
    ],
)
def test_standalone_pdl_bad_scope_is_exit_3(tmp_path, capsys, argv, message):
    prog = write(tmp_path, "c.pdl", COUNTER)
    out = tmp_path / "c.csv"
    argv = [a.format(out=out, dir=tmp_path) for a in argv]
    assert run_cli(prog, *argv) == 3
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_recorder_without_controller():
    values = iter(range(10))
    from motionvm.sim.scope import Channel

    rec = ScopeRecorder([Channel("v", RAW_UNIT, lambda: next(values))], 0.001, every=2)
    for k in range(5):
        rec.sample(k)
    assert rec.cycles == [0, 2, 4] and rec.columns == [[0, 1, 2]]
    assert not rec.hmi_gated


# ---------------------------------------------------------------- GDL


def test_gdl_states_are_scope_channels_beside_the_axes(tmp_path, capsys):
    """A GDL run records `OBJECT.STATE` channels on the same recorder as the axes."""
    gdl = Path(__file__).parents[2] / "examples" / "02_gdl_packer.gdl"
    scenario = gdl.with_suffix(".toml")
    out = tmp_path / "g.csv"
    argv = ["--scenario", scenario, "--scope", "cooling_fan.VALUE,axis0.ref_pos"]
    assert run_cli(gdl, *argv, "--scope-out", out) == 0
    header, rows = read_csv(out)
    assert header == ["time", "cooling_fan.VALUE", "axis0.ref_pos"]
    fan = [float(r[1]) for r in rows]
    assert fan[0] == 0.0 and {500.0, 750.0, 1000.0} <= set(fan)


# ---------------------------------------------------------------- SetHMIScope


HMI = """\
void main()
{
    int i;
    for (i = 0; i < 10; i++) {
        if (i == %d) SetHMIScope(1);
        if (i == %d) SetHMIScope(0);
        system_dtest0 = i;
        Sleep(1);
    }
}
"""


def run_hmi(tmp_path: Path, on: int, off: int) -> list[list[str]]:
    prog = write(tmp_path, "h.hmpl", HMI % (on, off))
    out = tmp_path / "h.csv"
    assert run_cli(prog, "--scope", "system_dtest0", "--scope-out", out) == 0
    return read_csv(out)[1]


def test_set_hmi_scope_limits_the_recording(tmp_path, capsys):
    assert run_hmi(tmp_path, 3, 6) == [["0.003", "3.0"], ["0.004", "4.0"], ["0.005", "5.0"]]


def test_set_hmi_scope_twice_records_both_windows(tmp_path, capsys):
    prog = write(
        tmp_path,
        "h.hmpl",
        """\
void main()
{
    int i;
    for (i = 0; i < 8; i++) {
        SetHMIScope(i == 1 || i == 2 || i == 5);
        system_dtest0 = i;
        Sleep(1);
    }
}
""",
    )
    out = tmp_path / "h.csv"
    assert run_cli(prog, "--scope", "system_dtest0", "--scope-out", out) == 0
    assert [r[1] for r in read_csv(out)[1]] == ["1.0", "2.0", "5.0"]


def test_without_set_hmi_scope_everything_is_recorded(tmp_path, capsys):
    rows = run_hmi(tmp_path, 99, 99)
    assert [r[1] for r in rows][:10] == [f"{i}.0" for i in range(10)]


def test_set_hmi_scope_never_on_gives_an_empty_recording_and_a_note(tmp_path, capsys):
    assert run_hmi(tmp_path, 99, 0) == []
    assert "the HMI scope was never on" in capsys.readouterr().err
