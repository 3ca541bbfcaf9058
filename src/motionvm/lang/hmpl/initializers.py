"""C's brace elision in initializers (C89 6.5.7, C99 6.7.8): a brace list rewritten with
every brace written out, so that the code that fills an object sees one list per
aggregate.

`int m[2][2] = {1, 2, 3, 4}` becomes `{{1, 2}, {3, 4}}`; `struct P ps[2] = {1, 2, 3, 4}`
becomes `{{1, 2}, {3, 4}}`; `{{1, 2}, 3, 4}` becomes `{{1, 2}, {3, 4}}`. A value meant
for an aggregate sub-object that is no brace list starts that sub-object's elided list,
which takes the values that follow until it is full, or a designator comes (C99: a
designator names a sub-object of the list that has the braces). Exceptions, as in C: a
string literal initializes a char array whole, and an expression of struct type a
struct whole. Sub-objects left without a value stay zero (the object is zero-filled
first); a value left over once the object is full is an error (`excess elements`).
"""

from __future__ import annotations

from collections.abc import Callable

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.source.files import SourcePos

Item = n.Expr | n.InitList | n.Designated


class ExcessError(Exception):
    """A value left over: the object (or a braced sub-object) is full."""

    def __init__(self, pos: SourcePos, message: str) -> None:
        super().__init__(message)
        self.pos = pos


def members(t: ct.StructT) -> list[tuple[str, int, ct.CType]]:
    """The members a brace list of struct `t` initializes, in order: all of them (a
    user's member may start with '_' too; Timer's two are hidden from `.` only)."""
    return list(t.fields)


def _is_char_array(t: ct.CType) -> bool:
    return isinstance(t, ct.ArrayT) and isinstance(t.elem, ct.IntT) and t.elem.size == 1


def _is_aggregate(t: ct.CType) -> bool:
    return isinstance(t, (ct.ArrayT, ct.StructT))


class Braces:
    """Rewrites brace lists for one declaration.

    `index_of(expr)` is the value of an array designator (a constant); `is_struct(expr)`
    says whether an expression has a struct type (it then initializes a struct whole).
    """

    def __init__(
        self,
        index_of: Callable[[n.Expr], int],
        is_struct: Callable[[n.Expr], bool],
        name: str,
    ) -> None:
        self.index_of = index_of
        self.is_struct = is_struct
        self.name = name

    def full(self, t: ct.CType, init):
        """`init` (for an object of type `t`) with all its braces written out."""
        if not isinstance(init, n.InitList) or not _is_aggregate(t):
            return init
        items = init.items
        if _is_char_array(t) and len(items) == 1 and isinstance(items[0], n.StrLit):
            return items[0]  # `char s[] = {"abc"}`
        if (
            isinstance(t, ct.ArrayT)
            and not _is_aggregate(t.elem)
            and (t.n is None or len(items) <= t.n)
            and not any(isinstance(x, (n.InitList, n.Designated)) for x in items)
        ):
            return init  # values for the elements one by one: nothing to elide
        stream = list(items)
        at = [0]
        out = self._fill(t, stream, at, braced=True)
        if at[0] < len(stream):
            extra = stream[at[0]]
            raise ExcessError(
                extra.pos,
                f"excess elements in the initializer of '{self.name}' "
                f"(too many initializers: '{t}' takes no more values)",
            )
        return n.InitList(init.pos, tuple(out))

    def _fill(self, t: ct.CType, stream: list, at: list[int], braced: bool) -> list[Item]:
        """Values for the sub-objects of `t` taken from `stream` from `at[0]` on: all of
        the list when `braced`, else until `t` is full or a designator comes."""
        out: list[Item] = []
        if isinstance(t, ct.ArrayT):
            limit = t.n
            names: list[str] = []
            fields: list = []
        else:
            assert isinstance(t, ct.StructT)
            fields = members(t)
            names = [f[0] for f in fields]
            limit = 1 if t.kind == "union" else len(fields)
        k = 0
        while at[0] < len(stream):
            it = stream[at[0]]
            if isinstance(it, n.Designated):
                if not braced:
                    break  # a designator belongs to the list that has the braces
                if isinstance(t, ct.ArrayT):
                    if it.index is None:
                        out.append(it)  # the initialization reports the designator
                        at[0] += 1
                        k += 1
                        continue
                    k = self.index_of(it.index)
                    sub = t.elem
                elif it.field is None or it.field not in names:
                    out.append(it)
                    at[0] += 1
                    k += 1
                    continue
                else:
                    k = names.index(it.field)
                    sub = fields[k][2]
                stream[at[0]] = it.value  # the value is now the next item
                value = self._one(sub, stream, at)
                out.append(n.Designated(it.pos, it.field, it.index, value))
                k += 1
                continue
            if limit is not None and k >= limit:
                break
            if isinstance(t, ct.StructT) and t.kind == "union" and out:
                break  # one member of a union
            sub = t.elem if isinstance(t, ct.ArrayT) else fields[k][2]
            out.append(self._one(sub, stream, at))
            k += 1
        return out

    def _one(self, sub: ct.CType, stream: list, at: list[int]) -> Item:
        """The value of one sub-object of type `sub`, starting at `stream[at[0]]`."""
        it = stream[at[0]]
        if isinstance(it, n.InitList):
            at[0] += 1
            return self.full(sub, it)
        if not _is_aggregate(sub):
            at[0] += 1
            return it
        if isinstance(it, n.StrLit) and _is_char_array(sub):
            at[0] += 1
            return it
        if isinstance(sub, ct.StructT) and self.is_struct(it):
            at[0] += 1
            return it
        start = at[0]
        values = self._fill(sub, stream, at, braced=False)
        if at[0] == start:  # `sub` takes no value by position: the value is the error's
            at[0] += 1
            return it
        return n.InitList(it.pos, tuple(values))


def array_length(braces: Braces, t: ct.ArrayT, init) -> int | None:
    """The length of `T a[] = init` (t: the array of unknown length): one past the
    highest element the initializer gives, as C counts it."""
    if isinstance(init, n.StrLit):
        return len(init.value) + 1 if _is_char_array(t) else None
    if not isinstance(init, n.InitList):
        return None
    full = braces.full(t, init)
    if isinstance(full, n.StrLit):
        return len(full.value) + 1
    count = i = 0
    for it in full.items:
        if isinstance(it, n.Designated) and it.index is not None:
            i = braces.index_of(it.index)
        i += 1
        count = max(count, i)
    return count
