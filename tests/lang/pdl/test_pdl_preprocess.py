"""PDL preprocessor: macros, conditional compilation and #include (manual §2.5.3-§2.5.6)."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.pdl.preprocess import MAX_INCLUDE_DEPTH, preprocess
from motionvm.source import DiagnosticSink


def pp(text: str, name: str = "mem/pp.pdl") -> tuple[str, list[str]]:
    sink = DiagnosticSink()
    toks = preprocess(name, sink, text)
    out = " ".join(t.text for t in toks if t.kind != "eof")
    return out, [f"{d.pos.line}:{d.pos.col}: {d.message}" for d in sink.items]


def test_object_like_macro() -> None:
    assert pp("#define LIMIT 100\nx = LIMIT;") == ("x = 100 ;", [])


def test_function_like_macros_expand_recursively_as_in_the_manual() -> None:
    text = (
        "#define ADD2(r,a,b)        r = a+b;\n"
        "#define ADD3(r,a,b,c)      ADD2(r,a,b)    r += c;\n"
        "#define ADD4(r,a,b,c,d)    ADD3(r,a,b,c) r += d;\n"
        "ADD4(result,var1,var2,var3,var4)\n"
    )
    out, errors = pp(text)
    assert errors == []
    assert out == "result = var1 + var2 ; result += var3 ; result += var4 ;"


def test_multi_line_macro_with_backslashes() -> None:
    text = "#define LONGCODE  var1=var2+var3;\\\n   ff1=ff2*ff3;\\ \n   var++;\nLONGCODE\n"
    out, errors = pp(text)
    assert errors == []
    assert out == "var1 = var2 + var3 ; ff1 = ff2 * ff3 ; var ++ ;"


def test_trailing_semicolon_is_part_of_the_body() -> None:
    sink = DiagnosticSink()
    toks = preprocess("mem/semi.pdl", sink, "#define size 10;\n#long array[size]\n")
    semi = next(t for t in toks if t.text == ";")
    assert semi.origin is not None and semi.origin.name == "size"
    assert semi.origin.body_ends_with_semicolon
    assert (semi.pos.line, semi.pos.col) == (2, 13)  # the use of the macro


def test_expanded_tokens_carry_the_position_of_the_use() -> None:
    sink = DiagnosticSink()
    toks = preprocess("mem/pos.pdl", sink, "#define INC(v) v += 1;\n\n   INC(count)\n")
    assert [(t.text, t.pos.line, t.pos.col) for t in toks[:-1]] == [
        ("count", 3, 8),
        ("+=", 3, 4),
        ("1", 3, 4),
        (";", 3, 4),
    ]


def test_function_like_macro_name_without_parentheses_is_left_alone() -> None:
    assert pp("#define F(a) a\nx = F;") == ("x = F ;", [])


def test_object_like_when_a_space_precedes_the_parenthesis() -> None:
    assert pp("#define G (1)\nx = G;") == ("x = ( 1 ) ;", [])


def test_rescan_with_following_tokens() -> None:
    assert pp("#define F(a) a+1\n#define G F\nx = G(2);") == ("x = 2 + 1 ;", [])


def test_self_reference_does_not_loop() -> None:
    assert pp("#define X X+1\ny = X;") == ("y = X + 1 ;", [])
    assert pp("#define A B\n#define B A\ny = A;") == ("y = A ;", [])


def test_exponential_expansion_is_stopped() -> None:
    lines = ["#define M0 x"] + [f"#define M{i} M{i - 1} M{i - 1}" for i in range(1, 30)]
    _, errors = pp("\n".join(lines) + "\nM29\n")
    assert errors == ["31:1: macro expansion too large (recursive macros?)"]


def test_macros_are_not_expanded_in_strings() -> None:
    assert pp('#define N 5\nprintl/103("N=%ld ", N);') == ('printl / 103 ( "N=%ld " , 5 ) ;', [])


def test_arguments_with_parentheses_and_commas() -> None:
    assert pp("#define INVOKE(p, a) p(a);\nINVOKE(f, (1))") == ("f ( ( 1 ) ) ;", [])


def test_undef_then_redefine() -> None:
    text = "#define KEY STRING1\nKEY\n#undef KEY\n#define KEY STRING2\nKEY\n"
    assert pp(text) == ("STRING1 STRING2", [])


def test_identical_redefinition_is_allowed() -> None:
    assert pp("#define A 1\n#define A 1\nA") == ("1", [])


COND = {
    "ifdef": "#ifdef KEY\na\n#endif\n",
    "ifdef_else": "#ifdef KEY\na\n#else\nb\n#endif\n",
    "ifndef_else": "#ifndef KEY\na\n#else\nb\n#endif\n",
    "elifdef": "#ifdef KEY1\na\n#elifdef KEY2\nb\n#endif\n",
    "elifndef": "#ifdef KEY1\na\n#elifndef KEY2\nb\n#else\nc\n#endif\n",
}


@pytest.mark.parametrize(
    ("construct", "defined", "expected"),
    [
        ("ifdef", "KEY", "a"),
        ("ifdef", "", ""),
        ("ifdef_else", "KEY", "a"),
        ("ifdef_else", "", "b"),
        ("ifndef_else", "", "a"),
        ("ifndef_else", "KEY", "b"),
        ("elifdef", "KEY1", "a"),
        ("elifdef", "KEY2", "b"),
        ("elifdef", "", ""),
        ("elifdef", "KEY1 KEY2", "a"),
        ("elifndef", "", "b"),
        ("elifndef", "KEY2", "c"),
        ("elifndef", "KEY1", "a"),
    ],
)
def test_conditional_compilation_table(construct: str, defined: str, expected: str) -> None:
    defs = "".join(f"#define {k}\n" for k in defined.split())
    assert pp(defs + COND[construct]) == (expected, [])


def test_nested_conditionals_and_directives_inside_them() -> None:
    text = (
        "#define A\n"
        "#ifdef A\n  #ifdef B\n    x\n  #else\n    #define C\n  #endif\n#endif\n"
        "#ifndef B\n  #ifdef C\n    y\n  #endif\n#endif\n"
        '#ifdef B\n  #ifdef A\n    z\n  #else\n    #include "missing.h"\n  #endif\n#endif\n'
    )
    assert pp(text) == ("y", [])


def test_skipped_region_ignores_unknown_directives() -> None:
    assert pp("#ifdef NO\n#pragma nothing\n#endif\nx") == ("x", [])


def test_statement_directives_pass_through() -> None:
    assert pp("#task/2;\n#long a;") == ("#task / 2 ; #long a ;", [])


def test_include_relative_to_the_including_file(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "common.h").write_text("#define ONE 1\n#long shared;\n")
    main = tmp_path / "lib" / "main.pdl"
    main.write_text('#include "..\\common.h"\nshared = ONE;\n')
    sink = DiagnosticSink()
    toks = preprocess(str(main), sink)
    assert not sink.items
    assert " ".join(t.text for t in toks[:-1]) == "#long shared ; shared = 1 ;"
    assert toks[0].pos.file.endswith("common.h")


def _include_chain(tmp_path: Path, depth: int) -> Path:
    for i in range(depth):
        (tmp_path / f"f{i}.h").write_text(f'#include "f{i + 1}.h"\n')
    (tmp_path / f"f{depth}.h").write_text("#long deepest;\n")
    return tmp_path / "f0.h"


def test_include_nesting_of_20_levels_is_allowed(tmp_path: Path) -> None:
    sink = DiagnosticSink()
    toks = preprocess(str(_include_chain(tmp_path, MAX_INCLUDE_DEPTH)), sink)
    assert not sink.items
    assert [t.text for t in toks[:-1]] == ["#long", "deepest", ";"]


def test_include_nesting_of_21_levels_is_an_error(tmp_path: Path) -> None:
    sink = DiagnosticSink()
    preprocess(str(_include_chain(tmp_path, MAX_INCLUDE_DEPTH + 1)), sink)
    assert [(d.pos.file.rsplit("/", 1)[-1], d.pos.line, d.message) for d in sink.items] == [
        ("f20.h", 1, "'#include' nested more than 20 levels deep (including 'f21.h')")
    ]


def test_recursive_include_is_an_error(tmp_path: Path) -> None:
    (tmp_path / "a.h").write_text('#include "b.h"\n')
    (tmp_path / "b.h").write_text('#include "a.h"\n')
    sink = DiagnosticSink()
    preprocess(str(tmp_path / "a.h"), sink)
    assert [d.message for d in sink.items] == ["'a.h' includes itself (recursive #include)"]


def test_include_with_angle_brackets(tmp_path: Path) -> None:
    (tmp_path / "x.h").write_text("#long fromx;\n")
    (tmp_path / "m.pdl").write_text("#include <x.h>\n")
    sink = DiagnosticSink()
    toks = preprocess(str(tmp_path / "m.pdl"), sink)
    assert not sink.items and [t.text for t in toks[:-1]] == ["#long", "fromx", ";"]


def test_missing_endif_in_an_included_file_is_reported_there(tmp_path: Path) -> None:
    (tmp_path / "open.h").write_text("#ifdef X\n")
    (tmp_path / "m.pdl").write_text('#include "open.h"\n#endif\n')
    sink = DiagnosticSink()
    preprocess(str(tmp_path / "m.pdl"), sink)
    assert [(d.pos.file.rsplit("/", 1)[-1], d.pos.line, d.message) for d in sink.items] == [
        ("open.h", 1, "'#ifdef' has no matching '#endif'"),
        ("m.pdl", 2, "'#endif' without a matching '#ifdef' or '#ifndef'"),
    ]
