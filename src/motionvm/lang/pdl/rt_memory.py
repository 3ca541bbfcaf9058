"""The PDL drive's data memory: 16,000 user long words plus the tasks' stacks, typed views.

Layout (word indices): word 0 is never allocated, so an unset pointer (0) is caught;
words 1..16000 hold the user variables (the checker's byte offsets / 4, plus 1);
each task then owns `stack_words` words for procedure frames.

Addresses, as `&var` yields them and pointers hold them (the manual's memory model:
pointers are word addresses):

* a long or float element: its word index (1..);
* a short element: SHORT_TAG + its half-word index, because two shorts share a word
  and a long pointer may point to a short.

Pointer arithmetic counts elements, so it is plain integer addition on both forms.
Every word has a kind in `kinds` (LONG, FLOAT, SHORT, or FREE); dereferencing checks
it, so a float pointer to a long, a long pointer to a float, or a pointer to nowhere
stops the task with a clear message instead of reading garbage.

Values: `M` ('i'), `H` ('h') and `F` ('f') are views of one buffer. A store of an int
outside the view's range raises ValueError; generated code catches it and wraps
(`w32`, `w16`), so the usual case costs nothing.
"""

from __future__ import annotations

import math

from motionvm.runtime.errors import RuntimeFault

FREE, LONG, FLOAT, SHORT = 0, 1, 2, 3
SHORT_TAG = 0x4000_0000
USER_BASE = 1
"""Word index of the first user variable."""

_KIND_TEXT = {FREE: "no variable", LONG: "a long", FLOAT: "a float", SHORT: "a short"}


def w32(v: int) -> int:
    """Wrap an integer to signed 32-bit (two's complement)."""
    return ((v + 0x8000_0000) & 0xFFFF_FFFF) - 0x8000_0000


def w16(v: int) -> int:
    """Keep the low 16 bits as a signed short (long -> short)."""
    return ((v + 0x8000) & 0xFFFF) - 0x8000


class Memory:
    """User memory and stacks as one buffer with long/short/float views and a kind map."""

    def __init__(self, user_words: int, stack_words: int, n_tasks: int = 4) -> None:
        self.user_words = user_words
        self.stack_words = stack_words
        self.user_end = USER_BASE + user_words
        """One past the last user word."""
        self.size = self.user_end + n_tasks * stack_words
        self.buf = bytearray(4 * self.size)
        self.M = memoryview(self.buf).cast("i")
        self.H = memoryview(self.buf).cast("h")
        self.F = memoryview(self.buf).cast("f")
        self.kinds = bytearray(self.size)
        self._global_kinds = bytearray(self.size)

    def stack_base(self, task: int) -> int:
        """First word of task `task`'s stack."""
        return self.user_end + task * self.stack_words

    def declare(self, word: int, n_words: int, kind: int) -> None:
        """Mark user words as holding variables of `kind` (at load time)."""
        self._global_kinds[word : word + n_words] = bytes([kind]) * n_words

    def clear(self) -> None:
        """Zero every variable (drive reset)."""
        self.buf[:] = bytes(len(self.buf))
        self.kinds[:] = self._global_kinds

    # ---------------------------------------------------------------- pointers

    def _where(self, addr: int) -> str:
        return f"0x{addr & 0xFFFF_FFFF:08x}"

    def _word_of(self, addr: int) -> tuple[int, bool]:
        """(word or half-word index, is_short) of an address, or a fault."""
        if addr >= SHORT_TAG:
            h = addr - SHORT_TAG
            if USER_BASE * 2 <= h < self.user_end * 2 and self.kinds[h >> 1] == SHORT:
                return h, True
            raise RuntimeFault(f"bad pointer {self._where(addr)}: it does not point to a variable")
        if addr == 0:
            raise RuntimeFault("bad pointer: it is 0 (the pointer was never set)")
        if 0 < addr < self.size:
            return addr, False
        raise RuntimeFault(f"bad pointer {self._where(addr)}: outside the drive's memory")

    def load_long(self, addr: int) -> int:
        """`*p` through a long pointer: a long or a short (sign-extended)."""
        i, short = self._word_of(addr)
        if short:
            return self.H[i]
        k = self.kinds[i]
        if k == LONG:
            return self.M[i]
        raise RuntimeFault(self._mismatch("long", addr, k))

    def store_long(self, addr: int, v: float) -> None:
        """`*p = v` through a long pointer (rounding a float, wrapping to the width)."""
        i, short = self._word_of(addr)
        if type(v) is float:
            v = round_int(v, 16 if short else 32)
        if short:
            self.H[i] = w16(v)
            return
        k = self.kinds[i]
        if k != LONG:
            raise RuntimeFault(self._mismatch("long", addr, k))
        self.M[i] = w32(v)

    def load_float(self, addr: int) -> float:
        """`*p` through a float pointer."""
        i, short = self._word_of(addr)
        k = SHORT if short else self.kinds[i]
        if k != FLOAT:
            raise RuntimeFault(self._mismatch("float", addr, k))
        return self.F[i]

    def store_float(self, addr: int, v: float) -> None:
        """`*p = v` through a float pointer."""
        i, short = self._word_of(addr)
        k = SHORT if short else self.kinds[i]
        if k != FLOAT:
            raise RuntimeFault(self._mismatch("float", addr, k))
        self.F[i] = v

    def _mismatch(self, ptype: str, addr: int, kind: int) -> str:
        if kind == FREE:
            return f"bad pointer {self._where(addr)}: it does not point to a variable"
        return (
            f"a {ptype} pointer cannot access {_KIND_TEXT[kind]} variable (at "
            f"{self._where(addr)}); the pointer type must match the data"
        )

    # ---------------------------------------------------------------- blocks

    def check_block(self, addr: int, n: int, what: str) -> tuple[int, bool]:
        """Start index of `n` consecutive elements from `addr`, all inside memory."""
        if addr >= SHORT_TAG:
            h = addr - SHORT_TAG
            if not (USER_BASE * 2 <= h and h + n <= self.user_end * 2):
                raise RuntimeFault(
                    f"{what}: {n} elements from {self._where(addr)} leave user memory"
                )
            return h, True
        if not (0 < addr and addr + n <= self.size):
            raise RuntimeFault(f"{what}: {n} elements from {self._where(addr)} leave the memory")
        return addr, False

    def fill(self, addr: int, values: tuple, kind: int) -> None:
        """Write `values` to consecutive elements (initialiser lists, strings)."""
        i, short = self.check_block(addr, len(values), "the assignment")
        if short:
            for k, v in enumerate(values):
                self.H[i + k] = w16(round_int(v, 16) if type(v) is float else v)
        elif kind == FLOAT:
            for k, v in enumerate(values):
                self.F[i + k] = v
        else:
            for k, v in enumerate(values):
                self.M[i + k] = w32(round_int(v, 32) if type(v) is float else v)

    def read_block(self, addr: int, n: int, kind: int) -> list:
        """`n` elements from `addr` as Python numbers."""
        i, short = self.check_block(addr, n, "the function")
        if short:
            return list(self.H[i : i + n])
        view = self.F if kind == FLOAT else self.M
        return list(view[i : i + n])

    def write_block(self, addr: int, values: list, kind: int) -> None:
        """Store already typed `values` at `addr` (memcpy, memset)."""
        i, short = self.check_block(addr, len(values), "the function")
        if short:
            self.H[i : i + len(values)] = memoryview(_pack(values, "h")).cast("h")
        elif kind == FLOAT:
            self.F[i : i + len(values)] = memoryview(_pack(values, "f")).cast("f")
        else:
            self.M[i : i + len(values)] = memoryview(_pack(values, "i")).cast("i")


def _pack(values: list, fmt: str) -> bytes:
    import array

    return array.array(fmt, values).tobytes()


INT_LIMITS = {32: (-0x8000_0000, 0x7FFF_FFFF), 16: (-0x8000, 0x7FFF)}


def round_int(x: float, bits: int = 32) -> int:
    """A float stored into an integer: nearest, halves away from zero, saturated."""
    if math.isnan(x):
        return 0
    lo, hi = INT_LIMITS[bits]
    if x >= hi:
        return hi
    if x <= lo:
        return lo
    i = int(x)
    d = x - i
    if d >= 0.5:
        i += 1
    elif d <= -0.5:
        i -= 1
    return i
