"""HMPL lexer: every token class, literal values, positions, and lexical errors."""

from __future__ import annotations

import pytest

from motionvm.lang.hmpl.lexer import lex_fragment, scan, tokenize
from motionvm.source import DiagnosticSink, SourceFile, SourcePos


def lex(text: str) -> tuple[list, list[str]]:
    sink = DiagnosticSink()
    toks = tokenize(SourceFile.register("lex.hmpl", text), sink)
    return toks, [d.headline() for d in sink.items]


def kinds(text: str) -> list[tuple[str, str]]:
    toks, errors = lex(text)
    assert errors == []
    return [(t.kind, t.text) for t in toks[:-1]]


def one(text: str):
    toks, errors = lex(text)
    assert errors == []
    assert len(toks) == 2, toks
    return toks[0]


def test_names_and_keywords():
    assert kinds("int x _AUTORUN_ uint8_t Timer _a1 while") == [
        ("keyword", "int"),
        ("name", "x"),
        ("keyword", "_AUTORUN_"),
        ("keyword", "uint8_t"),
        ("name", "Timer"),
        ("name", "_a1"),
        ("keyword", "while"),
    ]


@pytest.mark.parametrize(
    "text, value, suffix",
    [
        ("0", 0, ""),
        ("42", 42, ""),
        ("0x1F", 31, ""),
        ("0XffU", 255, "u"),
        ("017", 15, ""),
        ("0b101", 5, ""),
        ("10u", 10, "u"),
        ("10L", 10, "l"),
        ("10ul", 10, "ul"),
        ("10LU", 10, "ul"),
        ("10ll", 10, "ll"),
        ("10ULL", 10, "ull"),
        ("10llu", 10, "ull"),
        ("18446744073709551615", 2**64 - 1, ""),
    ],
)
def test_integer_constants(text, value, suffix):
    t = one(text)
    assert (t.kind, t.value, t.suffix) == ("int", value, suffix)


@pytest.mark.parametrize(
    "text, value, suffix",
    [
        ("1.0", 1.0, ""),
        (".5", 0.5, ""),
        ("1.", 1.0, ""),
        ("1e3", 1000.0, ""),
        ("1E-3", 0.001, ""),
        ("2.5e+2", 250.0, ""),
        ("1.5f", 1.5, "f"),
        ("1.5F", 1.5, "f"),
        ("08.5", 8.5, ""),
        ("3.14159265358979323846", 3.141592653589793, ""),
    ],
)
def test_floating_constants(text, value, suffix):
    t = one(text)
    assert (t.kind, t.value, t.suffix) == ("float", value, suffix)


@pytest.mark.parametrize(
    "text, value",
    [
        ("'a'", 97),
        ("'\\n'", 10),
        ("'\\t'", 9),
        ("'\\0'", 0),
        ("'\\\\'", 92),
        ("'\\''", 39),
        ("'\\\"'", 34),
        ("'\"'", 34),
        ("'\\x41'", 65),
        ("'\\101'", 65),
        ("'\\xff'", -1),
        ("'\\200'", -128),
    ],
)
def test_char_constants(text, value):
    t = one(text)
    assert (t.kind, t.value) == ("char", value)


def test_string_literals_and_escapes():
    t = one(r'"a\tb\n\\\"\x41\101\0z"')
    assert t.kind == "string"
    assert t.value == b'a\tb\n\\"AA\x00z'
    assert one('"中文"').value == "中文".encode()
    assert one('""').value == b""
    assert one('"it\'s"').value == b"it's"


def test_adjacent_strings_stay_separate_tokens():
    assert kinds('"a" "b"') == [("string", '"a"'), ("string", '"b"')]


def test_all_punctuators_longest_match():
    text = (
        "... <<= >>= -> ++ -- << >> <= >= == != && || *= /= %= += -= &= ^= |= ## "
        "[ ] ( ) { } . & * + - ~ ! / % < > ^ | ? : ; = , #"
    )
    assert [t for _, t in kinds(text)] == text.split()
    assert [t for _, t in kinds("a+++b")] == ["a", "++", "+", "b"]
    assert [t for _, t in kinds("x->y")] == ["x", "->", "y"]
    assert [t for _, t in kinds("a<<=b>>c")] == ["a", "<<=", "b", ">>", "c"]


def test_comments_are_skipped_and_lines_counted():
    toks, errors = lex("a // one\n/* two\nthree */ b /**/c\n// last")
    assert errors == []
    assert [(t.text, t.pos.line, t.pos.col) for t in toks[:-1]] == [
        ("a", 1, 1),
        ("b", 3, 10),
        ("c", 3, 16),
    ]


def test_columns_after_continued_lines_and_multi_line_literals():
    # the lexer counts a line's columns from the last newline it met: a line continuation
    # or an escaped newline inside a string literal starts a line as a newline token does
    toks, errors = lex("a \\\n  b \"x\\\ny\" c\n 1.5 'q' /* \n */ d")
    assert errors == []
    assert [(t.text, t.pos.line, t.pos.col) for t in toks[:-1]] == [
        ("a", 1, 1),
        ("b", 2, 3),
        ('"x\\\ny"', 2, 5),
        ("c", 3, 4),
        ("1.5", 4, 2),
        ("'q'", 4, 6),
        ("d", 5, 5),
    ]


def test_positions_count_columns_from_one():
    toks, _ = lex("int  x=1;\n\tfoo ( );")
    assert [(t.text, t.pos.line, t.pos.col) for t in toks[:-1]] == [
        ("int", 1, 1),
        ("x", 1, 6),
        ("=", 1, 7),
        ("1", 1, 8),
        (";", 1, 9),
        ("foo", 2, 2),
        ("(", 2, 6),
        (")", 2, 8),
        (";", 2, 9),
    ]
    assert toks[-1].kind == "eof"
    assert toks[-1].pos == SourcePos("lex.hmpl", 2, 10)


def test_unicode_blanks_are_white_space():
    assert kinds("\ufeffint\u00a0x\u3000;") == [("keyword", "int"), ("name", "x"), ("punct", ";")]


def test_chinese_comments():
    assert kinds("x = 1; // 當前 task ID\n/* 註解 */ y") == [
        ("name", "x"),
        ("punct", "="),
        ("int", "1"),
        ("punct", ";"),
        ("name", "y"),
    ]


@pytest.mark.parametrize(
    "text, message",
    [
        ('x = "abc;\ny', "lex.hmpl:1:5: error: unterminated string literal"),
        ("/* never closed\n int x;", "lex.hmpl:1:1: error: unterminated comment"),
        ("'a", "lex.hmpl:1:1: error: unterminated character constant"),
        ("''", "lex.hmpl:1:1: error: empty character constant"),
        ("'ab'", "lex.hmpl:1:1: error: character constant 'ab' holds more than one byte"),
        ("12abc", "lex.hmpl:1:1: error: invalid suffix 'abc' on integer constant"),
        ("1.5q", "lex.hmpl:1:1: error: invalid suffix 'q' on floating constant"),
        ("10lul", "lex.hmpl:1:1: error: invalid suffix 'lul' on integer constant"),
        ("10lL", "lex.hmpl:1:1: error: invalid suffix 'lL' on integer constant"),
        ("1f", "lex.hmpl:1:1: error: invalid suffix 'f' on integer constant"),
        ("089", "lex.hmpl:1:1: error: invalid digit '8' in octal constant"),
        ("1e", "lex.hmpl:1:1: error: invalid numeric constant '1e'"),
        ("  @", "lex.hmpl:1:3: error: stray '@' in program"),
        ("x$", "lex.hmpl:1:2: error: stray '$' in program"),
        (
            "x = 1；",
            (
                "lex.hmpl:1:6: error: stray '；' in program "
                "(a full-width character; did you mean ';'?)"
            ),
        ),
        ('"\\q"', "lex.hmpl:1:1: error: unknown escape sequence '\\q'"),
        ('"\\x100"', "lex.hmpl:1:1: error: hex escape sequence '\\x100' out of range"),
        (
            "99999999999999999999",
            (
                "lex.hmpl:1:1: error: integer constant '99999999999999999999' is too large "
                "(the limit is 18446744073709551615)"
            ),
        ),
    ],
)
def test_lexical_errors(text, message):
    _, errors = lex(text)
    assert errors[0] == message


def test_lexing_continues_after_an_error():
    toks, errors = lex("a @ b")
    assert [t.text for t in toks[:-1]] == ["a", "b"]
    assert len(errors) == 1


def test_scan_marks_directive_lines():
    sc = scan(SourceFile("d.hmpl", "#define A 1 \\\n  + 2\nx # y\n  # if A\nz"))
    texts = [t.text for t in sc.tokens]
    ranges = [texts[a:b] for a, b in sc.directives]
    assert ranges == [["#", "define", "A", "1", "+", "2"], ["#", "if", "A"]]
    assert sc.errors == []


def test_scan_holds_errors_back():
    sc = scan(SourceFile("e.hmpl", "a\n'oops\n"))
    assert [(p.line, msg, always) for p, msg, always in sc.errors] == [
        (2, "unterminated character constant", False)
    ]


def test_lex_fragment():
    pos = SourcePos("f.hmpl", 3, 4)
    toks = lex_fragment("x1", pos)
    assert toks is not None and [(t.kind, t.text, t.pos) for t in toks] == [("name", "x1", pos)]
    assert lex_fragment('"abc', pos) is None


def test_too_many_errors_do_not_escape():
    toks, errors = lex("@ " * 50 + "x")
    assert len(errors) == 20 and toks[-2].text == "x"


def test_dots_and_slashes_where_punctuators_meet_numbers_and_comments():
    # the one-character punctuators are tried before numbers and comments: a `.` before
    # a digit still starts a number, a `/` before `/` or `*` still starts a comment
    assert kinds("a..5 x.y .5") == [
        ("name", "a"),
        ("punct", "."),
        ("float", ".5"),
        ("name", "x"),
        ("punct", "."),
        ("name", "y"),
        ("float", ".5"),
    ]
    assert [t for _, t in kinds("a/b/=c/*d*/e//f\ng...h")] == [
        "a", "/", "b", "/=", "c", "e", "g", "...", "h",
    ]  # fmt: skip


def test_scan_collects_the_texts_of_names_and_keywords():
    sc = scan(SourceFile("n.hmpl", 'int x = y1 + 2; /* zz */ "s" while\n#define Q 1\n'))
    assert sc.names == {"int", "x", "y1", "while", "define", "Q"}
