"""A long recording keeps its memory flat: old samples go to a temporary file in chunks,
and every file written from it is the same as from a recording kept in memory."""

from __future__ import annotations

import pytest

from motionvm.cli import main
from motionvm.sim.scope import ScopeRecorder

PROGRAM = """\
int count;
double table[2];
void main()
{
    int i;
    Enable(0); Till(IsEnabled(0));
    for (i = 0; i < 60; i++) {
        count = i;
        table[1] = i * 0.25;
        HIMC_GPO(3) = i % 2;
        if (i == 10) SetHMIScope(1);
        if (i == 40) SetHMIScope(0);
        if (i % 20 == 0) MoveRel(0, 3.0);
        Sleep(1);
    }
    Till(IsInPos(0));
}
"""
CHANNELS = "system_timeInMs,count,table[1],gpo3,axis0.pos_fb,axis0.ref_vel"


def _files(tmp_path, chunk: int, monkeypatch, *options: str) -> list[bytes]:
    monkeypatch.setattr(ScopeRecorder, "CHUNK", chunk)
    prog = tmp_path / "p.hmpl"
    prog.write_text(PROGRAM, encoding="utf-8")
    outs = [tmp_path / f"{chunk}.csv", tmp_path / f"{chunk}.vcd"]
    argv = ["run", "--scope", CHANNELS, *options]
    for out in outs:
        argv += ["--scope-out", str(out)]
    assert main([*argv, str(prog)]) == 0
    return [out.read_bytes() for out in outs]


@pytest.mark.parametrize("options", [(), ("--scope-window", "0.012:0.05"), ("--scope-every", "3")])
def test_chunks_on_file_write_the_same_files(tmp_path, monkeypatch, options):
    assert _files(tmp_path, 7, monkeypatch, *options) == _files(
        tmp_path, 100000, monkeypatch, *options
    )


def test_a_recording_reads_back_across_chunks(monkeypatch):
    monkeypatch.setattr(ScopeRecorder, "CHUNK", 4)
    rec = ScopeRecorder([], 0.001)
    for cycle in range(11):
        rec.sample(cycle)
    assert len(rec) == 11 and rec.cycles == list(range(11)) and rec.hmi_on == [True] * 11
    assert rec._file is not None and len(rec._cycles) == 3
