"""`--version`, help for every option with the exit codes, and durations (150ms, 2s, 1min)."""

from __future__ import annotations

import argparse

import pytest

from motionvm import __version__, compiled_build
from motionvm.cli.options import build_parser, duration

EXIT_CODES = ("0", "1", "2", "3", "4", "124", "130")


def test_version_prints_the_package_version(motionvm, tmp_path):
    r = motionvm("--version", cwd=tmp_path)
    status = compiled_build.STATUS
    assert (r.returncode, r.stdout, r.stderr) == (
        0, f"motionvm {__version__} (motion cycle: {status})\n", ""
    )  # fmt: skip
    assert __version__ == "0.1.0"


@pytest.mark.parametrize("argv", [["--help"], ["run", "--help"]])
def test_help_ends_with_the_exit_codes(motionvm, tmp_path, argv):
    r = motionvm(*argv, cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == ""
    table = r.stdout.split("exit codes:\n", 1)[1].splitlines()
    codes = [line.split()[0] for line in table if line.startswith("  ")]
    assert tuple(codes) == EXIT_CODES
    assert "  124  the run had not finished at --timeout, or can never end" in table


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def test_every_option_and_positional_of_every_command_has_help():
    commands = _subparsers(build_parser())
    assert {"run", "check", "compile", "builtins", "errors", "dump", "scope", "test"} <= set(
        commands
    )
    missing = [
        f"{name} {action.dest}"
        for name, parser in commands.items()
        for action in parser._actions
        if not action.help
    ]
    assert missing == []


def test_every_command_has_help_in_the_overview(motionvm, tmp_path):
    out = motionvm("--help", cwd=tmp_path).stdout
    for name in ("run", "check", "compile", "builtins", "errors", "dump", "scope", "test"):
        assert any(
            line.split()[:1] == [name] and len(line.split()) > 1 for line in out.splitlines()
        )


@pytest.mark.parametrize(
    ("text", "seconds"),
    [("1.5", 1.5), ("150ms", 0.15), ("350ms", 0.35), ("2s", 2.0), ("1min", 60.0), ("0", 0.0)],
)
def test_durations(text, seconds):
    assert duration(text) == seconds


@pytest.mark.parametrize("text", ["5x", "fast", "-1", "-2s", "inf", "nan", "1e400", ""])
def test_bad_durations_are_refused(text):
    with pytest.raises(argparse.ArgumentTypeError):
        duration(text)


def test_until_takes_milliseconds(motionvm, tmp_path):
    (tmp_path / "a.hmpl").write_text(
        'void main() {\n    while (1) {\n        Sleep(100);\n        Print("t");\n    }\n}\n',
        "utf-8",
    )
    r = motionvm("run", "--until", "350ms", "a.hmpl", cwd=tmp_path)
    assert (r.returncode, r.stdout) == (0, "t\nt\nt\n")
    assert "ended at t=0.35 s" in r.stderr
    r = motionvm("run", "--timeout", "0.5min", "--until", "1s", "a.hmpl", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout.count("t\n") == 9  # the one due at 1 s is not


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("5x", "unknown unit 'x'"),
        ("-1", "finite and non-negative"),
        ("inf", "finite and non-negative"),
        ("soon", "is not a duration"),
    ],
)
def test_a_bad_duration_is_a_clear_exit_3_error(motionvm, tmp_path, value, words):
    (tmp_path / "a.hmpl").write_text("void main() { }\n", "utf-8")
    for option in ("--until", "--timeout"):
        r = motionvm("run", option, value, "a.hmpl", cwd=tmp_path)
        assert r.returncode == 3
        assert f"error: argument {option}: '{value}'" in r.stderr and words in r.stderr
        assert "Traceback" not in r.stderr


def test_case_timeout_takes_a_duration(motionvm, tmp_path):
    r = motionvm("test", "--case-timeout", "1min", str(tmp_path), cwd=tmp_path)
    assert "--case-timeout" not in r.stderr
    r = motionvm("test", "--case-timeout", "later", str(tmp_path), cwd=tmp_path)
    assert r.returncode == 3 and "argument --case-timeout: 'later'" in r.stderr


@pytest.mark.parametrize(
    ("argv", "usage"),
    [
        (["run", "--bogus", "a.hmpl"], "usage: motionvm run "),
        (["builtins", "--nope"], "usage: motionvm builtins "),
        (["check", "--fast", "a.hmpl"], "usage: motionvm check "),
    ],
)
def test_an_unknown_option_prints_the_usage_of_its_command(motionvm, tmp_path, argv, usage):
    r = motionvm(*argv, cwd=tmp_path)
    assert r.returncode == 3 and r.stdout == ""
    assert r.stderr.startswith(usage)
    assert f"motionvm {argv[0]}: error: unrecognized arguments: {argv[1]}" in r.stderr
    assert "COMMAND" not in r.stderr  # not the top-level usage
