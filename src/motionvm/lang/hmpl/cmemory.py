"""The byte-addressed memory of an HMPL program: typed views, objects, stacks, checks.

Arrays, strings, unions, structs, Timers and every variable whose address is taken
live here; pointers are plain integer addresses into `buf`. Each live object's bytes
are marked valid in a shadow map and objects are separated by red zones of invalid
bytes, so a load or store through a pointer that walks off its object, or through a
null pointer, is caught with one shadow lookup. The shadow byte of a valid address
holds the bytes left in its object from there, capped at 255 (`shadow_pattern`), and
0 for an invalid one: an access of n <= 8 bytes at `a` is inside one live object iff
`shadow[a] >= n`, one byte read (`extent` reads one byte for an object's last 254
bytes and searches the shadow map for the end otherwise).

Layout: [0, NULL_GUARD) is never valid (null page); static objects (globals, task
variables, string literals, system variables) are bump-allocated after it; each task
owns a stack region for the memory-resident locals of its function frames.
"""

from __future__ import annotations

import mmap
import struct
from functools import lru_cache

from motionvm.runtime.errors import RuntimeFault

NULL_GUARD = 64
RED_ZONE = 8
ALIGN = 8
DEFAULT_STACK_SIZE = 64 * 1024

# struct/memoryview format letter and size of each scalar kind
SCALAR_FORMATS = {
    "i8": ("b", 1),
    "u8": ("B", 1),
    "i16": ("h", 2),
    "u16": ("H", 2),
    "i32": ("i", 4),
    "u32": ("I", 4),
    "i64": ("q", 8),
    "u64": ("Q", 8),
    "f32": ("f", 4),
    "f64": ("d", 8),
}

SHADOW_CAP = 255
"""The largest count of bytes left that a shadow byte holds."""
SHADOW_SPAN = 1 << 24
"""The shadow map covers at least addresses [0, SHADOW_SPAN) (bytes past the memory are
never valid), so that an address passing ADDRESS_SIGN_MASK indexes it safely."""
ADDRESS_SIGN_MASK = -SHADOW_SPAN
"""`a & (ADDRESS_SIGN_MASK | n - 1) == 0`: 0 <= a < SHADOW_SPAN and a is a multiple of
n (one test for the inline fast path of a pointer access; other addresses take the
checked path)."""

_F32 = struct.Struct("<f")
_CAP_RUN = bytes([SHADOW_CAP]) * 4096


@lru_cache(maxsize=256)
def shadow_pattern(size: int) -> bytes:
    """The shadow bytes of a live object of `size` bytes: the bytes left in the object
    from each byte on, capped at SHADOW_CAP (all nonzero: every byte is valid). Kept per
    size: every compile allocates the same system variables (a 4 MB user table) and
    frames of a few sizes."""
    tail = bytes(range(min(size, SHADOW_CAP), 0, -1))
    head = size - len(tail)
    if head <= 0:
        return tail
    run = _CAP_RUN if head <= len(_CAP_RUN) else bytes([SHADOW_CAP]) * head
    return run[:head] + tail


def to_f32(x: float) -> float:
    """Round a double to the nearest float (32-bit) value, as C does on storing a float."""
    try:
        return _F32.unpack(_F32.pack(x))[0]
    except OverflowError:
        return float("inf") if x > 0 else float("-inf")


def _round_up(n: int, a: int) -> int:
    return (n + a - 1) // a * a


class Memory:
    """One program's memory.

    Attributes `i8 ... f64` are memoryviews of the whole buffer with that element
    type; element k of view `i32` is at byte address 4*k. Library code should use
    the checked accessors (`load`, `store`, `read_cstr`, `write_bytes`, `extent`).
    """

    def __init__(self, size: int) -> None:
        size = _round_up(max(size, NULL_GUARD + ALIGN), ALIGN)
        self.size = size
        # anonymous maps: the kernel hands out zeroed pages on first touch, so a program
        # pays only for the pages it uses (a bytearray would zero all 28 MB up front)
        self.buf = mmap.mmap(-1, size)
        self.shadow = mmap.mmap(-1, max(size, SHADOW_SPAN))
        mv = memoryview(self.buf)
        for kind, (fmt, _) in SCALAR_FORMATS.items():
            setattr(self, kind, mv.cast(fmt))
        self.u8 = mv  # plain byte view
        self._static_top = NULL_GUARD
        self._static_limit = size
        self.names: dict[int, str] = {}

    def release(self) -> None:
        """Free both buffers now (the program will not run again): every typed view is
        released and the buffers emptied in place, whoever still refers to them. A view
        taken elsewhere and still held keeps the buffer until it goes."""
        for kind in SCALAR_FORMATS:
            getattr(self, kind).release()
        self.shadow.close()
        try:
            self.buf.close()
        except BufferError:
            pass
        self.size = 0

    # ------------------------------------------------------------ allocation

    def reserve_static(self, limit: int) -> None:
        """Static allocations may not pass byte `limit` (stacks live above it)."""
        self._static_limit = limit

    @property
    def static_limit(self) -> int:
        """Bytes of static memory in all [bytes]."""
        return self._static_limit

    def static_free(self) -> int:
        """Bytes of static memory still free [bytes]."""
        return max(0, self._static_limit - self._static_top - RED_ZONE)

    def alloc_static(self, size: int, name: str = "", align: int = ALIGN) -> int:
        """Allocate a zeroed object of `size` bytes for the whole run; return its address."""
        addr = _round_up(self._static_top, max(align, ALIGN))
        end = addr + max(size, 1)
        if end + RED_ZONE > self._static_limit:
            raise MemoryError(
                f"out of static memory allocating {size} bytes for {name or 'object'}"
            )
        self.shadow[addr : addr + size] = shadow_pattern(size)
        self._static_top = _round_up(end, ALIGN) + RED_ZONE
        if name:
            self.names[addr] = name
        return addr

    def static_image(self) -> tuple[int, bytes, bytes, dict[int, str]]:
        """What the compiler left in memory: the end of the statics, their bytes, their
        shadow bytes and their names (`restore_static` puts it into a fresh memory)."""
        top = self._static_top
        return top, bytes(self.buf[:top]), bytes(self.shadow[:top]), dict(self.names)

    def restore_static(self, image: tuple[int, bytes, bytes, dict[int, str]]) -> None:
        """Load a `static_image` into this memory, fresh from the same layout."""
        top, data, shadow, names = image
        if not NULL_GUARD <= top <= self._static_limit or len(data) != top or len(shadow) != top:
            raise ValueError("static image does not fit this memory")
        self.buf[:top] = data
        self.shadow[:top] = shadow
        self._static_top = top
        self.names = dict(names)

    # ------------------------------------------------------------ checks

    def extent(self, addr: int) -> int:
        """Bytes from `addr` to the end of the live object holding it; 0 if none does."""
        if addr <= 0 or addr >= self.size:
            return 0
        left = self.shadow[addr]
        if left < SHADOW_CAP:
            return left
        end = self.shadow.find(b"\0", addr)
        return (self.size if end < 0 else end) - addr

    def check(self, addr: int, n: int, what: str = "pointer") -> None:
        """Raise a RuntimeFault unless bytes [addr, addr+n) all lie inside one live object."""
        if addr == 0:
            raise RuntimeFault(f"null {what} dereferenced")
        if n <= 0:
            return
        if not (0 < addr < self.size) or self.extent(addr) < n:
            raise RuntimeFault(f"{what} 0x{addr:x} points outside its object ({n} bytes accessed)")

    # ------------------------------------------------------------ scalar access

    def load(self, addr: int, kind: str):
        """Checked load of one scalar of `kind` ('i32', 'f64', ...) at `addr`."""
        fmt, n = SCALAR_FORMATS[kind]
        self.check(addr, n)
        if addr % n == 0:
            return getattr(self, kind)[addr // n]
        return struct.unpack_from("<" + fmt, self.buf, addr)[0]

    def store(self, addr: int, kind: str, value) -> None:
        """Checked store of one scalar; integers wrap to the width, floats round for f32."""
        fmt, n = SCALAR_FORMATS[kind]
        self.check(addr, n)
        value = wrap_scalar(kind, value)
        if addr % n == 0:
            getattr(self, kind)[addr // n] = value
        else:
            struct.pack_into("<" + fmt, self.buf, addr, value)

    # ------------------------------------------------------------ bytes and strings

    def read_bytes(self, addr: int, n: int) -> bytes:
        self.check(addr, n)
        return bytes(self.buf[addr : addr + n])

    def write_bytes(self, addr: int, data: bytes, what: str = "destination") -> None:
        """Write raw bytes; a write past the end of the object is a fault and writes nothing."""
        n = len(data)
        if addr == 0:
            raise RuntimeFault(f"null {what} pointer")
        room = self.extent(addr)
        if room < n:
            raise RuntimeFault(
                f"{what} overflow: {n} bytes written into an object with {room} bytes left"
            )
        self.buf[addr : addr + n] = data

    def read_cstr(self, addr: int, what: str = "string") -> bytes:
        """The NUL-terminated string at `addr` (without the NUL); unterminated is a fault."""
        if addr == 0:
            raise RuntimeFault(f"null {what} pointer")
        room = self.extent(addr)
        if room == 0:
            raise RuntimeFault(f"{what} pointer 0x{addr:x} points outside any object")
        end = self.buf.find(b"\0", addr, addr + room)
        if end < 0:
            raise RuntimeFault(f"{what} is not terminated by '\\0' within its {room} bytes")
        return bytes(self.buf[addr:end])

    def write_cstr(self, addr: int, data: bytes, what: str = "destination") -> None:
        """Write `data` plus a terminating NUL; overflow is a fault and writes nothing."""
        self.write_bytes(addr, data + b"\x00", what)


def wrap_scalar(kind: str, value):
    """Convert a Python number to what C stores in a scalar of `kind`."""
    if kind == "f64":
        return float(value)
    if kind == "f32":
        return to_f32(float(value))
    v = int(value)
    bits = SCALAR_FORMATS[kind][1] * 8
    mask = (1 << bits) - 1
    v &= mask
    if kind[0] == "i" and v >> (bits - 1):
        v -= 1 << bits
    return v


class TaskStack:
    """A task's stack region for memory-resident locals; frames push and pop in LIFO order."""

    def __init__(self, mem: Memory, base: int, size: int) -> None:
        self.mem = mem
        self.base = base
        self.limit = base + size
        self.top = base

    def push(self, size: int, valid: bytes) -> int:
        """Allocate a frame of `size` bytes whose first len(`valid`) bytes are zeroed with
        `valid` as their shadow bytes (`shadow_pattern` of each object, 0 between them); the rest is only reserved (charged to the stack,
        never valid): the bytes of local arrays that the function keeps as Python lists."""
        fp = self.top
        end = fp + size
        if end > self.limit:
            raise RuntimeFault(
                f"stack overflow: task stack of {self.limit - self.base} bytes exhausted"
            )
        n = len(valid)
        self.mem.buf[fp : fp + n] = bytes(n)
        self.mem.shadow[fp : fp + n] = valid
        self.top = end
        return fp

    def pop(self, fp: int) -> None:
        """Release the frame at `fp` and every frame above it."""
        if fp < self.top:
            n = self.top - fp
            self.mem.shadow[fp : self.top] = bytes(n)
        self.top = fp

    def reset(self) -> None:
        self.pop(self.base)
