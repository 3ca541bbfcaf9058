"""Inputs past what the languages and files allow are located errors, never internal
ones: an oversize PDL constant, `#include` of a device or pipe, an array bigger than the
program's memory, a string literal that fills memory; in machine files and scenarios a
value nested thousands deep, a list where a name belongs, a NUL in a folder name and a
write to a read-only system variable."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from motionvm.source.toml_places import MAX_DEPTH

HMPL_MAIN = 'void main() {\n    Print("%d", 1);\n}\n'
PDL_MAIN = '#long x;\n#task/0;\nx = 1;\nprintl("%d", x);\nhalt;\n'


def test_a_5000_digit_pdl_constant_is_located(cli):
    text = PDL_MAIN.replace("x = 1;", "x = " + "9" * 5000 + ";")
    r = cli("check", "a.pdl", a__pdl=text)
    assert r.code == 2
    assert r.stderr.startswith("a.pdl:3:5: error: constant 9999999999...999999 (5000 characters)")
    assert len(r.stderr) < 2000  # the caret line is cut around the column


@pytest.mark.parametrize("digits", ["0x" + "f" * 3000, "4294967296", "0" * 50 + "42"])
def test_pdl_constants_compared_as_text(cli, digits):
    r = cli("check", "a.pdl", a__pdl=PDL_MAIN.replace("x = 1;", f"x = {digits};"))
    assert r.code == (0 if digits.endswith("42") else 2), r.stderr


@pytest.mark.parametrize("lang", ["hmpl", "pdl"])
@pytest.mark.parametrize("target", ["/dev/zero", "/dev/stdin", "fifo", "folder"])
def test_an_include_of_a_special_file_is_located(tmp_path, lang, target):
    if target == "fifo":
        os.mkfifo(tmp_path / "fifo")
    if target == "folder":
        (tmp_path / "folder").mkdir()
    main = HMPL_MAIN if lang == "hmpl" else PDL_MAIN
    (tmp_path / f"a.{lang}").write_text(f'#include "{target}"\n' + main)
    t0 = time.monotonic()
    # a child whose stdin is a pipe nobody writes to: reading /dev/stdin would wait forever
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionvm", "check", f"a.{lang}"],
        cwd=tmp_path,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    try:
        out, err = proc.communicate(timeout=20)
    finally:
        proc.kill()
    assert time.monotonic() - t0 < 10
    assert proc.returncode == 2, err
    assert err.startswith(f"a.{lang}:1:"), err
    assert "not a regular file" in err, err


def test_a_one_megabyte_string_literal_takes_little_memory(tmp_path: Path):
    """The lexer's string pattern kept the regex engine's state for every character:
    a 1 MB literal took 400 MB, 5 MB about 2 GB."""
    literal = "a" * 1_000_000 + "\\n" * 100_000
    (tmp_path / "s.hmpl").write_text(f'char s[] = "{literal}";\n' + HMPL_MAIN)
    probe = (
        "import sys\n"
        "from motionvm.cli import main\n"
        "code = main(['check', sys.argv[1]])\n"
        "hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM:')]\n"
        "print(code, hwm[0].split()[1] if hwm else 0)\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", probe, str(tmp_path / "s.hmpl")],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        timeout=120,
    )
    code, rss_kb = r.stdout.split()
    assert code == "0", r.stderr[-1000:]
    assert int(rss_kb) < 250 * 1024, rss_kb


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("int a[1000000000];\n", "1:5: error: array 'a' is too large: 4,000,000,000 bytes"),
        ("int a[100000000];\nint *p = a;\n", "1:5: error: 'a' does not fit in the program's static memory"),
        ("void f() { static double d[100000000]; d[0] = 1; }\n", "1:26: error: 'd' does not fit"),
    ],
)  # fmt: skip
def test_an_array_beyond_memory_is_located(cli, text, message):
    r = cli("check", "a.hmpl", a__hmpl=text + HMPL_MAIN)
    assert r.code == 2
    assert r.stderr.startswith("a.hmpl:" + message), r.stderr
    assert "undeclared" not in r.stderr  # no cascade at the uses


def test_a_string_literal_beyond_memory_is_located(cli):
    text = 'void main() {\n    Print("%s", "' + "a" * 9_000_000 + '");\n}\n'
    r = cli("check", "a.hmpl", a__hmpl=text)
    assert r.code == 2
    assert r.stderr.startswith("a.hmpl:2:17: error: a string literal does not fit"), r.stderr[:300]


@pytest.mark.parametrize("opener", ["[", "{a = "])
@pytest.mark.parametrize("what", ["machine", "scenario"])
def test_a_5000_deep_toml_value_is_located(cli, opener, what):
    closer = "]" if opener == "[" else "}"
    text = "x = " + opener * 5000 + ("1" if opener != "[" else "") + closer * 5000 + "\n"
    t0 = time.process_time()
    r = cli("run", f"--{what}", "f.toml", "a.hmpl", f__toml="# deep\n" + text, a__hmpl=HMPL_MAIN)
    assert time.process_time() - t0 < 5
    assert r.code == 3
    col = 5 + len(opener) * MAX_DEPTH
    assert f"f.toml:2:{col}: error: " in r.stderr, r.stderr
    assert f"nested more than {MAX_DEPTH} deep" in r.stderr


def test_brackets_in_strings_and_comments_do_not_count(cli):
    deep = "[" * (MAX_DEPTH + 1)
    text = f'[controller]\ndata_dir = "{deep}" # {deep}\n'
    r = cli("run", "--machine", "m.toml", "a.hmpl", m__toml=text, a__hmpl=HMPL_MAIN)
    assert r.code == 0, r.stderr


@pytest.mark.parametrize(
    ("what", "text", "message"),
    [
        ("machine", "[[slave]]\nkind = []\n", 'm.toml:2:1: error: [[slave]] 0: kind = []: must be "digital" or "analog"'),
        ("machine", '[controller]\ndata_dir = "a\\u0000b"\n', "m.toml:2:1: error: data_dir: a folder name cannot hold a NUL"),
        ("scenario", '[[event]]\nat = 0.1\nfault = "hw_limit"\naxis = 0\nside = []\n', 'm.toml:5:1: error: event 1: side = []: must be "left" or "right"'),
        ("scenario", '[[event]]\nat = 0.1\nfault = []\n', "m.toml:3:1: error: event 1: fault = []: must be one of"),
        ("scenario", '[[event]]\nat = 0.1\nset = "system_timeInMs"\nvalue = 5\n', "m.toml:3:1: error: event 1: set = 'system_timeInMs': 'system_timeInMs' is read-only"),
        ("scenario", "[initial]\nsystem_fclk = 3\n", "m.toml:2:1: error: [initial]: system_fclk: 'system_fclk' is read-only"),
    ],
)  # fmt: skip
def test_bad_values_are_located(cli, what, text, message):
    r = cli("run", f"--{what}", "m.toml", "a.hmpl", m__toml=text, a__hmpl=HMPL_MAIN)
    assert r.code == 3
    assert r.stderr.startswith(message), r.stderr
