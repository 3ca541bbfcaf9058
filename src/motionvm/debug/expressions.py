"""Expressions of the user's language evaluated on a paused program.

Conditions of breakpoints, watch expressions and the debugger's evaluate request are
written as in the program: C's operators for HMPL and PDL (`count > 3 && !done`,
`a[i] == 2`), GDL's `KEYWORD OF object` references (`VALUE OF fan > 300`). They are
translated to a Python expression tree of a few safe node kinds (numbers, names,
subscripts, unary, binary, comparison and boolean operators) and evaluated with names
looked up by `resolve(name)`: a frame's locals, then the program's globals, then every
variable of the run by its scope channel name (`axis0.pos_fb`, `gpi3`). Anything else
(calls, assignments, attribute access) is refused with a clear error.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from functools import lru_cache

_TOKEN = re.compile(
    r"\s*(?:(?P<num>0[xX][0-9a-fA-F]+|\d+\.\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|\d+(?:[eE][-+]?\d+)?)"
    r"|(?P<of>[A-Za-z_][\w$]*\s+(?i:OF)\s+[A-Za-z_]\w*(?:\{[^}]*\})?)"
    r"|(?P<item>[A-Za-z_][\w.$]*\s*\[\s*\d+\s*\])"
    r"|(?P<name>[A-Za-z_][\w.$]*)"
    r"|(?P<op>&&|\|\||==|!=|<=|>=|<<|>>|[-+*/%<>!()\[\]&|^~]))"
)


class ExpressionError(Exception):
    """An expression that cannot be read or evaluated; the message says why."""


def to_python(text: str) -> str:
    """The Python text of an expression written in C or GDL syntax."""
    out: list[str] = []
    pos = 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise ExpressionError(f"cannot read '{text[pos:].strip()}' in '{text}'")
        pos = m.end()
        if m.group("num"):
            num = m.group("num")
            out.append(str(int(num, 16)) if num[:2].lower() == "0x" else num)
        elif m.group("of"):
            kw, obj = re.split(r"\s+OF\s+", m.group("of"), maxsplit=1, flags=re.IGNORECASE)
            obj, brace, rest = obj.partition("{")
            element = f"{{{rest.rstrip('}').strip()}}}" if brace else ""
            out.append(_name(f"{obj.strip()}{element}.{kw}"))  # the channel: `cell{2}.STATUS`
        elif m.group("item"):
            out.append(_name(re.sub(r"\s+", "", m.group("item"))))
        elif m.group("name"):
            word = m.group("name")
            upper = word.upper()
            if upper in ("AND", "OR", "NOT"):
                out.append(f" {upper.lower()} ")
            elif upper in ("TRUE", "ON"):
                out.append("1")
            elif upper in ("FALSE", "OFF"):
                out.append("0")
            else:
                out.append(_name(word))
        else:
            op = m.group("op")
            out.append({"&&": " and ", "||": " or ", "!": " not ", "/": "/"}.get(op, op))
    return "".join(out)


def _name(name: str) -> str:
    """A name as a Python call-free lookup: `_v("axis0.pos_fb")`."""
    return f"_v({name!r})"


_ALLOWED = (
    ast.Expression, ast.BoolOp, ast.BinOp, ast.UnaryOp, ast.Compare, ast.Constant,
    ast.Subscript, ast.Load, ast.And, ast.Or, ast.Not, ast.USub, ast.UAdd, ast.Invert,
    ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Mod, ast.LShift, ast.RShift, ast.BitAnd,
    ast.BitOr, ast.BitXor, ast.Eq, ast.NotEq, ast.Lt, ast.LtE, ast.Gt, ast.GtE,
)  # fmt: skip


@lru_cache(maxsize=256)
def compile_expression(text: str):
    """The code of an expression (ExpressionError if it is not one we evaluate)."""
    source = to_python(text)
    try:
        tree = ast.parse(source, mode="eval")
    except SyntaxError:
        raise ExpressionError(f"'{text}' is not an expression") from None
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            ok = (
                isinstance(node.func, ast.Name)
                and node.func.id == "_v"
                and len(node.args) == 1
                and isinstance(node.args[0], ast.Constant)
            )
            if ok:
                continue
            raise ExpressionError(f"'{text}': calls are not evaluated")
        if isinstance(node, ast.Name) and node.id == "_v":
            continue
        if not isinstance(node, _ALLOWED):
            raise ExpressionError(f"'{text}': {type(node).__name__} is not evaluated")
    tree = ast.fix_missing_locations(_Elements().visit(tree))
    return compile(tree, "<expression>", "eval")


class _Elements(ast.NodeTransformer):
    """`a[i]` as `_at(a, i)`: C's indices (no counting from the end)."""

    def visit_Subscript(self, node: ast.Subscript) -> ast.AST:
        self.generic_visit(node)
        at = ast.Name("_at", ast.Load())
        return ast.copy_location(ast.Call(at, [node.value, node.slice], []), node)


def _at(array, index):
    """An element of an array, its index checked as C would want it."""
    if not isinstance(array, list | tuple):
        raise ExpressionError(f"{_show(array)} is not an array")
    if isinstance(index, float) and index.is_integer():
        index = int(index)
    if not isinstance(index, int) or isinstance(index, bool):
        raise ExpressionError(f"index {_show(index)} is not a whole number")
    if not 0 <= index < len(array):
        raise ExpressionError(f"index {index} is out of range for an array of {len(array)}")
    return array[index]


def _show(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def evaluate(text: str, resolve: Callable[[str], object]):
    """The value of an expression, names looked up by `resolve(name)` (KeyError: unknown)."""
    code = compile_expression(text)

    def lookup(name: str):
        try:
            return resolve(name)
        except KeyError:
            pass
        base, bracket, index = name.partition("[")
        if bracket:  # an element of an array that is one value: `cells[2]`
            try:
                array = resolve(base)
            except KeyError:
                pass
            else:
                try:
                    return _at(array, int(index.rstrip("]")))
                except ExpressionError as exc:
                    raise ExpressionError(f"'{name}': {exc}") from None
        raise ExpressionError(f"unknown name '{name}'")

    try:
        return eval(code, {"__builtins__": {}, "_v": lookup, "_at": _at})  # noqa: S307 — checked above
    except ExpressionError:
        raise
    except Exception as exc:  # noqa: BLE001 — a division by zero, an index out of range
        raise ExpressionError(f"'{text}': {exc}") from None
