"""GDL lexer: the description's lexical rules, case by case."""

from __future__ import annotations

import pytest

from motionvm.lang.gdl.lexer import tokenize
from motionvm.source.diagnostics import DiagnosticSink


def lex(text: str) -> tuple[list[tuple[str, object]], list[str]]:
    sink = DiagnosticSink()
    toks = tokenize("t.gdl", text, sink)
    shown = [(t.kind, t.value if t.kind in ("int", "string") else t.text) for t in toks[:-1]]
    errors = [f"{d.pos.line}:{d.pos.col}: {d.message}" for d in sink.errors()]
    return shown, errors


def test_string_split_over_two_and_three_lines() -> None:
    toks, errors = lex("'string split\n'onto two lines'\n'string split\n'onto three\n'lines'")
    assert errors == []
    assert toks == [
        ("string", "string splitonto two lines"),
        ("string", "string splitonto threelines"),
    ]


def test_string_continuation_may_be_indented_with_spaces() -> None:
    assert lex("'abc\n   'def'") == ([("string", "abcdef")], [])


def test_string_continuation_rejects_other_characters_before_the_quote() -> None:
    _, errors = lex("'abc\nx 'def'")
    assert errors[0].startswith("1:1: unterminated string: a string continued on the next line")


def test_string_continuation_needs_the_quote() -> None:
    _, errors = lex("'abc\ndef'")
    assert errors[0].startswith("1:1: unterminated string")


def test_tab_in_string_is_one_space() -> None:
    assert lex("'A\tB'") == ([("string", "A B")], [])


def test_string_length_limit_is_40() -> None:
    assert lex("'" + "x" * 40 + "'")[1] == []
    assert lex("'" + "x" * 41 + "'")[1] == ["1:1: string has 41 characters, more than the limit 40"]


def test_empty_string_and_bar_inside_string() -> None:
    assert lex("'' 'x|y|z'")[0] == [("string", ""), ("string", "x|y|z")]


def test_comment_is_a_separator_anywhere() -> None:
    toks, errors = lex("CONSTANT$STATUS |set power| OF main_motor = ENABLED;")
    assert errors == []
    assert [t[1] for t in toks] == ["CONSTANT$STATUS", "OF", "main_motor", "=", "ENABLED", ";"]


def test_comments_do_not_nest() -> None:
    assert lex("|a |b| c|") == ([("ident", "b")], [])


def test_comment_spans_lines_and_holds_any_character() -> None:
    toks, errors = lex("|line one\n ~ é 'q' \n|x")
    assert errors == [] and toks == [("ident", "x")]


def test_unterminated_comment() -> None:
    assert lex("x |oops")[1] == ["1:3: unterminated comment: no closing vertical bar"]


@pytest.mark.parametrize(
    ("text", "delims"),
    [
        ("a <= b", ["<="]),
        ("a < = b", ["<", "="]),
        ("a <\n= b", ["<", "="]),
        ("a <||= b", ["<", "="]),
        ("a <> b", ["<>"]),
        ("a >= b", [">="]),
        ("a => b", ["=", ">"]),
    ],
)
def test_double_delimiters_only_when_written_together(text: str, delims: list[str]) -> None:
    toks, errors = lex(text)
    assert errors == []
    assert [t[1] for t in toks if t[0] == "delim"] == delims


def test_numbers() -> None:
    assert lex("999999999") == ([("int", 999999999)], [])
    assert lex("-5")[0] == [("delim", "-"), ("int", 5)]
    assert lex("007")[0] == [("int", 7)]
    assert lex("1000000000")[1] == [
        "1:1: integer constant 1000000000 is beyond the GDL integer range: at most 999999999 "
        "(9 digits)"
    ]


def test_leading_zeros_do_not_count_toward_the_range() -> None:
    assert lex("0000000007") == ([("int", 7)], [])
    assert lex("000000000999999999") == ([("int", 999999999)], [])
    assert lex("0001000000000")[1] == [
        "1:1: integer constant 0001000000000 is beyond the GDL integer range: at most "
        "999999999 (9 digits)"
    ]


def test_a_constant_of_thousands_of_digits_is_an_error_not_a_crash() -> None:
    toks, errors = lex("9" * 5000 + " 1")
    assert errors == [
        "1:1: integer constant 999999999999... (5000 digits) is beyond the GDL integer "
        "range: at most 999999999 (9 digits)"
    ]
    assert [t[0] for t in toks] == ["int", "int"]


def test_no_reals() -> None:
    assert lex("1.5")[1] == [
        ("1:2: character '.' not accepted: GDL has no real numbers, only integers")
    ]


def test_digits_followed_by_letters() -> None:
    assert lex("1axis")[1] == [
        (
            "1:1: '1axis': a number cannot be followed by letters, and a "
            "name cannot start with a digit"
        )
    ]


def test_identifiers() -> None:
    assert lex("_axis_1") == ([("ident", "_axis_1")], [])
    assert lex("a" * 40)[1] == []
    assert lex("a" * 41)[1] == [
        ("1:1: identifier 'aaaaaaaaaaaa...' has 41 characters, more than the limit 40")
    ]


def test_keywords_are_case_insensitive() -> None:
    assert lex("if Status of x")[0] == [
        ("keyword", "IF"),
        ("keyword", "STATUS"),
        ("keyword", "OF"),
        ("ident", "x"),
    ]


def test_dollar_word_must_be_reserved() -> None:
    _, errors = lex("my$var STEPPER$MOTER")
    assert errors[0] == "1:1: unknown reserved word 'my$var': only reserved words contain '$'"
    assert errors[1] == (
        "1:8: unknown reserved word 'STEPPER$MOTER': only reserved words "
        "contain '$' (did you mean 'STEPPER$MOTOR'?)"
    )


@pytest.mark.parametrize("char", ["@", "#", ".", ":", "!", "%", '"', "`", "?", "~"])
def test_characters_not_accepted(char: str) -> None:
    _, errors = lex(f"a {char} b")
    assert len(errors) == 1 and errors[0].startswith("1:3: character")


def test_characters_outside_the_set_allowed_in_strings_and_comments() -> None:
    assert lex("'@#:!' |@#:!|")[1] == []


def test_positions_count_lines_and_columns() -> None:
    sink = DiagnosticSink()
    toks = tokenize("t.gdl", "MODULE m;\n  |c|  x\n'a\n 'b' y", sink)
    assert [(t.text, t.pos.line, t.pos.col) for t in toks[:-1]] == [
        ("MODULE", 1, 1),
        ("m", 1, 8),
        (";", 1, 9),
        ("x", 2, 8),
        ("ab", 3, 1),
        ("y", 4, 6),
    ]


def test_positions_after_comments_over_lines_and_at_an_unclosed_one() -> None:
    sink = DiagnosticSink()
    toks = tokenize("t.gdl", "a |one\ntwo\n  three| b\r\n\t c |open\nnever\n", sink)
    assert [(t.kind, t.pos.line, t.pos.col) for t in toks] == [
        ("ident", 1, 1),
        ("ident", 3, 10),
        ("ident", 4, 3),
        ("eof", 6, 1),
    ]
    assert [f"{d.pos.line}:{d.pos.col}" for d in sink.errors()] == ["4:5"]
