"""HMPL's C types (manual 1.4): sizes, alignment, conversions and their spelling in messages."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, slots=True)
class CType:
    """Base of every type; `size` and `align` in bytes.

    The kind flags (`is_integer`, ..., `is_scalar`) are class attributes: the lowering
    asks them for every operand, and a class attribute costs no call."""

    size: int
    align: int

    is_integer = False
    is_float = False
    is_arith = False  # integer or floating
    is_pointer = False
    is_scalar = False  # arithmetic or pointer


@dataclass(frozen=True, slots=True)
class VoidT(CType):
    def __str__(self) -> str:
        return "void"


@dataclass(frozen=True, slots=True, eq=False)
class IntT(CType):
    """A fixed-width integer; `code` is the memory view ('i32', 'u8', ...); `bits`, `min`
    and `max` are worked out once, when the type is made. The integer types are the
    constants below, no two alike, so they compare by identity (in C, at C speed)."""

    name: str = "int"
    signed: bool = True
    code: str = "i32"
    bits: int = field(init=False, repr=False, compare=False)
    min: int = field(init=False, repr=False, compare=False)
    max: int = field(init=False, repr=False, compare=False)

    is_integer = True
    is_arith = True
    is_scalar = True
    __eq__ = object.__eq__
    __hash__ = object.__hash__

    def __post_init__(self) -> None:
        bits = self.size * 8
        object.__setattr__(self, "bits", bits)
        object.__setattr__(self, "min", -(1 << (bits - 1)) if self.signed else 0)
        object.__setattr__(self, "max", (1 << (bits - 1)) - 1 if self.signed else (1 << bits) - 1)

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True, slots=True, eq=False)
class FloatT(CType):
    """`float` or `double`: the two constants below, compared by identity."""

    name: str = "double"
    code: str = "f64"

    is_float = True
    is_arith = True
    is_scalar = True
    __eq__ = object.__eq__
    __hash__ = object.__hash__

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True, slots=True)
class PtrT(CType):
    target: CType = field(default_factory=lambda: VOID)

    is_pointer = True
    is_scalar = True

    def __str__(self) -> str:
        if isinstance(self.target, FuncT):
            return f"{self.target.ret} (*)(...)"
        return f"{self.target} *"


@dataclass(frozen=True, slots=True)
class ArrayT(CType):
    """`elem[n]`; n is None for an array of unknown size (parameters, `extern`)."""

    elem: CType = field(default_factory=lambda: INT)
    n: int | None = None

    def __str__(self) -> str:
        # C spells the outer dimension first: `int[2][3]` is two arrays of three ints
        dims, t = "", self
        while isinstance(t, ArrayT):
            dims += f"[{'' if t.n is None else t.n}]"
            t = t.elem
        return f"{t}{dims}"


@dataclass(frozen=True, slots=True, eq=False)
class StructT(CType):
    """A struct or union (Timer and Data_t are predefined ones).

    Each definition is its own type (compared by identity, as C does). While its members
    are declared it is incomplete (size 0): a member may point to it (`struct N *next`),
    then `complete` gives it its members, size and alignment."""

    kind: str = "struct"
    tag: str = ""
    fields: tuple[tuple[str, int, CType], ...] = ()  # (name, offset, type)

    def complete(self, size: int, align: int, fields: tuple) -> None:
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "align", align)
        object.__setattr__(self, "fields", fields)

    def field(self, name: str) -> tuple[int, CType] | None:
        for n, off, t in self.fields:
            if n == name:
                return off, t
        return None

    def __str__(self) -> str:
        if self.tag in ("Timer", "Data_t"):
            return self.tag
        return f"{self.kind} {self.tag}".strip()


@dataclass(frozen=True, slots=True)
class FuncT(CType):
    ret: CType = field(default_factory=lambda: VOID)
    params: tuple[CType, ...] = ()
    variadic: bool = False

    def __str__(self) -> str:
        ps = ", ".join(str(p) for p in self.params) + (", ..." if self.variadic else "")
        return f"{self.ret}({ps})"


@dataclass(frozen=True, slots=True)
class ErrorT(CType):
    """The type of a name whose declaration failed: uses of it report nothing more."""

    def __str__(self) -> str:
        return "<error>"


VOID = VoidT(0, 1)
ERROR = ErrorT(0, 1)
CHAR = IntT(1, 1, "char", True, "i8")
I8 = IntT(1, 1, "int8_t", True, "i8")
U8 = IntT(1, 1, "uint8_t", False, "u8")
I16 = IntT(2, 2, "int16_t", True, "i16")
U16 = IntT(2, 2, "uint16_t", False, "u16")
INT = IntT(4, 4, "int", True, "i32")
U32 = IntT(4, 4, "uint32_t", False, "u32")
I64 = IntT(8, 8, "int64_t", True, "i64")
U64 = IntT(8, 8, "uint64_t", False, "u64")
FLOAT = FloatT(4, 4, "float", "f32")
DOUBLE = FloatT(8, 8, "double", "f64")

BASE_TYPES: dict[str, CType] = {
    "void": VOID,
    "char": CHAR,
    "int8_t": I8,
    "uint8_t": U8,
    "int16_t": I16,
    "uint16_t": U16,
    "int32_t": INT,
    "int": INT,
    "uint32_t": U32,
    "int64_t": I64,
    "uint64_t": U64,
    "float": FLOAT,
    "double": DOUBLE,
    "short": I16,
    "unsigned short": U16,
    "unsigned char": U8,
    "unsigned int": U32,
    "unsigned": U32,
    "long long": I64,
    "unsigned long long": U64,
    "long": INT,
}

# Timer (manual 1.4: 8 bytes): start time [ms], flags (bit0 previous IN, bit1 running, bit2 Q)
TIMER = StructT(8, 8, "struct", "Timer", (("_start_ms", 0, INT), ("_flags", 4, INT)))


def _data_t() -> StructT:
    members = (
        ("bytes", 0, ArrayT(65, 1, CHAR, 65)),
        ("uint8_", 0, U8),
        ("uint16_", 0, U16),
        ("uint32_", 0, U32),
        ("uint64_", 0, U64),
        ("int8_", 0, I8),
        ("int16_", 0, I16),
        ("int32_", 0, INT),
        ("int64_", 0, I64),
        ("float_", 0, FLOAT),
        ("double_", 0, DOUBLE),
    )
    # manual 1.4 gives Data_t 65 bytes: a packed union (members may sit unaligned in arrays)
    return StructT(65, 1, "union", "Data_t", members)


DATA_T = _data_t()


def pointer_to(t: CType) -> PtrT:
    return PtrT(8, 8, t)


def array_of(elem: CType, n: int | None) -> ArrayT:
    return ArrayT(elem.size * (n or 0), elem.align, elem, n)


def decay(t: CType) -> CType:
    """Arrays become pointers to their first element, functions pointers to themselves."""
    if isinstance(t, ArrayT):
        return pointer_to(t.elem)
    if isinstance(t, FuncT):
        return pointer_to(t)
    return t


def promote(t: CType) -> CType:
    """C integer promotion: types narrower than int become int."""
    if isinstance(t, IntT) and t.size < 4:
        return INT
    return t


def common_arith(a: CType, b: CType) -> CType:
    """The usual arithmetic conversions of C for a binary operator."""
    if a.is_float or b.is_float:
        if a == DOUBLE or b == DOUBLE:
            return DOUBLE
        if a == FLOAT or b == FLOAT:
            return FLOAT
    # the integer promotions (`promote`) inline
    if a.size < 4 and type(a) is IntT:
        a = INT
    if b.size < 4 and type(b) is IntT:
        b = INT
    assert isinstance(a, IntT) and isinstance(b, IntT)
    if a is b:
        return a
    if a.size != b.size:
        big, small = (a, b) if a.size > b.size else (b, a)
        if not big.signed and small.signed:
            return big
        if big.signed and not small.signed:
            return big  # the wider signed type holds every value of the narrower unsigned
        return big
    return a if not a.signed else b  # same size: the unsigned one wins


def same_pointee_family(a: CType, b: CType) -> bool:
    """Pointer targets that convert silently: equal, void, or 8-bit integer types."""
    if a == b or isinstance(a, VoidT) or isinstance(b, VoidT):
        return True
    if isinstance(a, IntT) and isinstance(b, IntT) and a.size == 1 and b.size == 1:
        return True
    return False


def wrap_int(v: int, t: IntT) -> int:
    """Reduce an integer to the range of `t` (two's complement)."""
    bits = t.bits
    v &= (1 << bits) - 1
    if t.signed and v >> (bits - 1):
        v -= 1 << bits
    return v
