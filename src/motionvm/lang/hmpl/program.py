"""Whole-program compilation of HMPL: every task's unit into one Python namespace.

Steps: (1) declare types, variables and function signatures of task 0 (global scope)
and of every other task (task scope); (2) find address-taken names and which functions
can block (they become generators); (3) lower every function and each task's global
initializers; (4) compile one Python module per source file with that file as the
code's filename, so faults point at the user's lines.

Names in the shared namespace: task 0's globals and functions are `g_NAME`, task k's
are `tK_NAME`; locals are `v_NAME`; run-time helpers start with `_`; built-ins `b_NAME`.
"""

from __future__ import annotations

import ast
import struct
from collections.abc import Callable
from dataclasses import dataclass, field

from motionvm.lang.coverage import compile_module
from motionvm.lang.hmpl import catalog, check_memo
from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import FuncFacts, constant_init, scan
from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.initializers import Braces, ExcessError, array_length
from motionvm.lang.hmpl.initializers import members as struct_members
from motionvm.lang.hmpl.lint import lint_function
from motionvm.lang.hmpl.lower_context import SemanticError
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_function import FunctionLowerer
from motionvm.lang.hmpl.lvalues import VIEW_NAMES, call, name, view_code
from motionvm.lang.hmpl.symbols import FuncSym, Scope, VarSym, error_symbol
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

_PACK = {
    "i8": "b",
    "u8": "B",
    "i16": "h",
    "u16": "H",
    "i32": "i",
    "u32": "I",
    "i64": "q",
    "u64": "Q",
    "f32": "f",
    "f64": "d",
}


LIST_BYTES = 64 * 1024 * 1024
"""Declared bytes [bytes] the file-scope arrays kept in Python lists may take together
(each element costs 8 bytes of the host's memory however small its type)."""


@dataclass
class Unit:
    task: int
    path: str
    tu: n.TranslationUnit


@dataclass
class TaskInfo:
    task: int
    path: str
    entry: str | None = None  # pyname of main()
    autorun: bool = False
    init: str = ""  # pyname of the initializer function
    functions: dict[str, FuncSym] = field(default_factory=dict)  # callable by StartTaskFunc


@dataclass
class CompiledProgram:
    tasks: dict[int, TaskInfo]
    modules: list[tuple[str, ast.Module]]  # (filename, module)
    codes: list[tuple[str, object]]  # (filename, code object)
    sysvars: dict[str, VarSym]
    globals_: dict[str, VarSym]
    rebuild: Callable[[], list[tuple[str, ast.Module]]] | None = None
    """Makes `modules` again, for a program read from the compile cache (it holds code
    objects only)."""

    def python_source(self) -> str:
        if not self.modules and self.rebuild is not None:
            self.modules = self.rebuild()
        out = []
        for fname, mod in self.modules:
            out.append(f"# ---- {fname}\n{run_deep(ast.unparse, mod)}\n")
        return "\n".join(out)


class ProgramCompiler:
    """Compiles all task units of one program against one Memory."""

    def __init__(
        self,
        mem: Memory,
        sink: DiagnosticSink,
        builtin_impl: dict[str, bool],
        bytecode: bool = True,
    ) -> None:
        self.mem = mem
        self.bytecode = bytecode
        """Whether the program is compiled to code; false: a check (`motionvm check`), which
        keeps only the diagnostics, so the lowering skips what only the code needs."""
        self.sink = sink
        self.builtins = catalog.builtin_signatures()
        self.builtin_impl = builtin_impl  # name -> blocking, for implemented built-ins
        self.constants = catalog.constants()
        self.global_scope = Scope(None, "global")
        self.global_scope.types.update({"Timer": ct.TIMER, "Data_t": ct.DATA_T})
        self.task_scopes: dict[int, Scope] = {0: self.global_scope}
        self.tasks: dict[int, TaskInfo] = {}
        self._strings: dict[bytes, int] = {}
        self._list_bytes = 0  # declared bytes of the file-scope arrays kept in lists
        self._structs: dict[int, ct.StructT] = {}  # id(StructDef) -> its type
        self._declared_only: set[int] = set()  # ids of struct types declared, not defined
        # (task, name) -> the first prototype inside a function of a function that the
        # file did not declare before it: a later declaration must agree with it
        self._block_protos: dict[tuple[int, str], FuncSym] = {}
        self.sysvars: dict[str, VarSym] = {}
        self.addr_taken: set[str] = set()
        self._warned: set[tuple[SourcePos, str]] = set()
        # the static memory requests of the function being lowered, for its kept check
        self._requests: list[tuple | None] | None = None
        self._alloc_system()

    def warn(self, pos: SourcePos, message: str) -> None:
        """A warning, once per place and text (some expressions are lowered twice)."""
        if (pos, message) not in self._warned:
            self._warned.add((pos, message))
            self.sink.warning(pos, message)

    # ------------------------------------------------------------ symbols

    def _alloc_system(self) -> None:
        for sv in catalog.system_variables():
            t = ct.array_of(sv.type, sv.n) if sv.n else sv.type
            addr = self.mem.alloc_static(t.size, sv.name)
            self.sysvars[sv.name] = VarSym(sv.name, t, "static", None, addr=addr)
        self.timer_init = self.mem.alloc_static(ct.TIMER.size, "TimerInit")

    def global_symbol(self, ident: str, task: int):
        sv = self.sysvars.get(ident)
        if sv is not None:
            return sv
        if ident == "TimerInit":
            return VarSym(
                "TimerInit", ct.TIMER, "static", None, addr=self.timer_init, is_const=True
            )
        if ident == "_TASKID_":
            return VarSym(ident, ct.INT, "const", None, const_value=task, is_const=True)
        c = self.constants.get(ident)
        if c is not None:
            return VarSym(ident, c.type, "const", None, const_value=c.value, is_const=True)
        return None

    def global_names(self, task: int) -> list[str]:
        return list(self.sysvars) + list(self.constants) + list(self.builtins) + ["TimerInit"]

    def function_names(self, task: int) -> list[str]:
        scope = self.task_scopes.get(task, self.global_scope)
        own = [k for k, v in scope.names.items() if isinstance(v, FuncSym)]
        glob = [k for k, v in self.global_scope.names.items() if isinstance(v, FuncSym)]
        return own + glob + list(self.builtins)

    def prototype(self, fname: str, task: int) -> str:
        sig = self.builtins.get(fname)
        if sig is not None:
            return f"; prototype: {sig.prototype.rstrip(';')}"
        return ""

    def alloc_static_at(self, pos, size: int, name: str, align: int = 8) -> int:
        """`Memory.alloc_static` for an object declared at `pos`; a full static memory is
        a located error (SemanticError)."""
        if self._requests is not None:
            self._requests.append((pos, size, name, align))
        return self._alloc_static_at(pos, size, name, align)

    def _alloc_static_at(self, pos, size: int, name: str, align: int) -> int:
        mem = self.mem
        free = mem.static_free()
        try:
            return mem.alloc_static(size, name, align=align)
        except MemoryError:
            if self._requests is not None:
                self._requests.append(None)  # a function that fills the memory is not kept
            what = name if " " in name else f"'{name}'"  # a string literal has no name
            raise self._fail(
                pos,
                f"{what} does not fit in the program's static memory: it needs {size:,} "
                f"bytes, {free:,} of {mem.static_limit:,} are left",
            ) from None

    def charge_list(self, pos, size: int, name: str) -> None:
        """Count a file-scope array kept in a Python list (`list_backed`) against
        LIST_BYTES; beyond it a located error (SemanticError): a list costs 8 bytes per
        element, so `int a[1000000000];` would take 8 GB."""
        if self._list_bytes + size > LIST_BYTES:
            raise self._fail(
                pos,
                f"array '{name}' is too large: {size:,} bytes, and the program's arrays "
                f"may take {LIST_BYTES:,} bytes ({self._list_bytes:,} taken)",
            )
        self._list_bytes += size

    def string_literal(self, data: bytes, pos=None) -> int:
        if self._requests is not None:
            self._requests.append((pos, data))
        addr = self._strings.get(data)
        if addr is None:
            addr = self._alloc_static_at(pos, len(data) + 1, "a string literal", 1)
            self.mem.buf[addr : addr + len(data)] = data
            self._strings[data] = addr
        return addr

    # ------------------------------------------------------------ types

    def resolve_typeref(self, tr: n.TypeRef, scope: Scope, task: int) -> ct.CType:
        base = tr.base
        t = ct.BASE_TYPES.get(base)
        if t is None:
            if tr.struct_def is not None:
                t = self.define_struct(tr.struct_def, scope, task)
            elif base.startswith(("struct ", "union ")):
                kind, tag = base.split(" ", 1)
                t = scope.lookup_tag(tag)
                if t is None:  # C: declares the tag, an incomplete type until defined
                    t = scope.tags[tag] = ct.StructT(0, 1, kind, tag, ())
                    self._declared_only.add(id(t))
                elif t is not ct.ERROR and t.kind != kind:
                    raise self._fail(tr.pos, f"'{base}' defined as the wrong kind of tag")
            else:
                t = scope.lookup_type(base)
                if t is None:
                    known = list(ct.BASE_TYPES) + ["Timer", "Data_t"]
                    raise self._fail(
                        tr.pos, f"unknown type name '{base}'{did_you_mean(base, known)}"
                    )
            if t is ct.ERROR:  # a struct or typedef whose definition failed (reported)
                raise SemanticError(f"'{base}' has no valid definition")
        for _ in range(tr.pointers):
            t = ct.pointer_to(t)
        return t

    def define_struct(self, sd: n.StructDef, scope: Scope, task: int) -> ct.StructT:
        """The struct or union type; if it fails, its tag names the error type, so that
        later uses of the tag add no errors."""
        st = self._structs.get(id(sd))
        if st is not None:  # one type per definition, however often it is resolved
            if sd.tag:
                scope.tags[sd.tag] = st
            return st
        st = ct.StructT(0, 1, sd.kind, sd.tag or f"<anonymous {sd.kind}>", ())
        ahead = scope.tags.get(sd.tag) if sd.tag else None
        if ahead is not None and id(ahead) in self._declared_only:
            # `typedef struct s s;` (or a pointer) before `struct s { ... };` in this
            # scope: the definition completes that type
            if ahead.kind != sd.kind:
                raise self._fail(sd.pos, f"'{sd.kind} {sd.tag}' defined as the wrong kind of tag")
            self._declared_only.discard(id(ahead))
            st = ahead
        self._structs[id(sd)] = st
        if sd.tag:
            scope.tags[sd.tag] = st  # members may point to it
        try:
            self._define_struct(sd, st, scope, task)
        except SemanticError:
            if sd.tag and scope.tags.get(sd.tag) is st:
                scope.tags[sd.tag] = ct.ERROR  # type: ignore[assignment]
            raise
        return st

    def _define_struct(self, sd: n.StructDef, st: ct.StructT, scope: Scope, task: int) -> None:
        fields = []
        off = size = 0
        align = 1
        for f in sd.fields:
            ft = self.decl_type(f, scope, task)
            if ft.size == 0:
                raise self._fail(f.pos, f"field '{f.name}' has incomplete type '{ft}'")
            align = max(align, ft.align)
            if sd.kind == "union":
                fields.append((f.name, 0, ft))
                size = max(size, ft.size)
            else:
                off = (off + ft.align - 1) // ft.align * ft.align
                fields.append((f.name, off, ft))
                off += ft.size
                size = off
        size = (size + align - 1) // align * align
        st.complete(size, align, tuple(fields))

    def decl_type(self, d, scope: Scope, task: int) -> ct.CType:
        t = self.resolve_typeref(d.type, scope, task)
        dims = list(d.dims)
        for i, dim in enumerate(reversed(dims)):
            outer = i == len(dims) - 1
            if dim is None:
                if not outer:
                    raise self._fail(
                        d.pos, f"array '{d.name}' needs sizes for all but the first dimension"
                    )
                count = self._count_from_init(d, t, scope, task)
                if count is None:
                    if isinstance(d, n.Param):
                        return ct.pointer_to(t)
                    raise self._fail(d.pos, f"array size missing in '{d.name}'")
            else:
                count = self._const_int(dim, scope, task)
                if count <= 0:
                    raise self._fail(
                        dim.pos, f"size of array '{d.name}' must be positive (it is {count})"
                    )
            t = ct.array_of(t, count)
        if isinstance(d, n.Param) and isinstance(t, ct.ArrayT):
            return ct.pointer_to(t.elem)
        return t

    def require_complete(self, d, t: ct.CType) -> None:
        """A variable's type must be complete: its size known (not a struct only
        declared, as by `typedef struct s s;`, nor an array of one)."""
        elem = t
        while isinstance(elem, ct.ArrayT):
            elem = elem.elem
        if isinstance(elem, ct.StructT) and not elem.fields:
            raise self._fail(
                d.pos, f"storage size of '{d.name}' is not known: '{elem}' is an incomplete type"
            )

    def _count_from_init(self, d, elem: ct.CType, scope: Scope, task: int) -> int | None:
        """The length of `T a[] = init` from its initializer (brace elision counted)."""
        init = getattr(d, "init", None)
        if init is None:
            return None
        x = FunctionLowerer(self, task, scope, None, set()).x
        try:
            count = array_length(self.braces(x, d.name), ct.array_of(elem, None), init)
        except ExcessError as e:
            raise self._fail(e.pos, str(e)) from None
        return None if count is None else max(1, count)

    def braces(self, lw: ExprLowerer, vname: str) -> Braces:
        """The brace-elision rewriter of variable `vname`'s initializer (initializers.py)."""
        return Braces(lw.const_int, lambda e: self._has_struct_type(lw, e), vname)

    def _has_struct_type(self, lw: ExprLowerer, e) -> bool:
        """Whether expression `e` has a struct type: it is lowered once to learn its type,
        and what that reports is taken back (the initialization lowers it again)."""
        if isinstance(e, (n.IntLit, n.FloatLit, n.CharLit, n.StrLit)):
            return False
        if isinstance(e, n.CompoundLit):  # its type is written: no object to make here
            return not e.dims and isinstance(lw.resolve_type(e.type), ct.StructT)
        items, warned = self.sink.items[:], set(self._warned)
        try:
            return isinstance(lw.expr(e).type, ct.StructT)
        except SemanticError:
            return True  # initializes the struct whole, where its error is reported again
        finally:
            self.sink.items[:] = items
            self._warned = warned

    def _const_int(self, e, scope: Scope, task: int) -> int:
        if type(e) is n.IntLit and not e.suffix and 0 <= e.value <= ct.INT.max:
            return e.value  # `char buf[32]`: what the lowerer would find, without one
        return FunctionLowerer(self, task, scope, None, set()).x.const_int(e)

    def _fail(self, pos, msg: str) -> SemanticError:
        self.sink.error(pos, msg)
        return SemanticError(msg)

    # ------------------------------------------------------------ initializers

    def aggregate_init(self, lw: ExprLowerer, t: ct.CType, init, addr: ast.expr, vname: str):
        """(constant byte image of the object, statements for non-constant parts)."""
        image = bytearray(t.size)
        stores: list[ast.stmt] = []
        try:
            init = self.braces(lw, vname).full(t, init)
        except ExcessError as e:
            raise self._fail(e.pos, str(e)) from None
        self._init_into(lw, t, init, 0, image, stores, addr, vname)
        return image, stores

    def _init_into(self, lw, t, init, off, image, stores, addr, vname) -> None:
        if isinstance(t, ct.ArrayT) and isinstance(init, n.StrLit):
            if not (isinstance(t.elem, ct.IntT) and t.elem.size == 1):
                raise self._fail(init.pos, f"a string initializes only a char array, not '{t}'")
            data = init.value
            if t.n is not None and len(data) > t.n:
                raise self._fail(
                    init.pos,
                    f"string of {len(data)} characters is too long for '{vname}' ({t.n} bytes)",
                )
            image[off : off + len(data)] = data
            return
        if isinstance(t, ct.ArrayT):
            items = init.items if isinstance(init, n.InitList) else (init,)
            i = 0
            for it in items:
                if isinstance(it, n.Designated):
                    if it.index is None:
                        raise self._fail(
                            it.pos, f"field designator '.{it.field}' in the initializer of an array"
                        )
                    i = lw.const_int(it.index)
                    it = it.value
                if t.n is not None and not 0 <= i < t.n:
                    raise self._fail(
                        init.pos, f"too many initializers for '{vname}' (element {i} of {t.n})"
                    )
                self._init_into(lw, t.elem, it, off + i * t.elem.size, image, stores, addr, vname)
                i += 1
            return
        if isinstance(t, ct.StructT):
            if isinstance(init, n.Name) and init.id == "TimerInit" and t == ct.TIMER:
                return
            if not isinstance(init, n.InitList):
                v = lw.expr(init)
                if v.type != t:
                    raise self._fail(init.pos, f"cannot initialize '{t}' from '{v.type}'")
                stores.append(
                    lw.ctx.at(
                        [ast.Expr(call("_copy", _offset(addr, off), v.node, ast.Constant(t.size)))],
                        init.pos,
                    )[0]
                )
                return
            members = struct_members(t)
            k = 0
            for it in init.items:
                if isinstance(it, n.Designated):
                    names = [f[0] for f in members]
                    if it.field is None or it.field not in names:
                        what = f"'.{it.field}'" if it.field else "an index designator"
                        raise self._fail(
                            it.pos,
                            f"'{t}' has no member {what}{did_you_mean(it.field or '', names)}",
                        )
                    k = names.index(it.field)
                    it = it.value
                if k >= len(members) or (
                    t.kind == "union" and k > 0 and not isinstance(init.items[0], n.Designated)
                ):
                    raise self._fail(init.pos, f"too many initializers for '{t}'")
                fname, foff, ft = members[k]
                self._init_into(lw, ft, it, off + foff, image, stores, addr, vname)
                k += 1
            return
        # scalar element
        if isinstance(init, n.InitList):
            if len(init.items) != 1:
                raise self._fail(
                    init.pos, "braces around a scalar initializer need exactly one value"
                )
            init = init.items[0]
        v = lw.expr(init)
        node = lw.assign_convert(v, t, init.pos, f" in the initializer of '{vname}'")
        code = view_code(t)
        if isinstance(node, ast.Constant) or (
            isinstance(node, ast.UnaryOp) and isinstance(node.operand, ast.Constant)
        ):
            value = node.value if isinstance(node, ast.Constant) else -node.operand.value
            struct.pack_into("<" + _PACK[code], image, off, value)
            return
        target = ast.Subscript(name(VIEW_NAMES[code]), _scaled(addr, off, t.size), ast.Store())
        stores.append(lw.ctx.at([ast.Assign([target], node)], init.pos)[0])

    # ------------------------------------------------------------ declarations

    def declare_units(self, units: list[Unit]) -> None:
        for u in sorted(units, key=lambda u: u.task):
            scope = (
                self.global_scope
                if u.task == 0
                else self.task_scopes.setdefault(u.task, Scope(self.global_scope, "task"))
            )
            info = self.tasks.setdefault(u.task, TaskInfo(u.task, u.path, init=f"_init_t{u.task}"))
            prefix = "g_" if u.task == 0 else f"t{u.task}_"
            for item in u.tu.items:
                try:
                    self._declare_item(item, scope, u.task, prefix, info)
                except SemanticError:
                    pass

    def _declare_item(self, item, scope: Scope, task: int, prefix: str, info: TaskInfo) -> None:
        if isinstance(item, n.StructDef):
            self.define_struct(item, scope, task)
        elif isinstance(item, n.Typedef):
            try:
                t = self.resolve_typeref(item.type, scope, task)
                for dim in reversed(item.dims):
                    count = self._const_int(dim, scope, task) if dim is not None else None
                    if count is not None and count <= 0:
                        raise self._fail(
                            dim.pos, f"size of array '{item.name}' must be positive (it is {count})"
                        )
                    t = ct.array_of(t, count)
            except SemanticError:
                scope.types.setdefault(item.name, ct.ERROR)
                raise
            scope.types[item.name] = t
        elif isinstance(item, n.DeclStmt):
            for d in item.decls:
                try:
                    self._declare_item(d, scope, task, prefix, info)
                except SemanticError:
                    pass
        elif isinstance(item, n.VarDecl):
            if item.name in scope.names:
                self._redeclare(item, scope, task)
                return
            if item.type.struct_def is not None and not item.name:
                self.define_struct(item.type.struct_def, scope, task)
                return
            try:
                t = self.decl_type(item, scope, task)
                if isinstance(t, ct.VoidT):
                    raise self._fail(item.pos, f"variable '{item.name}' declared void")
                self.require_complete(item, t)
                in_list = self.list_backed(item, t)
                if in_list:
                    self.charge_list(item.pos, t.size, item.name)
                elif not t.is_scalar or item.name in self.addr_taken:
                    addr = self.alloc_static_at(item.pos, t.size, item.name, align=max(8, t.align))
            except SemanticError:
                scope.names[item.name] = error_symbol(item.name, item.pos)
                raise
            if (t.is_scalar and item.name not in self.addr_taken) or in_list:
                sym = VarSym(
                    item.name,
                    t,
                    "pyglobal" if t.is_scalar else "pylist",
                    item.pos,
                    pyname=prefix + item.name,
                    is_const=item.type.is_const,
                )
            else:
                sym = VarSym(
                    item.name, t, "static", item.pos, addr=addr, is_const=item.type.is_const
                )
            scope.names[item.name] = sym
            self._pending_inits.setdefault(task, []).append((sym, item))
        elif isinstance(item, n.FuncDef):
            try:
                self._declare_function(item, scope, task, prefix, info)
            except SemanticError:
                if item.name not in scope.names and not item.block_scope:
                    scope.names[item.name] = error_symbol(item.name, item.pos)
                raise

    def _redeclare(self, item: n.VarDecl, scope: Scope, task: int) -> None:
        """A file-scope variable declared again (C's tentative definitions: `int x;` then
        `int x = 3;`): the same type, at most one initializer; else a redefinition."""
        old = scope.names[item.name]
        pending = self._pending_inits.get(task, [])
        k = next((i for i, (sym, _) in enumerate(pending) if sym is old), None)
        if isinstance(old, VarSym) and k is not None:
            try:
                t = self.decl_type(item, scope, task)
            except SemanticError:
                return
            first = pending[k][1]
            if t == old.type and (item.init is None or first.init is None):
                if item.init is not None:
                    if old.storage == "pylist" and not constant_init(item.init):
                        raise self._fail(
                            item.pos, f"'{item.name}' needs a constant initializer here"
                        )
                    pending[k] = (old, item)
                return
            if t != old.type:
                raise self._fail(
                    item.pos, f"conflicting types for '{item.name}' (was '{old.type}')"
                )
        raise self._fail(item.pos, f"redefinition of '{item.name}'")

    def _declare_function(
        self, f: n.FuncDef, scope: Scope, task: int, prefix: str, info: TaskInfo
    ) -> None:
        """A function's definition or prototype at file scope; a prototype inside a
        function (`block_scope`) is only checked against the file's declarations here."""
        if f.name in self.builtins or f.name in catalog.MACRO_NAMES:
            raise self._fail(f.pos, f"'{f.name}' is a built-in function and cannot be redefined")
        ret = self.resolve_typeref(f.ret, scope, task)
        ptypes = []
        for p in f.params:
            pt = self.decl_type(p, scope, task)
            if isinstance(pt, ct.StructT):
                raise self._fail(p.pos, f"parameter '{p.name}': pass structs by pointer ('{pt} *')")
            ptypes.append(pt)
        if len(ptypes) == 1 and isinstance(ptypes[0], ct.VoidT) and not f.params[0].name:
            ptypes = []
        if f.name == "main" and ptypes:  # a task starts main() with no arguments
            self.sink.error(f.params[0].pos, "main takes no parameters")
            ptypes = []
        ftype = ct.FuncT(0, 1, ret, tuple(ptypes), False)
        old = scope.names.get(f.name)
        if old is None:
            # an earlier prototype inside a function; for one inside a function, also
            # task 0's function of that name (a task's block may declare it)
            prev = self._block_protos.get((task, f.name))
            if prev is None and f.block_scope:
                prev = scope.lookup(f.name)
            if isinstance(prev, FuncSym) and prev.type != ftype:
                raise self._fail(f.pos, f"conflicting types for '{f.name}' (was '{prev.type}')")
            if f.block_scope:  # visible in its block only (bound there when lowered)
                if prev is None:
                    self._block_protos[(task, f.name)] = FuncSym(
                        f.name, ftype, f.pos, prefix + f.name, task
                    )
                return
        if old is not None:
            if not isinstance(old, FuncSym):
                raise self._fail(f.pos, f"'{f.name}' redeclared as a different kind of symbol")
            if old.type != ftype:
                raise self._fail(f.pos, f"conflicting types for '{f.name}' (was '{old.type}')")
            if f.body is not None and old.defined:
                raise self._fail(f.pos, f"redefinition of '{f.name}'")
            sym = old
        else:
            sym = FuncSym(f.name, ftype, f.pos, prefix + f.name, task)
            scope.names[f.name] = sym
        if f.body is not None:
            sym.defined = True
            sym.node = f
            sym.param_names = tuple(p.name for p in f.params)
            info.functions[f.name] = sym
            if f.name == "main":
                info.entry = sym.pyname
                info.autorun = f.autorun
        elif f.autorun:
            self.sink.error(f.pos, "_AUTORUN_ needs a function definition")
        if f.autorun and f.name != "main":
            self.sink.error(f.pos, "_AUTORUN_ applies to a task's main() function")
        if not sym.param_names:
            sym.param_names = tuple(p.name for p in f.params)

    # ------------------------------------------------------------ analysis

    def _link_prototypes(self) -> None:
        """A task's prototype of a function that task 0 defines names that function."""
        for task, scope in self.task_scopes.items():
            if task == 0:
                continue
            for fname, sym in scope.names.items():
                if isinstance(sym, FuncSym) and not sym.defined:
                    g = self.global_scope.names.get(fname)
                    if isinstance(g, FuncSym) and g.defined and g.type == sym.type:
                        scope.names[fname] = g

    def block_prototype(self, f: n.FuncDef, task: int) -> FuncSym:
        """The function a prototype inside a function names: the file's (or task 0's)
        function of that name, or an undefined one that a call reports."""
        scope = self.task_scopes.get(task, self.global_scope)
        sym = scope.lookup(f.name)
        if isinstance(sym, FuncSym):
            return sym
        proto = self._block_protos.get((task, f.name))
        if proto is None or sym is not None:
            raise SemanticError(f"'{f.name}' has no valid declaration")  # reported
        return proto

    def list_backed(self, d: n.VarDecl, t: ct.CType) -> bool:
        """An array of scalars that is only ever indexed to its full depth (never decays to a
        pointer, never has an element's address taken) lives in a Python list: no program
        can observe its bytes, and list indexing is much faster than memory views."""
        if not isinstance(t, ct.ArrayT) or d.name in self.addr_taken:
            return False
        depth, elem = 0, t
        while isinstance(elem, ct.ArrayT):
            depth, elem = depth + 1, elem.elem
        if not isinstance(elem, (ct.IntT, ct.FloatT)):
            return False
        if self.array_uses.get(d.name, set()) - {depth}:
            return False
        return d.init is None or constant_init(d.init)

    def analyse(self, units: list[Unit]) -> None:
        """One pass over the program: array uses; per function address-taken names,
        waits and callees; address-taken names of the global declarations."""
        self.facts: dict[int, FuncFacts] = {}
        uses: dict[str, set] = {}
        blocking = self.builtin_impl
        for u in units:
            keys = u.tu.function_keys
            for item in u.tu.items:
                if type(item) is n.FuncDef:
                    scan((item.ret, item.params), uses, None, blocking)
                    if item.body is not None:
                        key = keys.get(id(item)) if keys is not None else None
                        if key is None:
                            facts = FuncFacts()
                            scan(item.body, uses, facts, blocking)
                        else:  # a function's scan is kept with its check
                            facts = check_memo.CHECKS.scan(key, item.body, uses, blocking)
                        self.facts[id(item)] = facts
                        self.addr_taken |= facts.addr_taken
                else:
                    facts = FuncFacts()
                    scan(item, uses, facts, blocking)
                    self.addr_taken |= facts.addr_taken
        self.array_uses = uses

    def classify_generators(self) -> None:
        """A function is a generator if it loops, waits, or calls one that is (fixpoint)."""
        funcs: list[FuncSym] = []
        for scope in self.task_scopes.values():
            funcs.extend(s for s in scope.names.values() if isinstance(s, FuncSym) and s.defined)
        calls: dict[int, list[FuncSym]] = {}
        for f in funcs:
            facts = self.facts[id(f.node)]
            f.is_generator = facts.waits
            scope = self.task_scopes.get(f.task, self.global_scope)
            calls[id(f)] = [
                c for c in (scope.lookup(nm) for nm in facts.callees) if isinstance(c, FuncSym)
            ]
        changed = True
        while changed:
            changed = False
            for f in funcs:
                if not f.is_generator and any(c.is_generator for c in calls[id(f)]):
                    f.is_generator = True
                    changed = True

    # ------------------------------------------------------------ lowering

    def compile(self, units: list[Unit]) -> CompiledProgram | None:
        bytecode = self.bytecode
        self._pending_inits: dict[int, list] = {}
        try:
            self.analyse(units)
            self.declare_units(units)
            self._link_prototypes()
            self.classify_generators()
            memo, env = self._kept_checks(units, bytecode)
            per_file: dict[str, list[ast.stmt]] = {}
            for u in sorted(units, key=lambda u: u.task):
                scope = self.task_scopes[u.task]
                per_file.setdefault(u.path, []).append(self._init_function(u, scope))
                keys = u.tu.function_keys
                for item in u.tu.items:
                    if isinstance(item, n.FuncDef) and item.body is not None:
                        sym = scope.names.get(item.name)
                        if not isinstance(sym, FuncSym) or sym.node is not item:
                            continue
                        key = keys.get(id(item)) if memo is not None else None
                        if key is not None:
                            if self._reuse(memo.get(env, u.task, key), key):
                                continue
                            first, self._requests = len(self.sink.items), []
                        fn = self._lower_function(u.task, scope, item, sym)
                        if key is not None:
                            memo.put(env, u.task, key, self.sink.items[first:], self._requests)
                            self._requests = None
                        if bytecode and fn is not None:  # `check` wants the diagnostics only
                            per_file.setdefault(item.pos.file, []).append(fn)
        except TooManyErrors:
            return None
        if self.sink.has_errors:
            return None
        modules, codes = [], []
        for fname, body in per_file.items():
            mod = ast.Module(body, [])
            modules.append((fname, mod))
            if bytecode:
                codes.append((fname, compile_module(mod, fname)))
        globals_ = {k: v for k, v in self.global_scope.names.items() if isinstance(v, VarSym)}
        return CompiledProgram(self.tasks, modules, codes, self.sysvars, globals_)

    def _lower_function(self, task: int, scope: Scope, item: n.FuncDef, sym: FuncSym):
        """The function's Python tree, its diagnostics in the sink; None if it failed."""
        lint_function(item, self.warn)
        facts = self.facts[id(item)]
        if not facts.assigned:  # a kept scan: lowering wants the names each body assigns
            facts = FuncFacts()
            scan(item.body, {}, facts, self.builtin_impl)
        lw = FunctionLowerer(
            self, task, Scope(scope, "function"), sym, facts.addr_taken, facts.assigned
        )
        try:
            return lw.function(item, sym)
        except SemanticError:
            return None

    def _kept_checks(self, units: list[Unit], bytecode: bool):
        """The kept function checks and this program's environment key, when it is
        checked (not compiled to code) and its units carry function keys."""
        if bytecode or any(u.tu.function_keys is None for u in units):
            return None, b""
        scopes = [self.task_scopes[k] for k in sorted(self.task_scopes)]
        env = check_memo.environment(units, scopes, self.addr_taken, self.array_uses)
        return check_memo.CHECKS, env

    def _reuse(self, entry: check_memo.Entry | None, key: check_memo.FunctionKey) -> bool:
        """Report a kept check again (moved with its function) and make its memory
        requests; False, doing nothing, when there is none or its requests might not fit."""
        if entry is None or entry.need > self.mem.static_free():
            return False
        delta = key.first - entry.first
        for r in entry.requests:
            pos = check_memo.moved(r[0], key.file, delta) if r[0] is not None else None
            if len(r) == 4:
                self._alloc_static_at(pos, r[1], r[2], r[3])
            else:
                self.string_literal(r[1], pos)
        for d in entry.diagnostics:
            pos = check_memo.moved(d.pos, key.file, delta)
            if d.severity == "error":
                self.sink.error(pos, d.message)
            elif d.severity == "warning":
                self._warned.add((pos, d.message))
                self.sink.warning(pos, d.message)
            else:
                self.sink.note(pos, d.message)
        return True

    def _init_function(self, u: Unit, scope: Scope) -> ast.FunctionDef:
        lw = FunctionLowerer(self, u.task, scope, None, set())
        body: list[ast.stmt] = []
        for sym, item in self._pending_inits.get(u.task, []):
            try:
                stmts = lw.init_var(sym, item.init, item.pos)
                if sym.storage == "pyglobal":
                    lw.globals_stored.add(sym.pyname)
                if lw.has_yield:
                    raise self._fail(
                        item.pos,
                        f"the initializer of '{item.name}' must not call a function that waits",
                    )
                body.extend(lw.ctx.at(stmts, item.pos))
            except SemanticError:
                pass
        if lw.globals_stored:
            body.insert(0, ast.Global(sorted(lw.globals_stored)))
        fn = ast.FunctionDef(
            f"_init_t{u.task}",
            ast.arguments([], [], None, [], [], None, []),
            body or [ast.Pass()],
            [],
            None,
        )
        return lw.ctx.at([fn], u.tu.pos)[0]


def _offset(addr: ast.expr, off: int) -> ast.expr:
    if off == 0:
        return addr
    if isinstance(addr, ast.Constant):
        return ast.Constant(addr.value + off)
    return ast.BinOp(addr, ast.Add(), ast.Constant(off))


def _scaled(addr: ast.expr, off: int, size: int) -> ast.expr:
    a = _offset(addr, off)
    if isinstance(a, ast.Constant):
        return ast.Constant(a.value // size)
    return ast.BinOp(a, ast.FloorDiv(), ast.Constant(size))
