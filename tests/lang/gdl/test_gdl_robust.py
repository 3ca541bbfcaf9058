"""No input makes the GDL compiler raise: random text, mutated programs, odd files."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from motionvm.lang.gdl.compiler import compile_app
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic
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


def test_gdl_missing_file_is_a_diagnostic(tmp_path: Path, cli) -> None:
    absent = tmp_path / "absent.gdl"
    sink = DiagnosticSink()
    assert compile_app([str(absent)], sink=sink) is None
    assert sink.has_errors
    rendered = "\n".join(render_diagnostic(d) for d in sink.items)
    assert "absent.gdl:1:1: error: cannot read the file" in rendered
    # The command line checks that its files exist before compiling: a bad command line.
    rc, out, err = cli("check", absent)
    assert (rc, out) == (3, "")
    assert err == f"motionvm: error: {absent}: no such file\n"


def test_gdl_binary_and_empty_files(tmp_path: Path, cli) -> None:
    (tmp_path / "bin.gdl").write_bytes(bytes(range(256)))
    (tmp_path / "empty.gdl").write_text("")
    for name in ("bin.gdl", "empty.gdl"):
        rc, _out, err = cli("check", tmp_path / name)
        assert rc == 2
        assert "Traceback" not in err


def test_gdl_compile_errors_exit_2_and_nothing_runs(tmp_path: Path, cli) -> None:
    (tmp_path / "bad.gdl").write_text("MODULE m;\n  IO$BOARD b [ SLOT = 99 ];\nEND$MODULE;\n")
    rc, out, err = cli("run", tmp_path / "bad.gdl")
    assert rc == 2
    assert out == ""
    assert err.splitlines()[1:] == [
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
    jumped, stepped = jumped_and_stepped([PROGRAMS / "packer.gdl"], str(folder / "s.toml"))
    assert jumped == stepped
    assert jumped[0].count("input ") == len(events)
