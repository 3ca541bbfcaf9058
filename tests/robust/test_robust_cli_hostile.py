"""Hostile command lines and files: an end time past any cycle count, a run that ends
before a task started, dumps of files the lexer gives up on or nested deeper than
Python's default recursion, and ports out of range or taken. Each is a clear message
and the documented exit code, never an internal error (exit 4)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

GDL = Path(__file__).parents[1] / "programs" / "gdl"

HELLO = 'void main() {\n    Print("hi");\n}\n'


@pytest.mark.parametrize("option", ["--until", "--timeout"])
def test_an_end_time_past_any_cycle_count_runs_to_the_end(cli, option):
    # 1e308 s is finite, but 1e308 / 0.001 s cycles overflows a float
    r = cli("run", option, "1e308", "a.hmpl", a__hmpl=HELLO)
    assert (r.code, r.stdout, r.stderr) == (0, "hi\n", "")


def test_a_task_the_run_ended_before_says_it_had_not_started(cli):
    # (a main that can wait is a generator, its frame at the function's first line:
    # that line's first word, 'void', is not where the task waits)
    r = cli("run", "--until", "0", "a.hmpl", a__hmpl="void main() {\n    Sleep(5);\n}\n")
    assert (r.code, r.stdout) == (0, "")
    assert r.stderr == (
        "a.hmpl:1:1: note: task 0 (not started yet) still ran when the run ended at t=0 s\n"
    )


@pytest.mark.parametrize("stage", ["tokens", "ast"])
@pytest.mark.parametrize("suffix", ["pdl", "gdl"])
def test_a_dump_of_a_file_with_too_many_errors_lists_them(cli, stage, suffix):
    (cli.folder / f"junk.{suffix}").write_bytes(b"\x01" * 50)
    r = cli("dump", "--stage", stage, f"junk.{suffix}")
    assert r.code == 2
    assert r.stderr.count(f"junk.{suffix}:1:") == 20  # the most errors of one file


def test_a_gdl_dump_of_an_expression_nested_1000_deep_is_the_tree(cli):
    deep = "(" * 1000 + "1" + ")" * 1000
    gdl = (
        "MODULE m;\n  INTEGER$VARIABLE v [ ];\n  PROCEDURE p;\n"
        "  DECLARE { ANY$OPERATING$CONDITION };\n  BEGIN\n"
        f"    VALUE OF v = {deep};\n  END$PROCEDURE;\nEND$MODULE;\n"
    )
    r = cli("dump", "--stage", "ast", "m.gdl", m__gdl=gdl)
    assert (r.code, r.stderr) == (0, "")
    assert r.stdout.startswith("GdlFile\n") and "IntLit value=1" in r.stdout


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["lsp", "--tcp", "-1"], "motionvm lsp: error: argument --tcp: -1: a port is 0..65535"),
        (["lsp", "--tcp", "65536"], "argument --tcp: 65536: a port is 0..65535"),
        (["lsp", "--tcp", "x"], "argument --tcp: 'x' is not a port number"),
        (["debug", "--port", "70000"], "argument --port: 70000: a port is 0..65535"),
        (["studio", "--port", "-2", "--no-browser"], "argument --port: -2: a port is 0..65535"),
    ],
)
def test_a_port_out_of_range_is_exit_3(cli, argv, message):
    r = cli(*argv)
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.splitlines()[-1].endswith(message)


def test_a_language_server_port_in_use_is_exit_3(cli):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        r = cli("lsp", "--tcp", str(port))
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.startswith(f"motionvm: error: --tcp {port}: ")
    assert "address already in use" in r.stderr.lower()


@pytest.mark.parametrize(
    "argv", [["run"], ["check"], ["compile", "--emit-python"], ["dump", "--stage", "ast"]]
)
def test_a_folder_named_as_a_program_is_not_reported_missing(cli, argv):
    (cli.folder / "cell.hmpl").mkdir()
    r = cli(*argv, "cell.hmpl")
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr == (
        "motionvm: error: cell.hmpl: not a regular file (a device, pipe or folder)\n"
    )


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("long.hmpl", "x" * 200_000 + "\n"),
        ("long.pdl", "#task/0;\n" + "x" * 200_000 + "\nhalt;\n"),
        ("long.hmpl", "void main() { int " + "y" * 200_000 + " = 1; }\n"),
    ],
)
def test_a_name_of_200000_characters_is_quoted_by_its_ends(cli, name, text):
    (cli.folder / name).write_text(text, encoding="utf-8")
    r = cli("check", name)
    assert r.code in (0, 2)
    assert len(r.stderr) < 2_000  # each line shown is cut, each long name shortened
    assert "(200000 characters)" in r.stderr


def test_a_control_character_in_hmpl_is_named_as_gcc_names_it(cli):
    r = cli("check", "a.hmpl", a__hmpl="void main() {\n    int x;\x01\n}\x7f\n")
    assert r.code == 2
    errors = [line for line in r.stderr.splitlines() if ": error: " in line]
    assert errors == [
        "a.hmpl:2:11: error: stray '\\1' in program",
        "a.hmpl:3:2: error: stray '\\177' in program",
    ]


@pytest.mark.parametrize("timeout", ["1e7", "1e308"])
def test_a_case_timeout_past_what_the_system_waits_runs_the_cases(cli, timeout):
    # (one wait of 1e7 s overflows epoll's milliseconds; 1e308 s overflows time_t)
    case = 'void main() {\n    Print("hi"); // expect: hi\n}\n'
    r = cli("test", "--case-timeout", timeout, "c.hmpl", c__hmpl=case)
    assert r.code == 0
    assert "1 passed, 0 failed" in r.stdout


def test_a_link_to_nothing_is_reported_missing(cli):
    (cli.folder / "cell.hmpl").symlink_to(cli.folder / "gone.hmpl")
    r = cli("run", "cell.hmpl")
    assert (r.code, r.stderr) == (3, "motionvm: error: cell.hmpl: no such file\n")


def test_a_gdl_file_given_twice_is_named_not_reported_as_clashing_modules(cli):
    gdl = str(GDL / "globals.gdl")
    r = cli("check", gdl, str(GDL / "globals.2.gdl"), gdl)
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr == (
        f"motionvm: error: {gdl}: given twice; an application takes each of its .gdl files once\n"
    )


def test_two_pdl_files_on_the_command_line_are_named(cli):
    pdl = "#task/0;\nhalt;\n"
    r = cli("run", "a.pdl", "b.pdl", a__pdl=pdl, b__pdl=pdl)
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.startswith(
        "motionvm: error: at most one .pdl file on the command line, got 2 (a.pdl, b.pdl); "
    )
