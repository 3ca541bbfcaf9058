"""PDL lexer: token kinds, values, positions, comments, splices and lexical errors."""

from __future__ import annotations

import pytest

from motionvm.lang.pdl.dump import dump_tokens
from motionvm.lang.pdl.lexer import tokenize
from motionvm.source import DiagnosticSink


def lex(text: str) -> tuple[list, DiagnosticSink]:
    sink = DiagnosticSink()
    return tokenize("t.pdl", text, sink), sink


def kinds(text: str) -> list[tuple[str, str]]:
    toks, sink = lex(text)
    assert not sink.items, [d.headline() for d in sink.items]
    return [(t.kind, t.text) for t in toks[:-1]]


def test_statement_tokens() -> None:
    assert kinds("pr[x]=pr[y]+400000;") == [
        ("name", "pr"),
        ("punct", "["),
        ("name", "x"),
        ("punct", "]"),
        ("punct", "="),
        ("name", "pr"),
        ("punct", "["),
        ("name", "y"),
        ("punct", "]"),
        ("punct", "+"),
        ("int", "400000"),
        ("punct", ";"),
    ]


def test_two_character_operators_are_single_tokens() -> None:
    ops = "+= -= *= /= %= &= |= @= ++ -- <= >= <> ->"
    assert [t for _, t in kinds(ops)] == ops.split()


def test_keywords_are_case_insensitive_and_identifiers_keep_case() -> None:
    toks, _ = lex("Sleep While TOUT myVar #Long")
    assert [(t.kind, t.value) for t in toks[:-1]] == [
        ("keyword", "sleep"),
        ("keyword", "while"),
        ("keyword", "tout"),
        ("name", None),
        ("directive", "long"),
    ]
    assert toks[3].text == "myVar"


def test_run_is_not_reserved() -> None:
    # The manual uses `run` as a parameter name: proc func(..., instate run).
    assert kinds("run") == [("name", "run")]


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("20000", 20000),
        ("0x02FC", 764),
        ("0xaabbccdd", -1430532899),
        ("0x000f0000", 983040),
        ("4294967295", -1),
        ("2147483648", -2147483648),
        ("0X10", 16),
    ],
)
def test_integer_constants_are_signed_32_bit(text: str, value: int) -> None:
    toks, sink = lex(text)
    assert not sink.items
    assert toks[0].kind == "int" and toks[0].value == value


@pytest.mark.parametrize(
    ("text", "value"), [("5.4", 5.4), ("0.5", 0.5), ("44.2", 44.2), (".5", 0.5), ("3.", 3.0)]
)
def test_float_constants(text: str, value: float) -> None:
    toks, _ = lex(text)
    assert toks[0].kind == "float" and toks[0].value == value


def test_strings_and_escapes() -> None:
    toks, sink = lex(r'"a \"b\" c\\d %ld"')
    assert not sink.items
    assert toks[0].kind == "string" and toks[0].value == 'a "b" c\\d %ld'


def test_typographic_quotes_from_the_pdf_read_as_ascii() -> None:
    toks, sink = lex("printl/101(\u201cOK, found home limit\u201d);")
    assert not sink.items
    assert [t.value for t in toks if t.kind == "string"] == ["OK, found home limit"]


def test_comments_are_removed() -> None:
    assert kinds("a=1; // c\n/* b\n c */ b=2;") == [
        ("name", "a"),
        ("punct", "="),
        ("int", "1"),
        ("punct", ";"),
        ("name", "b"),
        ("punct", "="),
        ("int", "2"),
        ("punct", ";"),
    ]


def test_positions_and_end_columns() -> None:
    toks, _ = lex("x = 1;\n  loop(10) do")
    assert [(t.pos.line, t.pos.col, t.end_col) for t in toks[:-1]] == [
        (1, 1, 2),
        (1, 3, 4),
        (1, 5, 6),
        (1, 6, 7),
        (2, 3, 7),
        (2, 7, 8),
        (2, 8, 10),
        (2, 10, 11),
        (2, 12, 14),
    ]


def test_line_starts_are_marked_and_splices_join_lines() -> None:
    toks, _ = lex("#define A x=1;\\  \n y=2;\nz;")
    assert [t.text for t in toks if t.bol] == ["#define", "z", ""]
    y = next(t for t in toks if t.text == "y")
    assert (y.pos.line, y.pos.col) == (2, 2)


def test_block_comment_does_not_start_a_line() -> None:
    toks, _ = lex("#define A 1 /* to\nhere */ 2\nB")
    assert [t.text for t in toks if t.bol] == ["#define", "B", ""]


def test_directive_tokens() -> None:
    toks, _ = lex("#task/2;")
    assert [(t.kind, t.text) for t in toks[:-1]] == [
        ("directive", "#task"),
        ("punct", "/"),
        ("int", "2"),
        ("punct", ";"),
    ]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("x = $;", "1:5: unexpected character '$'"),
        ("v2=100\u2019", "1:7: unexpected character '\u2019' (did you mean ';'?)"),
        ("x = 4294967296;", "1:5: constant 4294967296 does not fit in 32 bits"),
        ("x = 0x;", "1:5: hexadecimal constant '0x' has no digits"),
        ('x = "abc\n', "1:5: unterminated string: missing closing '\"' on this line"),
        ("/* open", "1:1: unterminated comment: '/*' has no closing '*/'"),
        ("# long x;", "1:1: no space is allowed between '#' and 'long': write '#long'"),
        ("# ;", "1:1: '#' must be followed by a directive name such as #long"),
        ("x = 1\uff1b", "1:6: full-width character '\uff1b' (did you mean ';'?)"),
    ],
)
def test_lexical_errors(text: str, message: str) -> None:
    _, sink = lex(text)
    assert [f"{d.pos.line}:{d.pos.col}: {d.message}" for d in sink.items] == [message]


def test_stray_quote_becomes_a_semicolon_for_recovery() -> None:
    toks, _ = lex("v2=100'")
    assert [t.text for t in toks[:-1]] == ["v2", "=", "100", ";"]


def test_dump_tokens() -> None:
    toks, _ = lex("#long a;\na=<x_run>;")
    assert dump_tokens(toks) == (
        "1:1 directive #long\n1:7 name a\n1:8 punct ;\n2:1 name a\n2:2 punct =\n"
        "2:3 punct <\n2:4 name x_run\n2:9 punct >\n2:10 punct ;\n2:11 eof\n"
    )
