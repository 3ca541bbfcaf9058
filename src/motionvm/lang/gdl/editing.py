"""What an editor sees inside a GDL file: modules, objects and procedures, names resolved
(case-insensitively, as GDL reads them), the object types of the catalogue and their
state variables, parameters and operators."""

from __future__ import annotations

from functools import lru_cache

from motionvm.lang.gdl.lexer import INSTRUCTION_WORDS, tokenize
from motionvm.lang.gdl.parser import parse_tokens
from motionvm.lang.index import Completion, SourceIndex, Symbol, resolve
from motionvm.lang.interface import NameDoc
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile


class _Quiet(DiagnosticSink):
    """A sink that keeps nothing and never stops a stage: an editor's file is read to the
    end however many errors it has (`check` reports them)."""

    def error(self, pos, message: str) -> None:
        pass

    def warning(self, pos, message: str) -> None:
        pass


def _tokens(path: str, text: str):
    try:
        return tokenize(path, text, _Quiet())
    except (TooManyErrors, RecursionError):
        return []


def symbols(path: str, text: str | None) -> list[Symbol]:
    """Modules, their objects and procedures."""
    text = SourceFile.text_of(path, text)
    if text is None:
        return []
    toks = _tokens(path, text)
    if not toks:
        return []
    try:
        tree = parse_tokens(toks, path, _Quiet())
    except (TooManyErrors, RecursionError):
        return []
    out: list[Symbol] = []
    for module in tree.modules:
        name = module.name
        out.append(Symbol(name.text, "module", path, name.pos.line, name.pos.col,
                          detail=f"MODULE {name.text}"))  # fmt: skip
        for obj in module.objects:
            out.append(Symbol(obj.name.text, "object", path, obj.name.pos.line,
                              obj.name.pos.col, name.text, f"{obj.type_kw} {obj.name.text}"))  # fmt: skip
        for proc in module.procedures:
            out.append(Symbol(proc.name.text, "procedure", path, proc.name.pos.line,
                              proc.name.pos.col, name.text, f"PROCEDURE {proc.name.text}"))  # fmt: skip
    out.sort(key=lambda s: (s.line, s.col))
    return out


def build_index(path: str, text: str) -> SourceIndex:
    syms = symbols(path, text)
    names = [(t.text, t.pos.line, t.pos.col) for t in _tokens(path, text) if t.kind == "ident"]
    return resolve(path, text, syms, names, fold=True)


@lru_cache(maxsize=1)
def docs() -> dict[str, NameDoc]:
    """The object types, their state variables, parameters and operators, and the
    instruction words."""
    from motionvm.lang.gdl.objects import TYPES

    out: dict[str, NameDoc] = {}
    for t in TYPES:
        states = ", ".join(s.keyword for s in t.states)
        out[t.name] = NameDoc(t.name, "type", f"{t.name} ({t.category} object type)",
                              t.doc + (f". State variables: {states}" if states else ""))  # fmt: skip
    for t in TYPES:
        for s in t.states:
            values = f" ({', '.join(s.values)})" if s.values else ""
            out.setdefault(s.keyword, NameDoc(s.keyword, "variable",
                           f"{s.keyword} OF object: {s.kind}{values}, access {s.access}",
                           f"A state variable of {t.name} and other types."))  # fmt: skip
        for p in t.params:
            out.setdefault(p.keyword, NameDoc(p.keyword, "variable", f"{p.keyword} = {p.kind}",
                                              f"A declaration parameter of {t.name}."))  # fmt: skip
        for o in t.operators:
            args = ", ".join(a.name for a in o.args)
            out.setdefault(o.keyword, NameDoc(o.keyword, "builtin",
                           f"{o.keyword} OF object" + (f" ({args})" if args else ""), o.doc,
                           tuple((a.name, f"{a.kind} {a.lo}..{a.hi}") for a in o.args)))  # fmt: skip
    for w in sorted(INSTRUCTION_WORDS):
        out.setdefault(w, NameDoc(w, "keyword", "", f"`{w}`: an instruction word of GDL"))
    return out


def completions(index: SourceIndex, line: int, col: int, visible) -> list[Completion]:
    kinds = {"type": "class", "variable": "attribute", "builtin": "function"}
    out = [Completion(d.name, kinds.get(d.kind, d.kind), d.signature, doc=d.markdown())
           for d in docs().values()]  # fmt: skip
    return out + visible(index, line, col)
