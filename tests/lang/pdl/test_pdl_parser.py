"""PDL parser: every statement form of the manual, the AST dump, limits and robustness."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from motionvm.lang.pdl import compile_front
from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.dump import dump_ast
from motionvm.lang.pdl.parser import MAX_NESTING, MAX_PAREN_DEPTH, parse
from motionvm.lang.pdl.preprocess import preprocess
from motionvm.source import DiagnosticSink

MANUAL = Path(__file__).parents[2] / "programs" / "pdl" / "manual"


def parse_text(text: str) -> tuple[n.Program, list[str]]:
    sink = DiagnosticSink()
    program, _ = parse(preprocess("mem/p.pdl", sink, text), sink)
    return program, [f"{d.pos.line}:{d.pos.col}: {d.message}" for d in sink.errors()]


def one(text: str) -> n.Item:
    program, errors = parse_text(text)
    assert errors == []
    assert len(program.items) == 1, program.items
    return program.items[0]


def test_declarations() -> None:
    d = one("#float _ro _lp(-0.5, 0.5) pgain, *pf, tab[20];")
    assert isinstance(d, n.VarDecl) and d.type == "float" and d.read_only
    assert d.limits is not None and (d.limits[0].value, d.limits[1].value) == (-0.5, 0.5)
    assert [(i.name, i.size, i.pointer) for i in d.items] == [
        ("pgain", None, False),
        ("pf", None, True),
        ("tab", 20, False),
    ]


def test_task_directive_and_label() -> None:
    program, errors = parse_text("#task/2;\n_entry: halt;")
    assert errors == []
    assert program.items == (
        n.TaskDirective(program.items[0].pos, 2),
        n.Label(program.items[1].pos, "_entry"),
        n.Simple(program.items[2].pos, "halt"),
    )


@pytest.mark.parametrize(
    ("text", "value_type"),
    [
        ("v = w;", n.VarRef),
        ("v = 5;", n.IntConst),
        ("v = -5;", n.IntConst),
        ("v = {1, 2, -3};", n.InitList),
        ('v = "abcd";', n.StringConst),
        ("v = -w;", n.Neg),
        ("v = <x_run>;", n.AngleRef),
        ("v = <_label>;", n.AngleRef),
        ("v = w @ 3;", n.BinOp),
        ("v = max(a, 3);", n.FuncCall),
        ("v = sttovar s1 & ~s2;", n.SttoVar),
        ("v = sizeof(arr);", n.SizeOf),
        ("p = &v[3];", n.AddressOf),
        ("v = *p[2];", n.Deref),
        ("v = 0.5 * w;", n.BinOp),
    ],
)
def test_assignment_forms(text: str, value_type: type) -> None:
    a = one(text)
    assert isinstance(a, n.Assign) and a.op == "=" and isinstance(a.value, value_type)


@pytest.mark.parametrize("op", ["+=", "-=", "*=", "/=", "%=", "&=", "|=", "@="])
def test_compound_assignment(op: str) -> None:
    a = one(f"x {op} y;")
    assert isinstance(a, n.Assign) and a.op == op


def test_state_assignment_is_form_8() -> None:
    a = one("OUT1 = IN1 & ~IN2;")
    assert isinstance(a, n.StateAssign) and isinstance(a.cond, n.Logic)


def test_auto_increment_and_indirection_targets() -> None:
    a = one("myar1[n+]=myar2[p+];")
    assert isinstance(a, n.Assign)
    assert a.target == n.VarRef(a.target.pos, "myar1", n.VarRef(a.target.index.pos, "n"), True)
    assert isinstance(a.value, n.VarRef) and a.value.auto_inc
    b = one("*pv[n]=50;")
    assert isinstance(b, n.Assign) and isinstance(b.target, n.Deref) and b.target.name == "pv"


@pytest.mark.parametrize("text", ["myvar ++;", "myvar [4]++;", "*po++;", "*po[n]--;"])
def test_increment_and_decrement(text: str) -> None:
    assert isinstance(one(text), n.IncDec)


def test_flow_commands() -> None:
    program, errors = parse_text(
        "goto l1; goto tab[2]; goto tab[i]; call sub; ret; halt; exitproc; lock; unlock;"
        "kill 2; kill t; wait 20; Sleep ar[x];"
    )
    assert errors == []
    assert [type(i).__name__ for i in program.items] == [
        "Goto",
        "Goto",
        "Goto",
        "CallLabel",
        "Simple",
        "Simple",
        "Simple",
        "Simple",
        "Simple",
        "Kill",
        "Kill",
        "Delay",
        "Delay",
    ]
    assert program.items[1].index == n.IntConst(program.items[1].index.pos, 2)


def test_blocks() -> None:
    program, errors = parse_text(
        "loop(nk) do loop(100) do x=1; end; end;\n"
        "if (a>1) do x=1; else do x=2; end;\n"
        "if(var1>var2) do var3=var1; else do var3=var2; end;\n"
        "if (a>1) call f;\n"
        "while (a < 5) do a += 1; end;\n"
        "till (x_home | t0 TOUT 60000);\n"
    )
    assert errors == []
    loop, if1, _if2, if3, wh, till = program.items
    assert isinstance(loop, n.Loop) and isinstance(loop.body[0], n.Loop)
    assert isinstance(if1, n.If) and if1.else_body is not None and not if1.single
    assert isinstance(if3, n.If) and if3.single and isinstance(if3.then_body[0], n.CallLabel)
    assert isinstance(wh, n.While) and isinstance(till, n.Till)
    assert isinstance(till.cond, n.Logic) and till.cond.ops == ("|",)
    assert isinstance(till.cond.terms[1], n.Relation) and till.cond.terms[1].op == "TOUT"


def test_condition_forms() -> None:
    c = one("if ((s2 & ~s3) | (~s2 & s3) | ~(v1 TOUT v2) | <st> | ~<st> | v->3) x = 1;")
    assert isinstance(c, n.If) and isinstance(c.cond, n.Logic)
    kinds = [type(t).__name__ for t in c.cond.terms]
    assert kinds == ["Logic", "Logic", "Not", "StateTest", "Not", "BitTest"]


def test_and_or_are_left_to_right_with_a_warning_when_mixed() -> None:
    sink = DiagnosticSink()
    program, _ = parse(preprocess("mem/w.pdl", sink, "till (a>1 & b>2 | c>3);"), sink)
    cond = program.items[0].cond
    assert isinstance(cond, n.Logic) and cond.ops == ("&", "|") and len(cond.terms) == 3
    assert [d.severity for d in sink.items] == ["warning"]


def test_procedures() -> None:
    program, errors = parse_text(
        "proc mul( float a, long b, float * res);\n"
        "proc func(long v1, float f2, instate run) do #long t; exitproc; end;\n"
        "mul(f1, 20, &m);\n"
    )
    assert errors == []
    proto, pdef, call = program.items
    assert isinstance(proto, n.ProcProto)
    assert [(p.type, p.name, p.pointer) for p in proto.params] == [
        ("float", "a", False),
        ("long", "b", False),
        ("float", "res", True),
    ]
    assert isinstance(pdef, n.ProcDef) and pdef.params[2].type == "instate"
    assert isinstance(call, n.ProcCall) and isinstance(call.args[2], n.AddressOf)


def test_print_commands_and_modes() -> None:
    program, errors = parse_text(
        'printl / 00000103 / 00000001 (" This is a test");\n'
        'printl/103("x=%ld %s ", x, ar[0]);\n'
        'prints("plain");\n'
        'retprintl/aBc("done %d ", IN1);\n'
        'printl/1f0/ffffffff("m");\n'
    )
    assert errors == []
    assert [(p.command, p.mode1, p.mode2, p.format.value, len(p.args)) for p in program.items] == [
        ("printl", 0x103, 1, " This is a test", 0),
        ("printl", 0x103, 0, "x=%ld %s ", 2),
        ("prints", 0, 0, "plain", 0),
        ("retprintl", 0xABC, 0, "done %d ", 1),
        ("printl", 0x1F0, 0xFFFFFFFF, "m", 0),
    ]


def test_set_state_commands() -> None:
    program, errors = parse_text("seton vacum_sl; setoff <a1>; toggle OUT2;")
    assert errors == []
    assert [(s.command, type(s.target).__name__) for s in program.items] == [
        ("seton", "VarRef"),
        ("setoff", "AngleRef"),
        ("toggle", "VarRef"),
    ]


def test_dump_ast() -> None:
    program, _ = parse_text("#long a[3];\nloop(2) do a[1]++; end;\nif (IN1) a = <x_run>;")
    assert (
        dump_ast(program)
        == """\
Program @1:1
  items:
    VarDecl @1:1 type='long'
      items:
        DeclItem @1:7 name='a' size=3
    Loop @2:1
      count: IntConst @2:6 value=2
      body:
        IncDec @2:12 op='++'
          target: VarRef @2:12 name='a'
            index: IntConst @2:14 value=1
    If @3:1 single=True
      cond: StateTest @3:5
        ref: VarRef @3:5 name='IN1'
      then_body:
        Assign @3:10 op='='
          target: VarRef @3:10 name='a'
          value: AngleRef @3:14 name='x_run'
"""
    )


def _nested_loops(depth: int) -> str:
    return "#long x;\n" + "loop(2) do\n" * depth + "x = 1;\n" + "end;\n" * depth


def test_nesting_depth_200_is_allowed() -> None:
    sink = DiagnosticSink()
    assert compile_front("mem/deep.pdl", sink=sink, text=_nested_loops(MAX_NESTING)) is not None


def test_nesting_depth_201_is_an_error() -> None:
    sink = DiagnosticSink()
    assert compile_front("mem/deep.pdl", sink=sink, text=_nested_loops(MAX_NESTING + 1)) is None
    assert [(d.pos.line, d.pos.col, d.message) for d in sink.items] == [
        (202, 1, "blocks nested more than 200 deep (if/else, while and loop count together)")
    ]


def test_very_deep_nesting_does_not_crash() -> None:
    sink = DiagnosticSink()
    assert compile_front("mem/deeper.pdl", sink=sink, text=_nested_loops(5000)) is None
    assert len(sink.errors()) == 1


def test_deep_parentheses() -> None:
    ok = "#long a;\ntill (" + "(" * MAX_PAREN_DEPTH + "a>1" + ")" * MAX_PAREN_DEPTH + ");"
    assert compile_front("mem/par.pdl", sink=DiagnosticSink(), text=ok) is not None
    sink = DiagnosticSink()
    bad = "#long a;\ntill (" + "(" * 5000 + "a>1" + ")" * 5000 + ");"
    assert compile_front("mem/par.pdl", sink=sink, text=bad) is None
    assert sink.errors()[0].message == f"parentheses nested more than {MAX_PAREN_DEPTH} deep"


def test_long_condition_chain_is_flat() -> None:
    text = "#long a;\ntill (" + " & ".join(["a>1"] * 3000) + ");"
    program = compile_front("mem/chain.pdl", sink=DiagnosticSink(), text=text)
    assert program is not None and len(program.items[1].cond.terms) == 3000


# ---------------------------------------------------------------- robustness

VOCAB = [
    "#long",
    "#short",
    "#float",
    "#task",
    "/",
    "2",
    ";",
    ":",
    ",",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    "=",
    "+=",
    "@=",
    "++",
    "--",
    "+",
    "-",
    "*",
    "&",
    "|",
    "~",
    "<",
    ">",
    "<=",
    "<>",
    "->",
    "x",
    "y",
    "arr",
    "p",
    "IN1",
    "x_run",
    "fclk",
    "_lbl",
    "lbl",
    "0",
    "7",
    "0x1F",
    "2.5",
    '"s',
    '%d"',
    "if",
    "else",
    "do",
    "end",
    "loop",
    "while",
    "till",
    "goto",
    "call",
    "ret",
    "halt",
    "proc",
    "long",
    "float",
    "instate",
    "exitproc",
    "printl/103",
    "seton",
    "sttovar",
    "sizeof",
    "max",
    "TOUT",
    "wait",
    "sleep",
    "kill",
    "lock",
    "#define",
    "#ifdef",
    "#endif",
    "#undef",
    "\\\n",
    "\n",
]


def _compile_never_raises(text: str) -> None:
    sink = DiagnosticSink()
    result = compile_front("mem/fuzz.pdl", sink=sink, text=text)
    assert result is not None or sink.has_errors


@settings(max_examples=400, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from(VOCAB), max_size=60))
def test_fuzz_token_soup(words: list[str]) -> None:
    _compile_never_raises(" ".join(words))


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.text(max_size=200))
def test_fuzz_random_text(text: str) -> None:
    _compile_never_raises(text)


@pytest.mark.parametrize("path", sorted(MANUAL.glob("*.pdl")), ids=lambda p: p.name)
def test_truncated_manual_examples(path: Path) -> None:
    text = path.read_text()
    for cut in range(0, len(text), 7):
        _compile_never_raises(text[:cut])


def test_every_parse_method_documents_its_grammar() -> None:
    import inspect

    from motionvm.lang.pdl import parser as parser_module
    from motionvm.lang.pdl.dump import dump_grammar

    lines = inspect.getsource(parser_module).splitlines()
    for i, line in enumerate(lines):
        if line.lstrip().startswith(("def _parse_", "def parse_program")):
            assert "# BNF:" in lines[i - 1], line
    grammar = dump_grammar()
    assert grammar.startswith("program = { top_item } EOF\n")
    assert 'cond = cterm { ( "&" | "|" ) cterm }\n' in grammar
