"""Lowering: GDL procedures become Python functions, built as `ast` nodes with user lines.

Each file's procedures become one Python module compiled with `filename=` that file,
so a run-time fault points at the user's line. Generated code calls only the methods
of its argument `rt`, an `api.ProcedureApi`. Before/after:

    PROCEDURE fan_control;                 def p_fan_control(rt):
    DECLARE { STATUS OF photocell };           rt.at(3)
    BEGIN                                      if not rt.read('run_request', 'STATUS', None):
      IF NOT STATUS OF run_request THEN            rt.at(4)
        VALUE OF cooling_fan = 0;                  rt.assign('cooling_fan', 'VALUE', None, 0)
        RETURN;                                    rt.at(5)
      END$IF;                                      return
      WHILE VALUE OF i <= 4 DO                 rt.at(7)
        VALUE OF i = VALUE OF i + 1;           while rt.read('i', 'VALUE', None) <= 4:
      END$WHILE;                                   rt.loop()
    END$PROCEDURE;                                 rt.at(8)
                                                   rt.assign('i', 'VALUE', None,
                                                             rt.read('i', 'VALUE', None) + 1)

`rt.at(line)` marks each instruction boundary (scenario events can be injected there);
`rt.loop()` counts WHILE iterations. A subscript is passed as an expression, or None
(a scalar, or a whole array), and checked by `rt`. `/` is `rt.div` (truncation toward
zero, division by zero is a fault); AND/OR are Python's short-circuit `and`/`or`.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from types import CodeType

from motionvm.lang.coverage import bind, compile_module
from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import App, ProcInfo
from motionvm.source.deep import run_deep
from motionvm.source.files import SourcePos

RELATIONS: dict[str, type[ast.cmpop]] = {
    "=": ast.Eq,
    "<>": ast.NotEq,
    "<": ast.Lt,
    ">": ast.Gt,
    "<=": ast.LtE,
    ">=": ast.GtE,
}
ARITH: dict[str, type[ast.operator]] = {"+": ast.Add, "-": ast.Sub, "*": ast.Mult}


def function_name(proc: ProcInfo) -> str:
    """The Python name of a procedure's function (prefixed: GDL names may be Python words)."""
    return f"p_{proc.name.lower()}"


def _at(node: ast.AST, pos: SourcePos) -> ast.AST:
    node.lineno = node.end_lineno = pos.line  # type: ignore[attr-defined]
    node.col_offset = pos.col - 1  # type: ignore[attr-defined]
    node.end_col_offset = pos.col  # type: ignore[attr-defined]
    return node


WHILES_PER_FUNCTION = 16
"""WHILE loops nested in one Python function; a deeper one becomes a nested function
(Python allows 20 nested blocks in a function, GDL has no such limit)."""


class Lowerer:
    """Builds the Python `ast` of the procedures of one file.

    A WHILE nested deeper than WHILES_PER_FUNCTION in its Python function is lowered as

        def _w3():                    # no locals: every value lives in `rt`
            while <cond>:
                ...                   # RETURN here: `return True`
            return False
        if _w3():
            return                    # (`return True` inside another such function)
    """

    def __init__(self) -> None:
        self.whiles = 0  # WHILE loops open in the current Python function
        self.nested = 0  # nested functions open
        self.count = 0

    def _rt_call(self, method: str, args: list[ast.expr], pos: SourcePos) -> ast.expr:
        func = _at(ast.Attribute(_at(ast.Name("rt", ast.Load()), pos), method, ast.Load()), pos)
        return _at(ast.Call(func, args, []), pos)  # type: ignore[return-value]

    def _const(self, value: object, pos: SourcePos) -> ast.expr:
        return _at(ast.Constant(value), pos)  # type: ignore[return-value]

    def _stmt(self, call: ast.expr, pos: SourcePos) -> ast.stmt:
        return _at(ast.Expr(call), pos)  # type: ignore[return-value]

    def procedure(self, proc: ProcInfo) -> ast.FunctionDef:
        pos = proc.node.pos
        args = ast.arguments(
            posonlyargs=[],
            args=[_at(ast.arg("rt"), pos)],
            kwonlyargs=[],
            kw_defaults=[],
            defaults=[],
        )
        body = self._block(proc.node.body) or [_at(ast.Pass(), pos)]
        func = ast.FunctionDef(name=function_name(proc), args=args, body=body, decorator_list=[])
        return _at(func, pos)  # type: ignore[return-value]

    def _block(self, body: tuple[n.Instr, ...]) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for instr in body:
            line = self._const(instr.pos.line, instr.pos)
            out.append(self._stmt(self._rt_call("at", [line], instr.pos), instr.pos))
            out.append(self._instr(instr))
        return out

    def _instr(self, instr: n.Instr) -> ast.stmt:
        pos = instr.pos
        if isinstance(instr, n.Assign):
            ref = instr.target
            args = [*self._target(ref.obj, ref.keyword), self._expr(instr.value)]
            return self._stmt(self._rt_call("assign", args, pos), pos)
        if isinstance(instr, n.OperatorCall):
            args = [*self._target(instr.obj, instr.keyword), *map(self._expr, instr.args)]
            return self._stmt(self._rt_call("call", args, pos), pos)
        if isinstance(instr, n.If):
            then = self._block(instr.then) or [_at(ast.Pass(), pos)]
            return _at(ast.If(self._expr(instr.cond), then, self._block(instr.orelse)), pos)  # type: ignore[return-value]
        if isinstance(instr, n.While):
            if self.whiles >= WHILES_PER_FUNCTION:
                return self._while_function(instr)
            self.whiles += 1
            try:
                body = [self._stmt(self._rt_call("loop", [], pos), pos), *self._block(instr.body)]
            finally:
                self.whiles -= 1
            return _at(ast.While(self._expr(instr.cond), body, []), pos)  # type: ignore[return-value]
        return self._return(pos)

    def _return(self, pos: SourcePos) -> ast.stmt:
        value = _at(ast.Constant(True), pos) if self.nested else None
        return _at(ast.Return(value), pos)  # type: ignore[return-value]

    def _while_function(self, instr: n.While) -> ast.stmt:
        """A WHILE as a nested function of its own (see the class docstring); the two
        statements come back wrapped in an always-true `if`."""
        pos = instr.pos
        self.count += 1
        fname = f"_w{self.count}"
        saved = self.whiles
        self.whiles, self.nested = 0, self.nested + 1
        try:
            loop = self._instr(instr)
        finally:
            self.whiles, self.nested = saved, self.nested - 1
        args = ast.arguments(posonlyargs=[], args=[], kwonlyargs=[], kw_defaults=[], defaults=[])
        done = _at(ast.Return(_at(ast.Constant(False), pos)), pos)
        func = _at(
            ast.FunctionDef(name=fname, args=args, body=[loop, done], decorator_list=[]), pos
        )
        test = _at(ast.Call(_at(ast.Name(fname, ast.Load()), pos), [], []), pos)
        leave = _at(ast.If(test, [self._return(pos)], []), pos)
        return _at(ast.If(_at(ast.Constant(True), pos), [func, leave], []), pos)  # type: ignore[return-value]

    def _target(self, ref: n.ObjectRef, keyword: str) -> list[ast.expr]:
        """obj key, keyword, subscript (an expression, or None: scalar or whole array)."""
        index = self._expr(ref.index) if ref.index is not None else self._const(None, ref.pos)
        return [self._const(ref.name.key, ref.pos), self._const(keyword, ref.pos), index]

    def _expr(self, e: n.Expr) -> ast.expr:
        pos = e.pos
        if isinstance(e, n.IntLit | n.DigitalLit | n.StrLit):
            return self._const(e.value, pos)
        if isinstance(e, n.SetLit):
            return self._const(e.word, pos)
        if isinstance(e, n.NameLit):
            return self._const(e.name.key, pos)
        if isinstance(e, n.StateRef):
            return self._rt_call("read", self._target(e.obj, e.keyword), pos)
        if isinstance(e, n.Unary):
            operand = self._expr(e.operand)
            op = {"NOT": ast.Not, "-": ast.USub, "+": ast.UAdd}[e.op]()
            return _at(ast.UnaryOp(op, operand), pos)  # type: ignore[return-value]
        assert isinstance(e, n.Binary)
        left, right = self._expr(e.left), self._expr(e.right)
        if e.op in ("AND", "OR"):
            op = ast.And() if e.op == "AND" else ast.Or()
            return _at(ast.BoolOp(op, [left, right]), pos)  # type: ignore[return-value]
        if e.op in RELATIONS:
            return _at(ast.Compare(left, [RELATIONS[e.op]()], [right]), pos)  # type: ignore[return-value]
        if e.op == "/":
            return self._rt_call("div", [left, right], pos)
        return _at(ast.BinOp(left, ARITH[e.op](), right), pos)  # type: ignore[return-value]


def lower_file(procs: list[ProcInfo]) -> ast.Module:
    """The Python module of the procedures of one file. Every node is built with its
    location (`_at`): no walk over the tree fills in missing ones."""
    lowerer = Lowerer()
    return ast.Module(body=[lowerer.procedure(p) for p in procs], type_ignores=[])


def _by_file(app: App) -> dict[str, list[ProcInfo]]:
    files: dict[str, list[ProcInfo]] = {}
    for proc in app.procedures:
        files.setdefault(proc.file, []).append(proc)
    return files


def compile_app_code(app: App) -> list[tuple[str, CodeType]]:
    """The code object of each file's procedures: (path, code), in link order."""
    return [
        (path, compile_module(lower_file(procs), path)) for path, procs in _by_file(app).items()
    ]


def load_app_code(app: App, codes: list[tuple[str, CodeType]]) -> dict[str, Callable[..., None]]:
    """Run each file's code (`compile_app_code`); procedure name (case-folded) -> function."""
    functions: dict[str, Callable[..., None]] = {}
    by_file = _by_file(app)
    for path, code in codes:
        namespace: dict[str, object] = {"__builtins__": {}}
        bind(namespace, code)
        exec(code, namespace)  # noqa: S102 - our own generated, checked code
        for proc in by_file.get(path, ()):
            functions[proc.name.lower()] = namespace[function_name(proc)]  # type: ignore[assignment]
    return functions


def lower_app(app: App) -> dict[str, Callable[..., None]]:
    """Compile every procedure once; procedure name (case-folded) -> function."""
    return load_app_code(app, compile_app_code(app))


def emit_python(app: App) -> str:
    """`ast.unparse` of the generated code, file by file (`--emit-python`)."""
    parts = []
    for path, procs in _by_file(app).items():
        parts.append(f"# {path}\n{run_deep(lambda p=procs: ast.unparse(lower_file(p)))}\n")
    return "\n".join(parts)
