"""The progress bar of `motionvm run`: on a terminal's stderr for a run that takes a while,
never otherwise, and never changing what the run does."""

from __future__ import annotations

import os
import pty
import re
import subprocess
import sys
from pathlib import Path

import pytest

from motionvm.session import RunSpec, Session, Source

BUSY = """void main() {
    int n = 0;
    while (1) {
        n = n + 1;
        Sleep(1);
        if (n % 200 == 0) Print("n=%d", n);
    }
}
"""
FINITE = BUSY.replace("while (1)", "while (n < 1200)")
PACED = ("--realtime", "--until", "1200ms")
"""Paced to the wall clock, a run lasts 1.2 s on any machine: long enough for the bar,
which waits half a second before it draws."""
COLOUR = re.compile(rb"\x1b\[(?:3\d|9\d|38;)[\d;]*m")
"""An SGR escape that sets a foreground colour."""
BAR_ESCAPE = re.compile(rb"\x1b\[(?:2K|\d*[ABCDGK])")
"""An escape that moves the cursor or erases (what a transient bar draws with); the
diagnostics are coloured on a terminal (SGR escapes) but never redraw."""
SGR = re.compile(r"\x1b\[[\d;]*m")


def plain(text: str) -> str:
    """`text` without its colours."""
    return SGR.sub("", text)


def run_on_terminal(*argv, cwd: Path, env: dict[str, str] | None = None):
    """`motionvm ARGV` with stderr on a pseudo-terminal: (exit code, stdout, stderr bytes)."""
    full_env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    full_env.update({"TERM": "xterm-256color", "COLUMNS": "100"})
    full_env.update(env or {})
    primary, secondary = pty.openpty()
    try:
        proc = subprocess.Popen(
            [sys.executable, "-m", "motionvm", *argv],
            cwd=cwd,
            stdout=subprocess.PIPE,
            stderr=secondary,
            env=full_env,
        )
        os.close(secondary)
        secondary = -1
        chunks = []
        while True:  # read while it runs: a full terminal buffer would stall it
            try:
                data = os.read(primary, 4096)
            except OSError:  # EIO: the child closed its end
                break
            if not data:
                break
            chunks.append(data)
        stdout = proc.stdout.read().decode()
        proc.stdout.close()
        code = proc.wait(timeout=120)
    finally:
        os.close(primary)
        if secondary >= 0:
            os.close(secondary)
    return code, stdout, b"".join(chunks)


def _lines_after_the_bar(err: bytes) -> list[str]:
    """What stays on the terminal once the transient bar is erased (its last line)."""
    text = err.decode()
    text = text[text.rfind("\x1b[2K") + 4 :] if "\x1b[2K" in text else text
    return [plain(line.strip("\r")) for line in text.splitlines()]


def test_a_long_run_shows_a_bar_towards_until(tmp_path, motionvm):
    (tmp_path / "busy.hmpl").write_text(BUSY, "utf-8")
    code, stdout, err = run_on_terminal("run", *PACED, "busy.hmpl", cwd=tmp_path)
    assert code == 0
    assert re.search(rb"t=\d\.\d{3} / 1\.2 s", err), err[:500]
    assert re.search(rb"\d+%", err)
    assert re.search(rb"\d+\.\dx real time", err)  # paced: about 1.0x
    assert re.search(rb"ETA 0:00:0\d", err)
    assert COLOUR.search(err)
    lines = _lines_after_the_bar(err)
    assert (
        lines[0] == "busy.hmpl:5:9: note: task 0 (in Sleep) still ran when the run ended at t=1.2 s"
    )
    assert re.fullmatch(r"motionvm: 1\.200 s simulated in .*, 0 faults", lines[1])
    # the same output as a run nobody watches
    piped = motionvm("run", *PACED, "busy.hmpl", cwd=tmp_path)
    assert stdout == piped.stdout and stdout.count("\n") == 5
    assert piped.stderr == lines[0] + "\n"


def test_without_an_end_a_spinner_shows_the_simulated_time(tmp_path):
    (tmp_path / "finite.hmpl").write_text(FINITE, "utf-8")
    code, stdout, err = run_on_terminal("run", "--realtime", "finite.hmpl", cwd=tmp_path)
    assert code == 0 and stdout.endswith("n=1200\n")
    assert re.search(rb"simulated t=\d+\.\d{3} s", err)
    assert b"/ " not in err  # no end time: no fraction, no bar


def test_no_color_takes_the_colour_out(tmp_path):
    (tmp_path / "busy.hmpl").write_text(BUSY, "utf-8")
    _, _, err = run_on_terminal("run", *PACED, "busy.hmpl", cwd=tmp_path, env={"NO_COLOR": "1"})
    assert re.search(rb"t=\d\.\d{3} / 1\.2 s", err)
    assert not COLOUR.search(err)


def test_no_progress_turns_it_off(tmp_path):
    (tmp_path / "busy.hmpl").write_text(BUSY, "utf-8")
    code, _, err = run_on_terminal("run", "--no-progress", *PACED, "busy.hmpl", cwd=tmp_path)
    assert code == 0
    assert not BAR_ESCAPE.search(err) and b"\r\x1b" not in err
    lines = plain(err.decode()).splitlines()
    assert len(lines) == 2 and lines[1].startswith("motionvm: 1.200 s simulated in ")


def test_no_bar_when_stderr_is_not_a_terminal(tmp_path, motionvm):
    (tmp_path / "busy.hmpl").write_text(BUSY, "utf-8")
    r = motionvm("run", *PACED, "busy.hmpl", cwd=tmp_path)
    assert r.returncode == 0
    assert (
        r.stderr
        == "busy.hmpl:5:9: note: task 0 (in Sleep) still ran when the run ended at t=1.2 s\n"
    )


def test_the_progress_callback_sees_the_run_without_changing_it(tmp_path):
    program = tmp_path / "busy.hmpl"
    program.write_text(BUSY, "utf-8")

    def run(progress=None, skip=True):
        lines: list[str] = []
        session = Session(
            RunSpec([Source(str(program))], skip=skip), emit=lines.append, report=lines.append
        )
        result = session.run(until=20.0, progress=progress)
        return lines, result.sim_time, result.reason

    seen: list[float] = []
    assert run(seen.append) == run()
    assert seen[0] == 0.0 and seen == sorted(seen)
    steps = {round((b - a) * 1000) for a, b in zip(seen, seen[1:])}
    assert steps == {100}  # every 100 cycles of 1 ms
    assert seen[-1] == pytest.approx(20.0)  # the end cycle is reported too
    stepped: list[float] = []
    assert run(stepped.append, skip=False) == run()
    assert stepped == seen


def test_a_short_run_gets_no_speed_nonsense_in_its_summary(tmp_path):
    (tmp_path / "quick.hmpl").write_text('void main() { Print("hi"); }\n', "utf-8")
    code, stdout, err = run_on_terminal("run", "quick.hmpl", cwd=tmp_path)
    assert code == 0 and stdout == "hi\n"
    (line,) = err.decode().splitlines()
    wall = r"(?:\d+\.\d{2} s|\d+\.\d{1,2} ms)"
    m = re.fullmatch(
        rf"motionvm: 0\.00[01] s simulated in ({wall})(?: \(\d+x real time\))?, 0 faults", line
    )
    assert m, line
    if "real time" in line:  # a speed only for a wall time long enough to measure it
        assert not m.group(1).endswith(" ms") or float(m.group(1).split()[0]) >= 10


@pytest.mark.parametrize(
    ("wall", "text"), [(2.5, "2.50 s"), (0.0456, "45.6 ms"), (0.00084, "0.84 ms")]
)
def test_wall_times_keep_their_precision(wall, text):
    from motionvm.cli.run import wall_text

    assert wall_text(wall) == text


def test_rate_and_eta():
    from motionvm.cli.progress import rate_and_eta

    assert rate_and_eta(10.0, 2.0, 20.0, 10.0) == ("5.0x real time", "ETA 0:00:02")
    assert rate_and_eta(500.0, 1.0, None, 500.0) == ("500x real time", "")
    assert rate_and_eta(0.0, 1.0, 5.0, 0.0) == ("", "")
