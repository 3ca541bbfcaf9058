"""HMPL string and memory built-ins (manual chapter 3) and host events (SendEvent, SendMsgEvent).

Every string argument is an address of a NUL-terminated `char` array in `self.mem`.
Text is bytes inside the controller: a string literal is its UTF-8 bytes, as gcc
stores it. A message leaves it decoded as UTF-8 (`message_text`), so `Print("25 °C")`
prints what the source says; a byte that is not part of a valid UTF-8 sequence (`%c`
of 0xB0) is one latin-1 character, so no byte is lost.

Decisions where the manual is silent:
- Writing past the end of the destination object (StringPrint, StringCopy[Ex],
  StringCat[Ex], MemoryCopy, MemorySet) is a RuntimeFault that names the function and
  the sizes, and nothing is written. So are null or dangling pointers and unterminated
  source strings.
- Print and StringPrint return -1 and print or write nothing when the formatted
  string would exceed HMPL_STR_MAX_LEN (512) characters (3.1: the longest HMPL string;
  3.2/3.3: -1 on an error); a destination too small for a shorter result is a fault.
- StringCopyEx/StringCatEx: `start_pos` must lie in [0, StringLen(source)] and
  `copy_len` must be -1 or >= 0, else the call returns ERR_ARG_OUT_OF_RANGE and writes
  nothing; a `copy_len` running past the end of source copies up to the end, as
  strncpy does. MemoryCopy/MemorySet with a negative `byte_num` return
  ERR_ARG_OUT_OF_RANGE; IsMemoryEqual with a negative `byte_num` is a RuntimeFault
  (it has no error return). MemoryCopy may overlap (memmove).
- StrFindChar of '\\0' returns StringLen(str), as strchr finds the terminator;
  StrFindStr of "" returns 0, as strstr does. StringToDouble parses like C's strtod
  (leading blanks, the longest valid prefix, hex floats, inf/nan; nothing valid -> 0.0).
- SendMsgEvent formats like Print; a message longer than SENDMSG_MAX_LEN (128)
  characters is truncated to its first 128 characters and still sent (the controller's
  fixed message buffer), and the call returns 0.
- SendEvent and SendMsgEvent each have a token bucket on simulated time: EVENT_RATE_HZ
  (1000) tokens per second, at most EVENT_BURST (100) saved up. A call finding the
  bucket empty is refused: nothing is sent and it returns ERR_EVENT_RATE (non-zero).
  The manual's "blocked until the average rate is below 1 kHz" is read as refused,
  since a task must not stall on a message.
- A sent event reaches the host as `rt.emit_event(kind, payload)`, kind "event" with
  the id (0-65535) or kind "msg" with the text, and is also one stdout line via
  `rt.emit`: `event <id>` for SendEvent, the message text itself for SendMsgEvent.

Run-time attributes used: `rt.mem`, `rt.emit(text)`, `rt.emit_event(kind, payload)`,
`rt.sim_time` [s].
"""

from __future__ import annotations

import re

from motionvm.lang.hmpl.cmemory import SHADOW_CAP
from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.lang.hmpl.lib.cformat import (
    ONE_INT,
    CFormat,
    FieldTooWide,
    compiled_format,
    format_c,
)
from motionvm.runtime.errors import RuntimeFault

HMPL_STR_MAX_LEN = 512
"""Longest string HMPL handles [characters, without the terminator] (manual 3.1)."""
SENDMSG_MAX_LEN = 128
"""Longest SendMsgEvent message [characters] (manual 2.19)."""
EVENT_RATE_HZ = 1000.0
"""Average rate allowed for SendEvent and for SendMsgEvent [1/s]."""
EVENT_BURST = 100.0
"""Calls that may be saved up and sent at once above the average rate."""

ERR_ARG_OUT_OF_RANGE = 0x138F  # eERR_HMPL_ARG_OUT_OF_RANGE
ERR_EVENT_RATE = 0x1770  # eERR_HMPL_EXEC_FAILED


def message_text(data: bytes) -> str:
    """The text of a message's bytes: UTF-8, with each byte outside a valid UTF-8
    sequence read as the latin-1 character of that byte."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        pass
    out = []
    while True:
        try:
            out.append(data.decode("utf-8"))
            return "".join(out)
        except UnicodeDecodeError as exc:
            out.append(data[: exc.start].decode("utf-8"))
            out.append(data[exc.start : exc.end].decode("latin-1"))
            data = data[exc.end :]


_STRTOD = re.compile(
    rb"[ \t\n\v\f\r]*([+-]?(?:"
    rb"0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
    rb"|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
    rb"|[iI][nN][fF](?:[iI][nN][iI][tT][yY])?"
    rb"|[nN][aA][nN](?:\([0-9A-Za-z_]*\))?))"
)


def strtod(text: bytes) -> float:
    """C's strtod of `text` (the longest valid prefix; 0.0 if there is none)."""
    m = _STRTOD.match(text)
    if m is None:
        return 0.0
    num = m.group(1)
    body = num.lstrip(b"+-")
    neg = num.startswith(b"-")
    if body[:2] in (b"0x", b"0X"):
        if b"p" not in body.lower():
            body += b"p0"
        if body[2:3] in (b".", b"p", b"P"):
            body = body[:2] + b"0" + body[2:]
        value = float.fromhex(body.decode("ascii"))
    elif body[:1] in b"nN":
        value = float("nan")
    else:
        value = float(body.split(b"(")[0])  # "inf", "infinity", digits; overflow gives inf
    return -value if neg else value


class _TokenBucket:
    """Average-rate limiter on simulated time."""

    __slots__ = ("burst", "last_time", "rate", "tokens")

    def __init__(self, rate: float, burst: float) -> None:
        self.rate = rate
        self.burst = burst
        self.tokens = burst
        self.last_time: float | None = None

    def take(self, sim_time: float) -> bool:
        """Spend one token at `sim_time` [s]; False if none is left."""
        if self.last_time is not None and sim_time > self.last_time:
            self.tokens = min(self.burst, self.tokens + (sim_time - self.last_time) * self.rate)
        if self.last_time is None or sim_time > self.last_time:
            self.last_time = sim_time
        if self.tokens >= 1.0:
            self.tokens -= 1.0
            return True
        return False


class StringLib(Library):
    """Chapter 3 (strings, memory) and 2.18/2.19 (events to the host)."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        self._buf = self.mem.buf
        self._shadow = self.mem.shadow
        # format address -> (its bytes and NUL, their count, compiled, `quick` of a one-%d format)
        self._formats: dict[int, tuple[bytes, int, CFormat, bytes]] = {}
        self._event_bucket = _TokenBucket(EVENT_RATE_HZ, EVENT_BURST)
        self._msg_bucket = _TokenBucket(EVENT_RATE_HZ, EVENT_BURST)

    # ------------------------------------------------------------ helpers

    def _format(self, func: str, fmt: int, args: tuple) -> bytes | None:
        """The formatted string, or None if it is longer than HMPL_STR_MAX_LEN."""
        try:
            entry = self._formats.get(fmt)
            # a format seen at this address before: still there, still in a live object?
            if (
                entry is not None
                and self._buf.find(entry[0], fmt, fmt + entry[1]) == fmt
                and self._shadow[fmt] >= entry[1]
            ):
                prog = entry[2]
            else:
                text = self.mem.read_cstr(fmt, f"{func} format")
                prog = compiled_format(text, func)
                if len(text) < SHADOW_CAP:
                    if len(self._formats) >= 256:
                        self._formats.clear()
                    one_int = prog.quick if prog.kinds is ONE_INT else b""
                    self._formats[fmt] = (text + b"\x00", len(text) + 1, prog, one_int)
            text = prog.render(args, self.mem, func)
        except FieldTooWide:
            return None
        return None if len(text) > HMPL_STR_MAX_LEN else text

    def _put_str(self, func: str, dest: int, text: bytes, at: int = 0) -> None:
        """Write `text` + NUL at dest+at, or fault without writing if it does not fit."""
        mem = self.mem
        if 0 < dest < mem.size:  # the common case, checked in place
            end = dest + at + len(text)
            left = self._shadow[dest]
            if end < dest + left or (left == SHADOW_CAP and end < self._shadow.find(b"\0", dest)):
                buf = self._buf
                buf[dest + at : end] = text
                buf[end] = 0
                return
        if dest == 0:
            raise RuntimeFault(f"{func}: null destination pointer")
        room = self.mem.extent(dest)
        if room == 0:
            raise RuntimeFault(f"{func}: destination 0x{dest:x} points outside any object")
        need = at + len(text) + 1
        if need > room:
            raise RuntimeFault(
                f"{func}: string overflow: {need} bytes ({at + len(text)} characters and '\\0')"
                f" do not fit the destination's {room} bytes"
            )
        self.mem.buf[dest + at : dest + need] = text + b"\x00"

    def _str(self, func: str, addr: int, what: str) -> bytes:
        return self.mem.read_cstr(addr, f"{func} {what}")

    def _str_end(self, func: str, addr: int, what: str) -> int:
        """The address of the NUL ending the string at `addr` (read_cstr's checks, no copy)."""
        if 0 < addr < self.mem.size:
            left = self._shadow[addr]
            if left:
                lim = addr + left if left < SHADOW_CAP else self._shadow.find(b"\0", addr)
                end = self._buf.find(b"\0", addr, lim)
                if end >= 0:
                    return end
        self.mem.read_cstr(addr, f"{func} {what}")  # raises the fault that says why
        raise AssertionError("unreachable")  # pragma: no cover

    def _room_end(self, addr: int) -> int:
        """The end of the live object holding `addr` (a valid address)."""
        left = self._shadow[addr]
        return addr + left if left < SHADOW_CAP else self._shadow.find(b"\0", addr)

    def _substring(self, func: str, source: int, start_pos: int, copy_len: int) -> bytes | None:
        src = self._str(func, source, "source")
        if not 0 <= start_pos <= len(src) or copy_len < -1:
            return None
        return src[start_pos:] if copy_len == -1 else src[start_pos : start_pos + copy_len]

    def _region(self, func: str, addr: int, n: int, what: str) -> None:
        """Fault unless [addr, addr+n) lies inside one object."""
        if addr == 0:
            raise RuntimeFault(f"{func}: null {what} pointer")
        room = self.mem.extent(addr)
        if room < n:
            raise RuntimeFault(
                f"{func}: {what} overflow: {n} bytes accessed in an object with {room} bytes left"
            )

    # ------------------------------------------------------------ output

    @builtin()
    def Print(self, format: int, *args) -> int:
        """Write one formatted message; return its length [characters], or -1."""
        text = self._format("Print", format, args)
        if text is None:
            return -1
        self.rt.emit(message_text(text))
        return len(text)

    @builtin()
    def StringPrint(self, destination: int, format: int, *args) -> int:
        """Write a formatted string into `destination`; return its length [characters], or -1."""
        # the fast path, with _format's and _put_str's checks in place
        entry = self._formats.get(format)
        if entry is not None and (
            self._buf.find(entry[0], format, format + entry[1]) == format
            and self._shadow[format] >= entry[1]
        ):
            one_int = entry[3]
            if (
                one_int
                and len(args) == 1
                and (v := args[0]).__class__ is int
                and -2147483648 <= v <= 2147483647
            ):
                text = one_int % v  # CFormat.render's first case, in place
            else:
                try:
                    text = entry[2].render(args, self.mem, "StringPrint")
                except FieldTooWide:
                    return -1
            n = len(text)
            if n > HMPL_STR_MAX_LEN:
                return -1
        else:
            text = self._format("StringPrint", format, args)
            if text is None:
                return -1
            n = len(text)
        if 0 < destination < self.mem.size:
            end = destination + n
            left = self._shadow[destination]
            if end < destination + left or (
                left == SHADOW_CAP and end < self._shadow.find(b"\0", destination)
            ):
                buf = self._buf
                buf[destination:end] = text
                buf[end] = 0
                return n
        self._put_str("StringPrint", destination, text)
        return n

    @builtin()
    def SendEvent(self, evt_id: int) -> int:
        """Send event `evt_id` (unsigned short) to the host; 0, or ERR_EVENT_RATE if refused."""
        evt_id &= 0xFFFF
        if not self._event_bucket.take(self.rt.sim_time):
            return ERR_EVENT_RATE
        self.rt.emit_event("event", evt_id)
        self.rt.emit(f"event {evt_id}")
        return 0

    @builtin()
    def SendMsgEvent(self, format: int, *args) -> int:
        """Send a formatted message (first 128 characters) to the host; 0, or ERR_EVENT_RATE."""
        text = format_c(
            self.mem.read_cstr(format, "SendMsgEvent format"), args, self.mem, "SendMsgEvent"
        )
        if not self._msg_bucket.take(self.rt.sim_time):
            return ERR_EVENT_RATE
        msg = message_text(text[:SENDMSG_MAX_LEN])
        self.rt.emit_event("msg", msg)
        self.rt.emit(msg)
        return 0

    # ------------------------------------------------------------ strings

    @builtin()
    def StringLen(self, str: int) -> int:
        if 0 < str < self.mem.size:  # _str_end in place, within what the shadow byte vouches for
            end = self._buf.find(b"\0", str, str + self._shadow[str])
            if end >= 0:
                return end - str
        return self._str_end("StringLen", str, "string") - str

    @builtin()
    def IsStringEqual(self, str1: int, str2: int) -> int:
        return int(
            self._str("IsStringEqual", str1, "str1") == self._str("IsStringEqual", str2, "str2")
        )

    @builtin()
    def StrFindChar(self, str: int, character: int) -> int:
        text = self._str("StrFindChar", str, "string")
        c = character & 0xFF
        return len(text) if c == 0 else text.find(c)

    @builtin()
    def StrFindCharEx(self, str: int, char_set: int, complement_set: int) -> int:
        """Offset of the first character in `char_set` (complement_set: not in it); -1 if none."""
        text = self._str("StrFindCharEx", str, "string")
        chars = frozenset(self._str("StrFindCharEx", char_set, "char_set"))
        want = not complement_set
        for i, c in enumerate(text):
            if (c in chars) == want:
                return i
        return -1

    @builtin()
    def StrFindStr(self, str1: int, str2: int) -> int:
        return self._str("StrFindStr", str1, "str1").find(self._str("StrFindStr", str2, "str2"))

    @builtin()
    def StringCopy(self, destination: int, source: int) -> int:
        self._put_str("StringCopy", destination, self._str("StringCopy", source, "source"))
        return 0

    @builtin()
    def StringCopyEx(self, destination: int, source: int, start_pos: int, copy_len: int) -> int:
        """Copy source[start_pos : start_pos+copy_len] (-1: to the end) into destination."""
        sub = self._substring("StringCopyEx", source, start_pos, copy_len)
        if sub is None:
            return ERR_ARG_OUT_OF_RANGE
        self._put_str("StringCopyEx", destination, sub)
        return 0

    @builtin()
    def StringCat(self, destination: int, source: int) -> int:
        size = self.mem.size
        if 0 < source < size and 0 < destination < size:  # _str_end's checks in place
            # each NUL is looked for first within the 255 bytes a shadow byte vouches for
            sh = self._shadow
            ls = sh[source]
            ld = sh[destination]
            if ls and ld:
                buf = self._buf
                src_end = buf.find(b"\0", source, source + ls)
                end = buf.find(b"\0", destination, destination + ld)
                if src_end >= 0 and end >= 0 and src_end - source < sh[end]:  # fits with its NUL
                    buf[end : end + (src_end - source) + 1] = buf[source : src_end + 1]
                    return 0
        src_end = self._str_end("StringCat", source, "source")
        end = self._str_end("StringCat", destination, "destination")
        n = src_end - source
        if end + n < self._room_end(destination):  # fits with its NUL: copy
            self._buf[end : end + n + 1] = self._buf[source : src_end + 1]
            return 0
        at = end - destination
        self._put_str("StringCat", destination, bytes(self._buf[source:src_end]), at)  # the fault
        return 0

    @builtin()
    def StringCatEx(self, destination: int, source: int, start_pos: int, copy_len: int) -> int:
        """Append source[start_pos : start_pos+copy_len] (-1: to the end) to destination."""
        sub = self._substring("StringCatEx", source, start_pos, copy_len)
        if sub is None:
            return ERR_ARG_OUT_OF_RANGE
        at = len(self._str("StringCatEx", destination, "destination"))
        self._put_str("StringCatEx", destination, sub, at)
        return 0

    @builtin()
    def StringToDouble(self, str: int) -> float:
        return strtod(self._str("StringToDouble", str, "string"))

    # ------------------------------------------------------------ memory

    @builtin()
    def MemoryCopy(self, destination: int, source: int, byte_num: int) -> int:
        if byte_num < 0:
            return ERR_ARG_OUT_OF_RANGE
        self._region("MemoryCopy", source, byte_num, "source")
        self._region("MemoryCopy", destination, byte_num, "destination")
        buf = self.mem.buf
        buf[destination : destination + byte_num] = buf[source : source + byte_num]
        return 0

    @builtin()
    def MemorySet(self, destination: int, value: int, byte_num: int) -> int:
        if byte_num < 0:
            return ERR_ARG_OUT_OF_RANGE
        self._region("MemorySet", destination, byte_num, "destination")
        self.mem.buf[destination : destination + byte_num] = bytes((value & 0xFF,)) * byte_num
        return 0

    @builtin()
    def IsMemoryEqual(self, memory_ptr1: int, memory_ptr2: int, byte_num: int) -> int:
        if byte_num < 0:
            raise RuntimeFault(f"IsMemoryEqual: byte_num {byte_num} is negative")
        self._region("IsMemoryEqual", memory_ptr1, byte_num, "memory_ptr1")
        self._region("IsMemoryEqual", memory_ptr2, byte_num, "memory_ptr2")
        buf = self.mem.buf
        return int(
            buf[memory_ptr1 : memory_ptr1 + byte_num] == buf[memory_ptr2 : memory_ptr2 + byte_num]
        )
