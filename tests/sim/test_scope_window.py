"""`--scope-window START:END` (CSV, VCD, plots) and `--scope-out -` (the CSV on stdout)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import motionvm
from motionvm.cli import main
from motionvm.sim.scope import Channel, ScopeError, ScopeRequest, ScopeWindow

LOOP = """\
void main()
{
    int i;
    Print("start");
    for (i = 0; i < 5; i++) {
        system_dtest0 = i;
        HIMC_GPO(3) = i % 2;
        Sleep(1);
    }
    Print("done");
}
"""


@pytest.fixture
def loop_file(tmp_path: Path) -> Path:
    p = tmp_path / "loop.hmpl"
    p.write_text(LOOP)
    return p


def run_cli(*argv) -> int:
    return main(["run", *map(str, argv)])


# ---------------------------------------------------------------- parsing


@pytest.mark.parametrize(
    ("text", "start", "end"),
    [
        ("0.1:0.25", 0.1, 0.25),
        (":2", None, 2.0),
        ("1.5:", 1.5, None),
        (":", None, None),
        ("150ms:300ms", 0.15, 0.3),
        ("200us:1ms", 0.0002, 0.001),
        (" 1.5s : 2 s ", 1.5, 2.0),
        ("1e-3:2e-3", 0.001, 0.002),
        ("0.2:0.2", 0.2, 0.2),
    ],
)
def test_window_parsing(text, start, end):
    w = ScopeWindow.parse(text)
    assert (w.start, w.end) == (pytest.approx(start), pytest.approx(end))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("0.1", "expected START:END in seconds"),
        ("a:b", "'a' is not a time"),
        ("1min:", "'1min' is not a time"),
        ("nan:", "'nan' is not a time"),
        ("1e999:", "'1e999' is not a time"),
        ("-1:2", "time -1 s is before the start"),
        ("2:1", "start 2 s is after end 1 s"),
        ("300ms:0.1", "start 0.3 s is after end 0.1 s"),
    ],
)
def test_bad_windows(text, message):
    with pytest.raises(ScopeError, match=message):
        ScopeWindow.parse(text)


def test_window_contains_both_ends():
    w = ScopeWindow(0.002, 0.004)
    assert [t in w for t in (0.001, 0.002, 0.003, 0.004, 0.005)] == [0, 1, 1, 1, 0]
    assert str(w) == "0.002:0.004" and str(ScopeWindow(None, 1.5)) == ":1.5"


def test_request_needs_scope_for_a_window():
    with pytest.raises(ScopeError, match="--scope-window needs --scope and --scope-out"):
        ScopeRequest.from_options([], [], None, "0:1")
    req = ScopeRequest.from_options(["count"], ["-"], None, "1:2")
    assert req.window == ScopeWindow(1.0, 2.0) and req.is_stdout(req.outputs[0])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--scope-window", "2:1"], "--scope-window '2:1': start 2 s is after end 1 s"),
        (["--scope-window", "abc"], "expected START:END"),
        (["--scope-out", "-"], "standard output can take one table only"),
    ],
)
def test_bad_window_or_stdout_is_exit_3(loop_file, tmp_path, capsys, argv, message):
    argv = ["--scope", "system_dtest0", "--scope-out", "-", *argv, loop_file]
    assert run_cli(*argv) == 3
    cap = capsys.readouterr()
    assert message in cap.err and cap.out == ""


# ---------------------------------------------------------------- files


def test_csv_window(loop_file, tmp_path):
    out = tmp_path / "run.csv"
    argv = ["--scope", "system_dtest0,gpo3", "--scope-out", out, "--scope-window", "2ms:0.004"]
    assert run_cli(*argv, loop_file) == 0
    assert out.read_text() == ("time,system_dtest0,gpo3\n0.002,2.0,0\n0.003,3.0,1\n0.004,4.0,0\n")


def test_open_windows_and_every(loop_file, tmp_path):
    out = tmp_path / "run.csv"
    base = ["--scope", "system_dtest0", "--scope-out", out]
    assert run_cli(*base, "--scope-window", ":0.001", loop_file) == 0
    assert out.read_text() == "time,system_dtest0\n0.0,0.0\n0.001,1.0\n"
    assert run_cli(*base, "--scope-window", "3ms:", "--scope-every", "2", loop_file) == 0
    assert out.read_text() == "time,system_dtest0\n0.004,4.0\n"


def test_vcd_window_starts_with_the_values_at_its_start(loop_file, tmp_path):
    out = tmp_path / "run.vcd"
    argv = ["--scope", "system_dtest0,gpo3", "--scope-out", out, "--scope-window", "3ms:4ms"]
    assert run_cli(*argv, loop_file) == 0
    body = out.read_text().partition("$enddefinitions $end\n")[2]
    assert body == '#3000\n$dumpvars\nr3.0 !\n1"\n$end\n#4000\nr4.0 !\n0"\n'


def test_plot_window(loop_file, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from motionvm.sim import scope_plot

    drawn = []
    build = scope_plot.build_figure

    def build_and_note(recorder, title=""):
        drawn.append(list(recorder.times))
        return build(recorder, title)

    monkeypatch.setattr(scope_plot, "build_figure", build_and_note)
    out = tmp_path / "run.png"
    argv = ["--scope", "system_dtest0,gpo3", "--scope-out", out, "--scope-window", "1ms:2ms"]
    assert run_cli(*argv, loop_file) == 0
    assert drawn == [[0.001, 0.002]]
    vcd = tmp_path / "run.vcd"
    assert run_cli(*argv[:3], vcd, *argv[4:], loop_file) == 0
    assert f"$comment {loop_file}, window 0.001:0.002 s $end" in vcd.read_text()
    assert out.read_bytes().startswith(b"\x89PNG")


def test_window_without_samples_notes_it(loop_file, tmp_path, capsys):
    out = tmp_path / "run.csv"
    argv = ["--scope", "system_dtest0", "--scope-out", out, "--scope-window", "1:2"]
    assert run_cli(*argv, loop_file) == 0
    assert out.read_text() == "time,system_dtest0\n"
    err = capsys.readouterr().err
    assert "--scope-window 1:2 holds no sample (the recording spans 0 to 0.005 s)" in err


def test_keep_window_is_idempotent():
    from motionvm.sim.scope import ScopeRecorder

    values = iter(range(10))
    rec = ScopeRecorder([Channel("n", "raw", lambda: next(values))], 0.001)
    for k in range(10):
        rec.sample(k)
    w = ScopeWindow(0.003, 0.005)
    rec.keep_window(w)
    rec.keep_window(w)
    assert rec.times == [0.003, 0.004, 0.005] and rec.columns == [[3, 4, 5]]


# ---------------------------------------------------------------- --scope-out -


def cli(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    src = str(Path(motionvm.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    return subprocess.run(
        [sys.executable, "-m", "motionvm", "run", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )


def test_csv_to_stdout_follows_the_messages(loop_file, tmp_path):
    r = cli(
        ["--scope", "system_dtest0,gpo3", "--scope-out", "-", "--scope-out", "run.vcd"]
        + ["--scope-window", ":2ms", loop_file.name],
        tmp_path,
    )
    assert (r.returncode, r.stderr) == (0, "")
    assert r.stdout == (
        "start\ndone\ntime,system_dtest0,gpo3\n0.0,0.0,0\n0.001,1.0,1\n0.002,2.0,0\n"
    )
    assert (tmp_path / "run.vcd").exists()


def test_csv_to_stdout_alone_is_pure_csv(tmp_path):
    (tmp_path / "quiet.hmpl").write_text("void main() { system_dtest1 = 0.1 + 0.2; Sleep(1); }\n")
    r = cli(["--scope", "system_dtest1", "--scope-out", "-", "quiet.hmpl"], tmp_path)
    assert (r.returncode, r.stderr) == (0, "")
    assert r.stdout == "time,system_dtest1\n0.0,0.30000000000000004\n0.001,0.30000000000000004\n"
