"""HMPL preprocessor: macros, conditionals, includes, _TASKID_, and their errors."""

from __future__ import annotations

import pytest

from motionvm.lang.hmpl.preprocess import preprocess
from motionvm.source import DiagnosticSink, SourcePos


def pp(text: str, task_id: int = 0, path: str = "pp.hmpl") -> tuple[str, list[str]]:
    sink = DiagnosticSink()
    toks = preprocess(path, task_id=task_id, sink=sink, text=text)
    assert toks[-1].kind == "eof"
    return " ".join(t.text for t in toks[:-1]), [d.headline() for d in sink.errors()]


def ok(text: str, task_id: int = 0) -> str:
    out, errors = pp(text, task_id)
    assert errors == []
    return out


def test_object_like_macro():
    assert ok("#define N 10\nint a[N];") == "int a [ 10 ] ;"


def test_function_like_macro_and_parenthesised_args():
    assert ok("#define MAX(a, b) ((a) > (b) ? (a) : (b))\nMAX(f(1, 2), y)") == (
        "( ( f ( 1 , 2 ) ) > ( y ) ? ( f ( 1 , 2 ) ) : ( y ) )"
    )


def test_function_like_name_without_call_is_left_alone():
    assert ok("#define F(x) x\nF + F(1)") == "F + 1"


def test_space_before_paren_makes_object_like():
    assert ok("#define F (x) x\nF(1)") == "( x ) x ( 1 )"


def test_macro_call_may_span_lines():
    assert ok("#define ADD(a, b) a + b\nADD(1,\n  2);") == "1 + 2 ;"


def test_stringize():
    assert ok('#define S(x) #x\nS(a  +  "b\\n")') == '"a + \\"b\\\\n\\""'
    sink = DiagnosticSink()
    toks = preprocess("s.hmpl", task_id=0, sink=sink, text='#define S(x) #x\nS(a "q")')
    assert toks[0].kind == "string" and toks[0].value == b'a "q"'


def test_token_paste_and_placemarkers():
    assert ok("#define CAT(a, b) a ## b\nCAT(x, 1) CAT(, y) CAT(z, ) CAT(1, 2)") == "x1 y z 12"
    assert ok("#define CAT3(a, b, c) a ## b ## c\nCAT3(p, q, r)") == "pqr"


def test_paste_result_is_rescanned():
    assert ok("#define AB 42\n#define CAT(a, b) a ## b\nCAT(A, B)") == "42"


def test_paste_of_arguments_does_not_expand_them_first():
    assert ok("#define N 1\n#define CAT(a, b) a ## b\nCAT(N, 2)") == "N2"


def test_arguments_are_expanded_before_substitution():
    assert ok("#define N 3\n#define ID(x) x\nID(N)") == "3"


def test_variadic_macro():
    assert ok('#define LOG(fmt, ...) Print(fmt, __VA_ARGS__)\nLOG("%d %d", 1, 2)') == (
        'Print ( "%d %d" , 1 , 2 )'
    )
    assert ok("#define V(...) f(__VA_ARGS__)\nV() V(a, (b, c))") == "f ( ) f ( a , ( b , c ) )"


def test_line_continuation_in_define():
    assert ok("#define LONG 1 + \\\n   2\nLONG") == "1 + 2"


def test_undef():
    assert ok("#define A 1\n#undef A\nA") == "A"


def test_recursion_is_guarded_as_in_c():
    assert ok("#define foo foo + 1\nfoo") == "foo + 1"
    assert ok("#define A B\n#define B A\nA B") == "A B"
    assert ok("#define f(x) x + f(x)\nf(2)") == "2 + f ( 2 )"


def test_c_standard_rescanning_example():
    # C11 6.10.3.5: f(2)(9) with f(a) = a*g and g(a) = f(a)
    assert ok("#define f(a) a*g\n#define g(a) f(a)\nf(2)(9)") == "2 * 9 * g"


def test_nested_macro_calls_in_arguments():
    text = "#define SQ(x) ((x) * (x))\n#define TWICE(x) (2 * (x))\nTWICE(SQ(TWICE(3)))"
    assert ok(text) == "( 2 * ( ( ( ( 2 * ( 3 ) ) ) * ( ( 2 * ( 3 ) ) ) ) ) )"


def test_bit_macros_of_manual_22_3():
    text = (
        "#define BIT_SET(a, idx)      ((a) |= (1<<(idx)))\n"
        "#define BIT_CLEAR(a, idx)   ((a) &= ~(1<<(idx)))\n"
        "#define BIT_FLIP(a, idx)    ((a) ^= (1<<(idx)))\n"
        "#define BIT_CHECK(a, idx)   ((a) & (1<<(idx)))\n"
        "BIT_SET(v, 0); BIT_CLEAR(v, 1); BIT_FLIP(v, 2); BIT_CHECK(v, 3)"
    )
    assert ok(text) == (
        "( ( v ) |= ( 1 << ( 0 ) ) ) ; ( ( v ) &= ~ ( 1 << ( 1 ) ) ) ; "
        "( ( v ) ^= ( 1 << ( 2 ) ) ) ; ( ( v ) & ( 1 << ( 3 ) ) )"
    )


def test_expanded_tokens_carry_the_use_position():
    sink = DiagnosticSink()
    text = "#define INC(v) v += ONE\n#define ONE 1\n\n  INC(count);"
    toks = preprocess("p.hmpl", task_id=0, sink=sink, text=text)
    use = SourcePos("p.hmpl", 4, 3)
    assert [(t.text, t.pos) for t in toks[:-1]] == [
        ("count", SourcePos("p.hmpl", 4, 7)),  # an argument keeps where it was written
        ("+=", use),
        ("1", SourcePos("p.hmpl", 4, 12)),  # the last one ends where the use ends
        (";", SourcePos("p.hmpl", 4, 13)),
    ]


def test_taskid_is_predefined():
    assert ok("int t = _TASKID_;", task_id=7) == "int t = 7 ;"
    text = "#if _TASKID_ == 0\nint global_var = 0;\n#endif\nStopTask(_TASKID_);"
    assert ok(text, task_id=0) == "int global_var = 0 ; StopTask ( 0 ) ;"
    assert ok(text, task_id=3) == "StopTask ( 3 ) ;"


@pytest.mark.parametrize(
    "cond, taken",
    [
        ("1", True),
        ("0", False),
        ("1 + 2 * 3 == 7", True),
        ("(1 + 2) * 3 == 9", True),
        ("10 - 2 - 3 == 5", True),
        ("1 << 4 == 16", True),
        ("-1 < 0", True),
        ("~0 == -1", True),
        ("!0 && !!5", True),
        ("0 || 0", False),
        ("1 ? 0 : 1", False),
        ("0 ? 1 : 2 == 2", True),
        ("7 / 2 == 3 && -7 / 2 == -3 && -7 % 2 == -1", True),
        ("0x10 == 16 && 010 == 8 && 'A' == 65", True),
        ("1 | 2 ^ 3 & 4", True),
        ("UNKNOWN", False),
        ("UNKNOWN == 0", True),
        ("defined N", True),
        ("defined(N) && N == 5", True),
        ("defined X", False),
        ("!defined(X)", True),
        ("0 && 1 / 0", False),
        ("1 || 1 / 0", True),
    ],
)
def test_if_expressions(cond, taken):
    out = ok(f"#define N 5\n#if {cond}\nyes\n#else\nno\n#endif")
    assert out == ("yes" if taken else "no")


def test_ifdef_ifndef_elif_else_nesting():
    text = """
#define A
#ifdef A
  a1
  #ifndef B
    b0
    #if 0
      never
    #elif 1
      e1
    #else
      never
    #endif
  #else
    never
  #endif
#elif 1
  never
#else
  never
#endif
#if 0
  #if 1
    never
  #else
    never
  #endif
  #bogus directive in a skipped region is fine
#endif
tail
"""
    assert ok(text) == "a1 b0 e1 tail"


def test_errors_in_skipped_regions_are_not_reported():
    assert ok("#if 0\ndon't @ 'x\n#endif\nok") == "ok"


def test_include_relative_to_including_file(tmp_path):
    (tmp_path / "inc").mkdir()
    (tmp_path / "inc" / "defs.h").write_text('#include "more.h"\n#define SPEED 12.5\n')
    (tmp_path / "inc" / "more.h").write_text("int from_more;\n")
    main = tmp_path / "main.hmpl"
    main.write_text('#include "inc/defs.h"\ndouble v = SPEED;\n')
    sink = DiagnosticSink()
    toks = preprocess(str(main), task_id=0, sink=sink)
    assert sink.items == []
    assert " ".join(t.text for t in toks[:-1]) == "int from_more ; double v = 12.5 ;"
    assert toks[0].pos.file.endswith("more.h")
    assert toks[-1].pos.file == str(main)


def test_include_guard_pattern(tmp_path):
    (tmp_path / "g.h").write_text("#ifndef G_H\n#define G_H\nint g;\n#endif\n")
    main = tmp_path / "m.hmpl"
    main.write_text('#include "g.h"\n#include "g.h"\n')
    sink = DiagnosticSink()
    toks = preprocess(str(main), task_id=0, sink=sink)
    assert sink.items == []
    assert " ".join(t.text for t in toks[:-1]) == "int g ;"


def test_include_errors(tmp_path):
    (tmp_path / "a.h").write_text('#include "b.h"\n')
    (tmp_path / "b.h").write_text('#include "a.h"\n')
    main = tmp_path / "m.hmpl"
    main.write_text('#include "a.h"\n#include "missing.h"\n#include nothing\nint x;\n')
    sink = DiagnosticSink()
    toks = preprocess(str(main), task_id=0, sink=sink)
    messages = [d.message for d in sink.errors()]
    assert messages == [
        "recursive #include of 'a.h' (an include cycle)",
        "cannot open include file 'missing.h': No such file or directory",
        '#include expects "FILENAME"',
    ]
    assert " ".join(t.text for t in toks[:-1]) == "int x ;"


def test_include_depth_limit(tmp_path):
    for k in range(5):
        (tmp_path / f"h{k}.h").write_text(f'#include "h{k + 1}.h"\n')
    (tmp_path / "h5.h").write_text("int deep;\n")
    main = tmp_path / "m.hmpl"
    main.write_text('#include "h0.h"\n')
    sink = DiagnosticSink()
    preprocess(str(main), task_id=0, sink=sink, include_depth_limit=3)
    assert [d.message for d in sink.errors()] == ["#include nested 3 deep exceeds the limit 3"]
    sink = DiagnosticSink()
    toks = preprocess(str(main), task_id=0, sink=sink)
    assert sink.items == [] and toks[0].text == "int"


def test_missing_main_file(tmp_path):
    sink = DiagnosticSink()
    toks = preprocess(str(tmp_path / "nope.hmpl"), task_id=0, sink=sink)
    assert [t.kind for t in toks] == ["eof"]
    assert sink.errors()[0].message.startswith("cannot read ")


@pytest.mark.parametrize(
    "text, message",
    [
        ("#error stop: bad config", "pp.hmpl:1:1: error: #error stop: bad config"),
        (
            "#defien X 1",
            (
                "pp.hmpl:1:2: error: invalid preprocessing directive '#defien' "
                "(did you mean 'define'?)"
            ),
        ),
        ("#foo", "pp.hmpl:1:2: error: invalid preprocessing directive '#foo'"),
        ("#define", "pp.hmpl:1:2: error: macro name missing in #define"),
        ("#define 3 x", "pp.hmpl:1:9: error: macro names must be identifiers, not '3'"),
        ("#define defined 1", "pp.hmpl:1:9: error: 'defined' cannot be used as a macro name"),
        ("#define F(a, a) a", "pp.hmpl:1:14: error: duplicate macro parameter 'a'"),
        ("#define F(a b) a", "pp.hmpl:1:13: error: expected ',' or ')' in macro parameter list"),
        ("#define F(a", "pp.hmpl:1:11: error: missing ')' in macro parameter list"),
        ("#define F(1) a", "pp.hmpl:1:11: error: expected parameter name, found '1'"),
        ("#define F(a) #b", "pp.hmpl:1:14: error: '#' is not followed by a macro parameter"),
        (
            "#define F(a) ## a",
            "pp.hmpl:1:14: error: '##' cannot appear at either end of a macro expansion",
        ),
        (
            "#define F(a, b) a\nF(1)",
            "pp.hmpl:2:1: error: macro 'F' requires 2 arguments, only 1 given",
        ),
        (
            "#define F(a) a\nF(1, 2)",
            "pp.hmpl:2:1: error: macro 'F' requires 1 argument, but 2 given",
        ),
        (
            "#define F(a) a\nF(1, (2)",
            "pp.hmpl:2:1: error: unterminated argument list invoking macro 'F'",
        ),
        (
            "#define CAT(a, b) a ## b\nCAT(+, /)",
            "pp.hmpl:2:1: error: pasting '+' and '/' does not give a valid token",
        ),
        ("#if 1 / 0\n#endif", "pp.hmpl:1:7: error: division by zero in #if"),
        ("#if\n#endif", "pp.hmpl:1:2: error: #if with no expression"),
        ("#if (1\n#endif", "pp.hmpl:1:5: error: missing ')' in #if expression"),
        ("#if 1 2\n#endif", "pp.hmpl:1:7: error: missing binary operator before '2' in #if"),
        ("#if 1.5\n#endif", "pp.hmpl:1:5: error: floating constant in preprocessor expression"),
        ('#if "s"\n#endif', "pp.hmpl:1:5: error: token '\"s\"' is not valid in #if expressions"),
        ("#if 1 +\n#endif", "pp.hmpl:1:7: error: expected value in #if expression"),
        ("#if defined\n#endif", "pp.hmpl:1:5: error: operator 'defined' requires an identifier"),
        ("#if defined(X\n#endif", "pp.hmpl:1:5: error: missing ')' after 'defined'"),
        ("#ifdef\n#endif", "pp.hmpl:1:2: error: #ifdef expects a macro name"),
        ("#if 1\nx", "pp.hmpl:1:1: error: unterminated #if (no matching #endif)"),
        ("#endif", "pp.hmpl:1:1: error: #endif without #if"),
        ("#else", "pp.hmpl:1:1: error: #else without #if"),
        ("#if 1\n#else\n#elif 1\n#endif", "pp.hmpl:3:1: error: #elif after #else"),
        ("#if 1\n#else\n#else\n#endif", "pp.hmpl:3:1: error: #else after #else"),
        ("x 'a", "pp.hmpl:1:3: error: unterminated character constant"),
        ("#if 0\n/* open", "pp.hmpl:2:1: error: unterminated comment"),
    ],
)
def test_preprocessor_errors(text, message):
    _, errors = pp(text)
    assert errors and errors[0] == message


def test_redefinition_warns():
    sink = DiagnosticSink()
    preprocess("w.hmpl", task_id=0, sink=sink, text="#define A 1\n#define A 1\n#define A 2")
    assert [d.headline() for d in sink.items] == ["w.hmpl:3:9: warning: 'A' redefined"]


def test_pragma_and_null_directive_are_accepted():
    assert ok("#\n#pragma once\nx") == "x"


def test_macro_expansion_blowup_is_stopped():
    lines = ["#define M0 x"] + [f"#define M{k} M{k - 1} M{k - 1}" for k in range(1, 24)]
    _out, errors = pp("\n".join(lines) + "\nM23")
    assert errors == [
        "pp.hmpl:25:1: error: macro expansion of 'M23' needs more than 200000 macro expansions"
    ]


def test_crlf_line_ends():
    assert ok("#define A \\\r\n 1\r\nint x = A;\r\n") == "int x = 1 ;"


def test_c_standard_example_3():
    # C11 6.10.3.5 EXAMPLE 3, token for token
    text = r"""#define x 3
#define f(a) f(x * (a))
#undef x
#define x 2
#define g f
#define z z[0]
#define h g(~
#define m(a) a(w)
#define w 0,1
#define t(a) a
#define p() int
#define q(x) x
#define r(x,y) x ## y
#define str(x) # x
f(y+1) + f(f(z)) % t(t(g)(0) + t)(1);
g(x+(3,4)-w) | h 5) & m
(f)^m(m);
p() i[q()] = { q(1), r(2,3), r(4,), r(,5), r(,) };
char c[2][6] = { str(hello), str() };
"""
    expected = """f(2 * (y+1)) + f(2 * (f(2 * (z[0])))) % f(2 * (0)) + t(1);
f(2 * (2+(3,4)-0,1)) | f(2 * (~ 5)) & f(2 * (0,1))^m(0,1);
int i[] = { 1, 23, 4, 5, };
char c[2][6] = { "hello", "" };"""
    assert ok(text).replace(" ", "") == expected.replace(" ", "").replace("\n", "")


def test_c_standard_example_4_stringize_and_glue():
    text = r"""#define str(s) # s
#define xstr(s) str(s)
#define debug(s, t) printf("x" # s "= %d, x" # t "= %s", \
 x ## s, x ## t)
#define INCFILE(n) vers ## n
#define glue(a, b) a ## b
#define xglue(a, b) glue(a, b)
#define HIGHLOW "hello"
#define LOW LOW ", world"
debug(1, 2);
fputs(str(strncmp("abc\0d", "abc", '\4') // this goes away
 == 0), s);
xstr(INCFILE(2).h)
glue(HIGH, LOW);
xglue(HIGH, LOW)
"""
    assert ok(text).split(" ; ") == [
        'printf ( "x" "1" "= %d, x" "2" "= %s" , x1 , x2 )',
        'fputs ( "strncmp(\\"abc\\\\0d\\", \\"abc\\", \'\\\\4\') == 0" , s )',
        '"vers2.h" "hello"',
        '"hello" ", world"',
    ]


def test_line_renumbers_the_following_lines():
    sink = DiagnosticSink()
    toks = preprocess(
        "pp.hmpl", task_id=0, sink=sink, text='a\n#line 10\nb\nc\n#line 40 "x.c"\nd\n#line 7\ne'
    )
    assert sink.errors() == []
    where = {t.text: (t.pos.file, t.pos.line) for t in toks[:-1]}
    assert where == {
        "a": ("pp.hmpl", 1),
        "b": ("pp.hmpl", 10),
        "c": ("pp.hmpl", 11),
        "d": ("x.c", 40),
        "e": ("x.c", 7),  # a #line without a file name keeps the last one
    }
    assert toks[-1].pos.file == "x.c"


def test_line_and_file_macros_follow_line():
    out = ok('__LINE__ __FILE__\n#line 70 "y.c"\n#define L __LINE__\n\nL __FILE__')
    assert out == '1 "pp.hmpl" 72 "y.c"'


def test_line_and_file_macros_are_defined():
    assert (
        ok("#if defined(__LINE__) && __LINE__ == 1\na\n#endif\n#ifdef __FILE__\nb\n#endif") == "a b"
    )


def test_line_numbers_lexical_errors_and_later_directives():
    _, errors = pp("#line 100\n$\n#error stop")
    assert errors == [
        "pp.hmpl:100:1: error: stray '$' in program",
        "pp.hmpl:101:1: error: #error stop",
    ]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("#line", 'pp.hmpl:1:2: error: #line expects a line number (#line N or #line N "FILE")'),
        ("#line 0", "pp.hmpl:1:7: error: #line number 0 is outside [1, 2147483647]"),
        ("#line 2147483648", "pp.hmpl:1:7: error: #line number 2147483648 is outside"),
        ("#line 0x10", "pp.hmpl:1:7: error: #line expects a line number, not '0x10'"),
        ("#line -1", "pp.hmpl:1:7: error: #line expects a line number, not '-'"),
        ("#line 5 x", "pp.hmpl:1:9: error: #line expects a file name in quotes, not 'x'"),
        ('#line 5 ""', "pp.hmpl:1:9: error: #line file name is empty"),
        ('#line 5 "a" 1', "pp.hmpl:1:13: error: extra tokens at end of #line directive"),
    ],
)
def test_malformed_line_is_an_error(text, message):
    out, errors = pp(text + "\nx")
    assert len(errors) == 1 and errors[0].startswith(message), errors
    assert out == "x"


def test_a_file_without_macro_names_is_not_expanded(monkeypatch):
    """Regions of a file in which no name is a macro, `__LINE__` or `__FILE__` pass
    without the expansion pass (`Scan.names`); the others still expand."""
    from motionvm.lang.hmpl.preprocess import Preprocessor

    calls = []
    real = Preprocessor.expand

    def counted(self, toks, hs_map=None):
        calls.append(len(toks))
        return real(self, toks, hs_map)

    monkeypatch.setattr(Preprocessor, "expand", counted)
    assert ok("int a;\n#undef Z\nint b = 2;\nint c;") == "int a ; int b = 2 ; int c ;"
    assert calls == []
    assert ok("#define N 3\nint a[N];\nint b = __LINE__;") == "int a [ 3 ] ; int b = 3 ;"
    assert calls
    calls.clear()
    assert ok("int t = _TASKID_;", task_id=5) == "int t = 5 ;"
    assert calls


def test_a_keyword_defined_as_a_macro_is_expanded():
    assert ok("#define while if\nwhile (x) y;") == "if ( x ) y ;"
    assert ok("#define int long\nint a;") == "long a ;"
