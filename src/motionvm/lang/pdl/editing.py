"""What an editor sees inside a PDL file: declarations, names resolved, documented names.

Declarations come from the parse of the preprocessed file, errors and all (a file being
edited is rarely correct); uses from the file's own tokens, so that names inside skipped
`#if` regions and macro definitions count. Names are case-sensitive; keywords and the
drive's system variables are not.
"""

from __future__ import annotations

from functools import lru_cache

from motionvm.lang.index import Completion, SourceIndex, Symbol, resolve
from motionvm.lang.interface import NameDoc
from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lexer import BUILTIN_FUNCS, KEYWORDS, tokenize
from motionvm.lang.pdl.parser import parse
from motionvm.lang.pdl.preprocess import preprocess
from motionvm.lang.tools import nodes
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors


class _Quiet(DiagnosticSink):
    """A sink that keeps nothing and never stops a stage: an editor's file is read to the
    end however many errors it has (`check` reports them)."""

    def error(self, pos, message: str) -> None:
        pass

    def warning(self, pos, message: str) -> None:
        pass


def symbols(path: str, text: str | None) -> list[Symbol]:
    """The declarations of a PDL file: variables, labels, procedures and their
    parameters, tasks, macros."""
    sink = _Quiet()
    try:
        program, _lost = parse(preprocess(path, sink, text), sink)
    except (OSError, TooManyErrors, RecursionError):
        return []
    out: list[Symbol] = []
    for node in nodes(program):
        pos = getattr(node, "pos", None)
        if pos is None or pos.file != path:
            continue
        if isinstance(node, n.VarDecl):
            for item in node.items:
                size = f"[{item.size}]" if item.size else ""
                out.append(Symbol(item.name, "variable", path, item.pos.line, item.pos.col,
                                  detail=f"{node.type} {item.name}{size}"))  # fmt: skip
        elif isinstance(node, n.Label):
            out.append(Symbol(node.name, "label", path, pos.line, pos.col, detail=f"{node.name}:"))
        elif isinstance(node, n.ProcDef):
            params = ", ".join(f"{p.type} {p.name}" for p in node.params)
            end = max((x.pos.line for x in nodes(node.body) if hasattr(x, "pos")), default=0)
            out.append(Symbol(node.name, "procedure", path, pos.line, pos.col,
                              detail=f"proc {node.name}({params})", end_line=end))  # fmt: skip
            for p in node.params:
                out.append(Symbol(p.name, "parameter", path, p.pos.line, p.pos.col, node.name,
                                  f"{p.type} {p.name}"))  # fmt: skip
        elif isinstance(node, n.TaskDirective):
            out.append(Symbol(f"#task/{node.task}", "task", path, pos.line, pos.col,
                              detail=f"#task/{node.task}", end_line=0))  # fmt: skip
    out += _macros(path, text)
    out.sort(key=lambda s: (s.line, s.col))
    return out


def _tokens(path: str, text: str | None):
    if text is None:
        try:
            from motionvm.source.files import SourceFile

            text = SourceFile.read(path).text
        except OSError:
            return []
    try:
        return tokenize(path, text, _Quiet())
    except (TooManyErrors, RecursionError):
        return []


def _macros(path: str, text: str | None) -> list[Symbol]:
    toks = _tokens(path, text)
    out = []
    for i, t in enumerate(toks[:-1]):
        nxt = toks[i + 1]
        if t.kind == "directive" and t.value == "define" and nxt.pos.line == t.pos.line:
            out.append(Symbol(nxt.text, "macro", path, nxt.pos.line, nxt.pos.col,
                              detail=f"#define {nxt.text}"))  # fmt: skip
    return out


def build_index(path: str, text: str) -> SourceIndex:
    syms = symbols(path, text)
    names = [(t.text, t.pos.line, t.pos.col) for t in _tokens(path, text) if t.kind == "name"]
    return resolve(path, text, syms, names)


@lru_cache(maxsize=1)
def docs() -> dict[str, NameDoc]:
    """The drive's system variables and states, the built-in functions and the keywords."""
    from motionvm.lang.pdl.sysvars import SYSVARS

    out: dict[str, NameDoc] = {}
    for sv in SYSVARS.values():
        size = f"[{sv.size}]" if sv.size > 1 else ""
        access = " (read only)" if sv.read_only else ""
        out[sv.name] = NameDoc(sv.name, "variable", f"{sv.kind} {sv.name}{size}{access}",
                               sv.doc or "a system variable of the drive")  # fmt: skip
    for k in sorted(KEYWORDS):
        kind = "builtin" if k in BUILTIN_FUNCS else "keyword"
        sig = f"{k}(...)" if k in BUILTIN_FUNCS else ""
        what = "a built-in function" if k in BUILTIN_FUNCS else "a keyword"
        out.setdefault(k, NameDoc(k, kind, sig, f"`{k}`: {what} of PDL"))
    return out


def completions(index: SourceIndex, line: int, col: int, visible) -> list[Completion]:
    out = [Completion(d.name, "keyword" if d.kind == "keyword" else
                      ("function" if d.kind == "builtin" else "variable"), d.signature,
                      doc=d.markdown()) for d in docs().values()]  # fmt: skip
    return out + visible(index, line, col)
