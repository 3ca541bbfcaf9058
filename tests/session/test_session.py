"""The run assembly: languages by suffix, compile before run, options per language, skipping."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

from motionvm.api import CompileError, SessionError, Simulation
from motionvm.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def cli(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text, encoding="utf-8")
    return p


def test_a_compile_error_in_any_language_and_nothing_runs(tmp_path):
    ok = write(tmp_path, "ok.hmpl", 'void main() { Print("ran"); }\n')
    bad = write(tmp_path, "bad.pdl", "#task/0;\nx = 1;\nhalt;\n")
    code, out, err = cli("run", ok, bad)
    assert code == 2 and out == "" and "bad.pdl:2:" in err
    with pytest.raises(CompileError) as exc:
        Simulation.from_files([ok, bad])
    assert exc.value.diagnostics and exc.value.diagnostics[0].pos.file.endswith("bad.pdl")


@pytest.mark.parametrize("option, value", [("--force", "VALUE OF x = 1"), ("--start", "_go")])
def test_an_option_of_a_language_without_files_is_exit_3(tmp_path, option, value):
    prog = write(tmp_path, "a.hmpl", "void main() { }\n")
    code, _out, err = cli("run", prog, option, value)
    assert code == 3 and option in err


def test_a_pdl_file_goes_to_the_first_axis_without_a_program(tmp_path, monkeypatch):
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    prog = write(tmp_path, "p.pdl", '#task/0;\nprintl("on");\nhalt;\n')
    machine = EXAMPLES / "03_pdl_drives.toml"  # axes 1 and 2 run programs
    sim = Simulation.from_files([prog], machine=machine)
    sim.run()
    assert [a for a, _d in sim.session.side("PDL").drives.drives] == [0, 1, 2]
    assert "on" in sim.messages


def test_a_bad_start_label_on_a_machine_is_a_command_line_error(tmp_path):
    prog = write(tmp_path, "p.pdl", "_go:\nret;\n")
    code, _out, err = cli(
        "run", "--machine", EXAMPLES / "03_pdl_drives.toml", prog, "--start", "_no"
    )
    assert code == 3 and "--start _no: the program has no label '_no'" in err


def test_check_compiles_any_number_of_files_of_every_language():
    files = [EXAMPLES / n for n in ("01_hello.hmpl", "03_pdl_drives.mover.pdl",
                                    "03_pdl_drives.counter.pdl", "02_gdl_packer.gdl")]  # fmt: skip
    assert cli("check", *files)[0] == 0


def test_no_skip_gives_the_same_output(tmp_path, monkeypatch):
    monkeypatch.chdir(EXAMPLES)
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    argv = ["run", "--machine", "03_pdl_drives.toml", "03_pdl_drives.hmpl", "--stamp"]
    jumped = cli(*argv)
    stepped = cli(*argv, "--no-skip")
    monkeypatch.setenv("MOTIONVM_NO_SKIP", "1")
    by_env = cli(*argv)
    assert jumped == stepped == by_env and jumped[0] == 0


def test_bad_input_that_is_not_a_program_raises_session_error(tmp_path):
    prog = write(tmp_path, "a.gdl", "MODULE m;\nEND$MODULE;\n")
    with pytest.raises(SessionError):
        Simulation.from_files([prog], scenario=str(tmp_path / "missing.toml"))
    with pytest.raises(SessionError):
        Simulation.from_files([tmp_path / "missing.hmpl"])
