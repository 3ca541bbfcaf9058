"""Source positions on generated Python: the placing walk (`lang/placing.py`) and the
positions of a few generated nodes of each language (a fault's line and column)."""

from __future__ import annotations

import ast

from motionvm.lang.gdl import compile_app
from motionvm.lang.gdl.lower import _by_file, lower_file
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.pdl.front import front_end
from motionvm.lang.pdl.lower import lower_program
from motionvm.lang.placing import PLACED, finish_locations, place
from motionvm.source.diagnostics import DiagnosticSink


def _where(node: ast.AST) -> tuple[int, int] | None:
    d = node.__dict__
    return (d["lineno"], d["col_offset"]) if "lineno" in d else None


def test_place_locates_what_has_no_location_and_skips_placed_statements() -> None:
    inner = place([ast.Assign([ast.Name("x", ast.Store())], ast.Constant(1))], 5, 4)
    assert inner[0].__dict__[PLACED]
    late = ast.Constant(2)  # slipped into a placed statement: a walk entering it stamps it
    inner[0].value = ast.BinOp(inner[0].value, ast.Add(), late)
    test = ast.Compare(ast.Name("y", ast.Load()), [ast.Lt()], [ast.Constant(3)])
    outer = ast.If(test, inner, [])
    assert place([outer], 4, 2) == [outer]
    assert [_where(x) for x in (outer, test, test.left, test.comparators[0])] == [(4, 2)] * 4
    assert _where(inner[0]) == _where(inner[0].targets[0]) == (5, 4)
    assert _where(late) is None  # the placed statement was not entered


def test_place_enters_a_located_node_it_did_not_mark() -> None:
    other = ast.Pass(lineno=9, col_offset=6)
    moved = ast.copy_location(ast.Assign([ast.Name("x", ast.Store())], ast.Constant(1)), other)
    place([ast.If(ast.Name("y", ast.Load()), [moved], [])], 4, 2)
    assert _where(moved) == (9, 6)
    assert _where(moved.targets[0]) == _where(moved.value) == (4, 2)


def test_finish_locations_gives_a_node_its_parents_place() -> None:
    placed = place([ast.Expr(ast.Name("a", ast.Load()))], 7, 3)
    late = ast.Name("b", ast.Load())
    placed[0].value = late
    body = [ast.Expr(ast.Call(ast.Name("f", ast.Load()), [], []))]
    fn = ast.FunctionDef("g", ast.arguments([], [], None, [], [], None, []), body, [], None)
    fn.lineno, fn.col_offset = 12, 0
    finish_locations(ast.Module([fn, *placed], []))
    assert [_where(x) for x in (body[0], body[0].value, body[0].value.func)] == [(12, 0)] * 3
    assert _where(late) is None


HMPL = """int total;
void main() {
    for (int i = 0; i < 3; i++) {
        if (i == 1)
            total = total + 10;
    }
    Print("%d", total);
}
"""


def _hmpl_nodes(bytecode: bool) -> list[ast.AST]:
    sink = DiagnosticSink()
    prog, mem = compile_tasks([TaskFile(0, "t.hmpl", HMPL)], sink, bytecode=bytecode)
    assert prog is not None, [d.headline() for d in sink.items]
    mem.release()
    return [x for _, mod in prog.modules for x in ast.walk(mod)]


def _first(nodes: list[ast.AST], cls: type, text: str) -> ast.AST:
    return next(x for x in nodes if type(x) is cls and ast.unparse(x).startswith(text))


def test_hmpl_generated_nodes_are_at_their_statements() -> None:
    nodes = _hmpl_nodes(bytecode=True)
    add = _first(nodes, ast.Assign, "g_total = g_total + 10")
    assert _where(add) == _where(add.targets[0]) == (5, 12)  # line 5, column 13
    assert _where(_first(nodes, ast.If, "if v_i == 1")) == (4, 8)
    assert _where(_first(nodes, ast.For, "for v_i in")) == (3, 4)
    printed = _first(nodes, ast.Expr, "b_Print(")
    assert _where(printed) == _where(printed.value.args[1]) == (7, 4)


def test_hmpl_check_leaves_the_nodes_it_lowers_unplaced() -> None:
    # a check keeps only its diagnostics: the initializers' function it lowers stays
    # without locations (its compile's `bytecode` is false), and a compile after it places
    checked = _hmpl_nodes(bytecode=False)
    assert any(type(x) is ast.Assign for x in checked)  # `g_total = 0`
    assert all(_where(x) is None for x in checked)
    assert _where(_first(_hmpl_nodes(bytecode=True), ast.Assign, "g_total = 0")) == (1, 4)


PDL = """#long total, i;
#task/0;
total = 0;
loop(3) do
  if (total < 20)
    total = total + 10;
end;
printl("%ld", total);
halt;
"""


def test_pdl_generated_nodes_are_at_their_statements() -> None:
    sink = DiagnosticSink()
    front = front_end("t.pdl", sink=sink, text=PDL)
    assert front is not None, [d.headline() for d in sink.items]
    module = lower_program("t.pdl", front.symbols).module
    assert module is not None
    nodes = list(ast.walk(module))
    add = _first(nodes, ast.Assign, "m1 = m1 + 10")
    assert _where(add) == _where(add.value) == (6, 4)
    assert _where(_first(nodes, ast.If, "if m1 < 20")) == (5, 2)
    assert _where(_first(nodes, ast.For, "for _ in range(3")) == (4, 0)
    assert _where(_first(nodes, ast.Expr, "_print(T")) == (8, 0)


GDL = """MODULE m;
  INTEGER$VARIABLE i [ INITIAL$VALUE = 1 ];
  DIGITAL$FLAG go [ ];
  PROCEDURE step;
  DECLARE { STATUS OF go };
  BEGIN
    WHILE VALUE OF i < 10 DO
      VALUE OF i = VALUE OF i + 1;
    END$WHILE;
  END$PROCEDURE;
END$MODULE;
"""


def test_gdl_generated_nodes_are_at_their_instructions() -> None:
    sink = DiagnosticSink()
    app = compile_app(["m.gdl"], sink=sink, texts={"m.gdl": GDL})
    assert app is not None, [d.headline() for d in sink.items]
    nodes = [x for procs in _by_file(app).values() for x in ast.walk(lower_file(procs))]
    assert _where(_first(nodes, ast.While, "while rt.read('i'")) == (7, 4)
    assign = _first(nodes, ast.Expr, "rt.assign('i'")
    assert _where(assign) == (8, 6)
    assert _where(assign.value.args[-1]) == (8, 30)  # the `+`: each node at its own place
