"""No input makes the GDL compiler raise: random text, mutated programs, odd files."""

from __future__ import annotations

import io
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from motionvm.lang.gdl import main_check, main_run
from motionvm.lang.gdl.compiler import compile_app
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourceFile

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"
PACKER = (PROGRAMS / "packer.gdl").read_text()
ALPHABET = "ABCDEFGIMNORSTUVW$_abcxyz0123456789 \n\t=+-*/(),;<>[]{}'|&.@{}"


def _compile_text(text: str, tmp_path: Path, name: str = "fuzz.gdl") -> DiagnosticSink:
    path = tmp_path / name
    path.write_text(text)
    SourceFile._cache.pop(str(path), None)
    sink = DiagnosticSink()
    compile_app([str(path)], sink=sink)
    return sink


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.text(alphabet=ALPHABET, max_size=200))
def test_gdl_random_text_never_raises(tmp_path_factory, text: str) -> None:
    _compile_text(text, tmp_path_factory.mktemp("f"))


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.integers(0, len(PACKER) - 1), st.integers(1, 30), st.text(alphabet=ALPHABET, max_size=8))
def test_gdl_mutated_example_never_raises(tmp_path_factory, at: int, cut: int, insert: str) -> None:
    text = PACKER[:at] + insert + PACKER[at + cut :]
    sink = _compile_text(text, tmp_path_factory.mktemp("m"))
    for d in sink.items:
        assert d.pos.line >= 1 and d.pos.col >= 1


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from(PACKER.split()), max_size=60))
def test_gdl_shuffled_words_never_raise(tmp_path_factory, words: list[str]) -> None:
    _compile_text(" ".join(words), tmp_path_factory.mktemp("w"))


def test_gdl_missing_file_is_a_diagnostic(tmp_path: Path) -> None:
    err = io.StringIO()
    assert main_check([str(tmp_path / "absent.gdl")], io.StringIO(), err) == 2
    assert "absent.gdl:1:1: error: cannot read the file" in err.getvalue()


def test_gdl_binary_and_empty_files(tmp_path: Path) -> None:
    (tmp_path / "bin.gdl").write_bytes(bytes(range(256)))
    (tmp_path / "empty.gdl").write_text("")
    for name in ("bin.gdl", "empty.gdl"):
        err = io.StringIO()
        assert main_check([str(tmp_path / name)], io.StringIO(), err) == 2
        assert "Traceback" not in err.getvalue()


def test_gdl_compile_errors_exit_2_and_nothing_runs(tmp_path: Path) -> None:
    (tmp_path / "bad.gdl").write_text("MODULE m;\n  IO$BOARD b [ SLOT = 99 ];\nEND$MODULE;\n")
    out, err = io.StringIO(), io.StringIO()
    assert main_run([str(tmp_path / "bad.gdl")], None, None, out, err) == 2
    assert out.getvalue() == ""
    assert err.getvalue().splitlines()[1:] == [
        "  IO$BOARD b [ SLOT = 99 ];",
        "                      ^",
    ]


_INPUTS = ["STATUS OF start_button", "STATUS OF stop_button"] + [
    f"STATUS OF photocell{{{i}}}" for i in range(1, 5)
]


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    st.lists(st.tuples(st.integers(0, 400), st.sampled_from(_INPUTS), st.booleans()), max_size=12)
)
def test_gdl_random_scenarios_run_the_same_stepped_or_jumped(
    tmp_path_factory, jumped_and_stepped, events
) -> None:
    folder = tmp_path_factory.mktemp("s")
    toml = "".join(
        f'[[event]]\nat = {ms / 1000}\nset = "{ref}"\nvalue = "{"ON" if on else "OFF"}"\n'
        for ms, ref, on in events
    )
    (folder / "s.toml").write_text(toml)
    app = compile_app([str(PROGRAMS / "packer.gdl")], sink=DiagnosticSink())
    assert app is not None
    jumped, stepped = jumped_and_stepped(app, str(folder / "s.toml"))
    assert jumped == stepped
    assert jumped[0].count("input ") == len(events)
