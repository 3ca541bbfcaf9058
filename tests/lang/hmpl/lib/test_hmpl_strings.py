"""StringLib: the manual's chapter 3 examples, SendEvent/SendMsgEvent, and every fault."""

from __future__ import annotations

import struct

import pytest

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib.strings import (
    ERR_ARG_OUT_OF_RANGE,
    ERR_EVENT_RATE,
    EVENT_BURST,
    StringLib,
    strtod,
)
from motionvm.runtime.errors import RuntimeFault


class FakeRuntime:
    """The parts of the HMPL run time a library uses."""

    def __init__(self) -> None:
        self.mem = Memory(1 << 20)
        self.lines: list[str] = []
        self.events: list[tuple[str, object]] = []
        self.sim_time = 0.0

    def emit(self, text: str) -> None:
        self.lines.append(text)

    def emit_event(self, kind: str, payload) -> None:
        self.events.append((kind, payload))


@pytest.fixture
def rt() -> FakeRuntime:
    return FakeRuntime()


@pytest.fixture
def lib(rt) -> StringLib:
    return StringLib(rt)


def cstr(rt, text: bytes, size: int | None = None) -> int:
    """A char array of `size` bytes (default: just fits) holding `text`."""
    addr = rt.mem.alloc_static(size or len(text) + 1)
    rt.mem.write_cstr(addr, text)
    return addr


def ints(rt, values: list[int]) -> int:
    addr = rt.mem.alloc_static(4 * len(values))
    rt.mem.write_bytes(addr, struct.pack(f"<{len(values)}i", *values))
    return addr


def read_ints(rt, addr: int, n: int) -> list[int]:
    return list(struct.unpack(f"<{n}i", rt.mem.read_bytes(addr, 4 * n)))


def test_registered_names():
    names = set(StringLib.builtin_methods())
    assert names == {
        "Print",
        "StringPrint",
        "StringLen",
        "IsStringEqual",
        "StrFindChar",
        "StrFindCharEx",
        "StrFindStr",
        "StringCopy",
        "StringCopyEx",
        "StringCat",
        "StringCatEx",
        "StringToDouble",
        "MemoryCopy",
        "MemorySet",
        "IsMemoryEqual",
        "SendEvent",
        "SendMsgEvent",
    }


# ------------------------------------------------------------ 3.2 Print, 3.3 StringPrint


def test_print_manual_example(rt, lib):
    s = cstr(rt, b"hello world")
    n = lib.Print(cstr(rt, b"var1: %d, var2: %f, str: %s"), 321, 1428.57, s)
    lib.Print(cstr(rt, b"var2: %e"), 1428.57)
    lib.Print(cstr(rt, b"var2: %g"), 1428.57)
    assert rt.lines == [
        "var1: 321, var2: 1428.570000, str: hello world",
        "var2: 1.428570e+03",
        "var2: 1428.57",
    ]
    assert n == len(rt.lines[0])


def test_print_decodes_latin1(rt, lib):
    lib.Print(cstr(rt, b"\xb0C %d"), 5)
    assert rt.lines == ["\u00b0C 5"]


def test_messages_decode_utf8_and_a_stray_byte_as_latin1(rt, lib):
    lib.Print(cstr(rt, "25 °C, 回原點".encode()))
    lib.Print(cstr(rt, b"%cC = " + "°C".encode()), 0xB0)  # a stray byte, then UTF-8
    lib.SendMsgEvent(cstr(rt, "Störung".encode()))
    assert rt.lines == ["25 °C, 回原點", "°C = °C", "Störung"]
    assert rt.events == [("msg", "Störung")]


def test_print_faults(rt, lib):
    with pytest.raises(RuntimeFault, match="Print: format needs 2 arguments, got 1"):
        lib.Print(cstr(rt, b"%d %d"), 1)
    assert lib.Print(cstr(rt, b"%512d"), 1) == 512
    with pytest.raises(RuntimeFault, match="null"):
        lib.Print(0)


def test_stringprint_manual_example(rt, lib):
    dest = rt.mem.alloc_static(80)
    s = cstr(rt, b"hello world")
    n = lib.StringPrint(dest, cstr(rt, b"var1: %d, var2: %f, str: %s"), 321, 1428.57, s)
    assert rt.mem.read_cstr(dest) == b"var1: 321, var2: 1428.570000, str: hello world"
    assert n == 46
    lib.StringPrint(dest, cstr(rt, b"var2: %e"), 1428.57)
    assert rt.mem.read_cstr(dest) == b"var2: 1.428570e+03"
    lib.StringPrint(dest, cstr(rt, b"var2: %g"), 1428.57)
    assert rt.mem.read_cstr(dest) == b"var2: 1428.57"
    assert rt.lines == []


def test_stringprint_overflow_writes_nothing(rt, lib):
    dest = cstr(rt, b"old", 8)
    assert lib.StringPrint(dest, cstr(rt, b"%s"), cstr(rt, b"1234567")) == 7
    lib.StringPrint(dest, cstr(rt, b"abc"))
    with pytest.raises(RuntimeFault, match=r"StringPrint: string overflow: 9 bytes .* 8 bytes"):
        lib.StringPrint(dest, cstr(rt, b"%d"), 12345678)
    assert rt.mem.read_cstr(dest) == b"abc"


def test_over_512_characters_returns_minus_one(rt, lib):
    # Manual 3.1: an HMPL string holds at most HMPL_STR_MAX_LEN (512) characters;
    # 3.2/3.3: Print and StringPrint return -1 on an error, and print or write nothing.
    assert lib.Print(cstr(rt, b"%513d"), 1) == -1
    assert lib.Print(cstr(rt, b"%5000d"), 1) == -1  # wider than any field formatted
    assert lib.Print(cstr(rt, b"%.5000f"), 1.0) == -1
    assert rt.lines == []
    big = cstr(rt, b"old", 1024)
    assert lib.StringPrint(big, cstr(rt, b"%600s"), cstr(rt, b"x")) == -1
    assert lib.StringPrint(big, cstr(rt, b"%*d"), 9999, 1) == -1
    assert rt.mem.read_cstr(big) == b"old"
    assert lib.StringPrint(big, cstr(rt, b"%512s"), cstr(rt, b"x")) == 512
    small = cstr(rt, b"", 8)
    assert lib.StringPrint(small, cstr(rt, b"%600s"), cstr(rt, b"x")) == -1
    with pytest.raises(RuntimeFault, match="StringPrint: string overflow"):
        lib.StringPrint(small, cstr(rt, b"%20s"), cstr(rt, b"x"))


# ------------------------------------------------------------ 3.4 - 3.8 queries


def test_stringlen(rt, lib):
    assert lib.StringLen(cstr(rt, b"hello world")) == 11
    assert lib.StringLen(cstr(rt, b"")) == 0


def test_isstringequal(rt, lib):
    s1, s2, s3 = cstr(rt, b"hello world"), cstr(rt, b"hello world"), cstr(rt, b"hello worldd")
    assert lib.IsStringEqual(s1, s2) == 1
    assert lib.IsStringEqual(s1, s3) == 0
    # only the text up to the terminator counts
    assert lib.IsStringEqual(s1, cstr(rt, b"hello world", 40)) == 1


def test_strfindchar(rt, lib):
    s = cstr(rt, b"hello world")
    assert lib.StrFindChar(s, ord("h")) == 0
    assert lib.StrFindChar(s, ord("l")) == 2
    assert lib.StrFindChar(s, ord("z")) == -1
    assert lib.StrFindChar(s, 0) == 11  # strchr finds the terminator
    assert lib.StrFindChar(cstr(rt, b"a\xe9b"), -23) == 1  # char -23 is byte 0xe9


def test_strfindcharex(rt, lib):
    s = cstr(rt, b"hello world")
    assert lib.StrFindCharEx(s, cstr(rt, b"lo "), 0) == 2
    assert lib.StrFindCharEx(s, cstr(rt, b"lo "), 1) == 0
    assert lib.StrFindCharEx(s, cstr(rt, b"zx!c"), 0) == -1
    assert lib.StrFindCharEx(s, cstr(rt, b"leh"), 1) == 4
    assert lib.StrFindCharEx(s, cstr(rt, b"helo wrd"), 1) == -1
    assert lib.StrFindCharEx(s, cstr(rt, b""), 0) == -1
    assert lib.StrFindCharEx(s, cstr(rt, b""), 5) == 0


def test_strfindstr(rt, lib):
    s = cstr(rt, b"hello world")
    assert lib.StrFindStr(s, cstr(rt, b"hel")) == 0
    assert lib.StrFindStr(s, cstr(rt, b"wor")) == 6
    assert lib.StrFindStr(s, cstr(rt, b"wol")) == -1
    assert lib.StrFindStr(s, cstr(rt, b"")) == 0


# ------------------------------------------------------------ 3.9 - 3.12 copy and concatenate


def test_stringcopy(rt, lib):
    dest = rt.mem.alloc_static(80)
    assert lib.StringCopy(dest, cstr(rt, b"hello world")) == 0
    lib.Print(cstr(rt, b"%s"), dest)
    assert rt.lines == ["hello world"]


def test_stringcopy_overflow_writes_nothing(rt, lib):
    dest = cstr(rt, b"keep", 11)
    with pytest.raises(
        RuntimeFault, match=r"StringCopy: string overflow: 12 bytes \(11 characters"
    ):
        lib.StringCopy(dest, cstr(rt, b"hello world"))
    assert rt.mem.read_cstr(dest) == b"keep"
    assert lib.StringCopy(dest, cstr(rt, b"hello worl")) == 0  # exactly fits


def test_stringcopyex_manual_example(rt, lib):
    src, dest = cstr(rt, b"hello world"), rt.mem.alloc_static(80)
    assert lib.StringCopyEx(dest, src, 6, 3) == 0
    assert rt.mem.read_cstr(dest) == b"wor"
    assert lib.StringCopyEx(dest, src, 6, -1) == 0
    assert rt.mem.read_cstr(dest) == b"world"
    assert lib.StringCopyEx(dest, src, 0, -1) == 0
    assert rt.mem.read_cstr(dest) == b"hello world"


def test_stringcopyex_ranges(rt, lib):
    src, dest = cstr(rt, b"hello"), cstr(rt, b"same", 80)
    assert lib.StringCopyEx(dest, src, 3, 100) == 0  # clamped at the end
    assert rt.mem.read_cstr(dest) == b"lo"
    assert lib.StringCopyEx(dest, src, 5, -1) == 0
    assert rt.mem.read_cstr(dest) == b""
    rt.mem.write_cstr(dest, b"same")
    for start, length in [(6, 1), (-1, 2), (0, -2)]:
        assert lib.StringCopyEx(dest, src, start, length) == ERR_ARG_OUT_OF_RANGE
    assert rt.mem.read_cstr(dest) == b"same"
    small = rt.mem.alloc_static(3)
    with pytest.raises(RuntimeFault, match="StringCopyEx: string overflow"):
        lib.StringCopyEx(small, src, 0, 3)


def test_stringcat(rt, lib):
    s = cstr(rt, b"hello", 80)
    assert lib.StringCat(s, cstr(rt, b" world")) == 0
    lib.Print(cstr(rt, b"%s"), s)
    assert rt.lines == ["hello world"]


def test_stringcat_overflow_writes_nothing(rt, lib):
    s = cstr(rt, b"hello", 8)
    with pytest.raises(RuntimeFault, match=r"StringCat: string overflow: 9 bytes .* 8 bytes"):
        lib.StringCat(s, cstr(rt, b"abc"))
    assert rt.mem.read_bytes(s, 8) == b"hello\0\0\0"
    assert lib.StringCat(s, cstr(rt, b"ab")) == 0
    assert rt.mem.read_cstr(s) == b"helloab"


def test_stringcatex_manual_example(rt, lib):
    src, dest = cstr(rt, b"friendsmy "), cstr(rt, b"hello ", 80)
    assert lib.StringCatEx(dest, src, 7, -1) == 0
    assert rt.mem.read_cstr(dest) == b"hello my "
    assert lib.StringCatEx(dest, src, 0, 7) == 0
    assert rt.mem.read_cstr(dest) == b"hello my friends"
    assert lib.StringCatEx(dest, src, 11, -1) == ERR_ARG_OUT_OF_RANGE
    assert rt.mem.read_cstr(dest) == b"hello my friends"
    small = cstr(rt, b"ab", 4)
    with pytest.raises(RuntimeFault, match="StringCatEx: string overflow"):
        lib.StringCatEx(small, src, 0, 2)


def test_unterminated_destination_faults(rt, lib):
    raw = rt.mem.alloc_static(4)
    rt.mem.write_bytes(raw, b"abcd")
    with pytest.raises(RuntimeFault, match="not terminated"):
        lib.StringCat(raw, cstr(rt, b""))


def test_null_and_dangling_pointers_fault(rt, lib):
    s = cstr(rt, b"x")
    with pytest.raises(RuntimeFault, match="null"):
        lib.StringLen(0)
    with pytest.raises(RuntimeFault, match="StringCopy: null destination"):
        lib.StringCopy(0, s)
    with pytest.raises(RuntimeFault, match="outside"):
        lib.StringCopy(rt.mem.size - 4, s)


# ------------------------------------------------------------ 3.13 StringToDouble


def test_stringtodouble(rt, lib):
    assert lib.StringToDouble(cstr(rt, b"1.234")) == 1.234


@pytest.mark.parametrize(
    "text, value",
    [
        (b"  -12.5e1xyz", -125.0),
        (b"+.5", 0.5),
        (b"7.", 7.0),
        (b"1e", 1.0),
        (b"1e+", 1.0),
        (b"abc", 0.0),
        (b"", 0.0),
        (b"-", 0.0),
        (b".", 0.0),
        (b"0x1p4", 16.0),
        (b"0x.8", 0.5),
        (b"0X1A", 26.0),
        (b"0x", 0.0),
        (b"1e999", float("inf")),
        (b"-INFINITY", float("-inf")),
        (b"infx", float("inf")),
        (b"\t\n 42", 42.0),
    ],
)
def test_strtod(text, value):
    assert strtod(text) == value


def test_strtod_nan():
    v = strtod(b"nan(123)")
    assert v != v


# ------------------------------------------------------------ 3.14 - 3.16 memory


def test_memorycopy_manual_example(rt, lib):
    a1 = ints(rt, [1, 2, 3, 4, 5])
    a2 = ints(rt, [11, 22, 33, 44, 55])
    a3 = ints(rt, [345, 456, 567, 678, 789])
    assert lib.MemoryCopy(a1, a2, 20) == 0
    assert read_ints(rt, a1, 5) == [11, 22, 33, 44, 55]
    assert lib.MemoryCopy(a1, a3, 4 * 3) == 0
    assert read_ints(rt, a1, 5) == [345, 456, 567, 44, 55]
    assert lib.MemoryCopy(a1 + 12, a3 + 12, 4 * 2) == 0
    assert read_ints(rt, a1, 5) == [345, 456, 567, 678, 789]


def test_memorycopy_overlap_and_faults(rt, lib):
    a = ints(rt, [1, 2, 3, 4, 5])
    assert lib.MemoryCopy(a + 4, a, 16) == 0  # memmove
    assert read_ints(rt, a, 5) == [1, 1, 2, 3, 4]
    b = ints(rt, [9, 9])
    with pytest.raises(RuntimeFault, match="MemoryCopy: destination overflow: 20 bytes .* 8 bytes"):
        lib.MemoryCopy(b, a, 20)
    assert read_ints(rt, b, 2) == [9, 9]
    with pytest.raises(RuntimeFault, match="MemoryCopy: source overflow"):
        lib.MemoryCopy(a, b, 12)
    assert lib.MemoryCopy(a, b, -1) == ERR_ARG_OUT_OF_RANGE
    assert lib.MemoryCopy(a, b, 0) == 0


def test_memoryset_manual_example(rt, lib):
    a = ints(rt, [1, 2, 3, 4, 5])
    assert lib.MemorySet(a, 0, 20) == 0
    assert read_ints(rt, a, 5) == [0, 0, 0, 0, 0]
    assert lib.MemorySet(a, 1, 4) == 0
    assert read_ints(rt, a, 5) == [16843009, 0, 0, 0, 0]
    assert lib.MemorySet(a, 0x1FF, 1) == 0  # stored as char
    assert read_ints(rt, a, 1) == [0x010101FF]


def test_memoryset_faults(rt, lib):
    a = ints(rt, [7, 7])
    with pytest.raises(RuntimeFault, match="MemorySet: destination overflow"):
        lib.MemorySet(a, 0, 9)
    assert read_ints(rt, a, 2) == [7, 7]
    assert lib.MemorySet(a, 0, -4) == ERR_ARG_OUT_OF_RANGE
    with pytest.raises(RuntimeFault, match="null"):
        lib.MemorySet(0, 0, 4)


def test_ismemoryequal_manual_example(rt, lib):
    a1 = ints(rt, [1, 2, 3, 4, 5])
    a2 = ints(rt, [1, 2, 3, 44, 55])
    assert lib.IsMemoryEqual(a1, a2, 20) == 0
    assert lib.IsMemoryEqual(a1, a2, 12) == 1
    assert lib.IsMemoryEqual(a1, a2, 0) == 1
    with pytest.raises(RuntimeFault, match="memory_ptr2 overflow"):
        lib.IsMemoryEqual(a1, a2 + 8, 20)
    with pytest.raises(RuntimeFault, match="negative"):
        lib.IsMemoryEqual(a1, a2, -1)


# ------------------------------------------------------------ 2.18 SendEvent, 2.19 SendMsgEvent


def test_sendmsgevent_manual_example(rt, lib):
    assert lib.SendMsgEvent(cstr(rt, b"variable: %d"), 88) == 0
    assert rt.events == [("msg", "variable: 88")]
    assert rt.lines == ["variable: 88"]


def test_sendmsgevent_truncates_to_128(rt, lib):
    assert lib.SendMsgEvent(cstr(rt, b"%200s"), cstr(rt, b"end")) == 0
    assert rt.events[0][1] == " " * 128
    assert lib.SendMsgEvent(cstr(rt, b"%-128s|"), cstr(rt, b"a")) == 0
    assert rt.lines[1] == "a" + " " * 127
    with pytest.raises(RuntimeFault, match="SendMsgEvent: format needs 1 arguments, got 0"):
        lib.SendMsgEvent(cstr(rt, b"%d"))


def test_sendevent(rt, lib):
    assert lib.SendEvent(42) == 0
    assert lib.SendEvent(-1) == 0  # unsigned short
    assert rt.events == [("event", 42), ("event", 65535)]
    assert rt.lines == ["event 42", "event 65535"]


@pytest.mark.parametrize("call", ["event", "msg"])
def test_rate_limit_refuses_bursts(rt, lib, call):
    fmt = cstr(rt, b"m")
    send = (lambda: lib.SendEvent(1)) if call == "event" else (lambda: lib.SendMsgEvent(fmt))
    results = [send() for _ in range(int(EVENT_BURST) + 5)]
    assert results[: int(EVENT_BURST)] == [0] * int(EVENT_BURST)
    assert results[int(EVENT_BURST) :] == [ERR_EVENT_RATE] * 5
    assert len(rt.events) == len(rt.lines) == EVENT_BURST
    rt.sim_time += 0.0015  # 1.5 tokens come back
    assert [send(), send()] == [0, ERR_EVENT_RATE]


def test_rate_limit_allows_one_per_cycle_forever(rt, lib):
    for cycle in range(5000):
        rt.sim_time = cycle * 0.001
        assert lib.SendEvent(cycle) == 0
    for cycle in range(5000, 5300):  # two per cycle: the burst drains, then half are refused
        rt.sim_time = cycle * 0.001
        lib.SendEvent(1)
        lib.SendEvent(2)
    assert 5000 + 300 + EVENT_BURST - 2 <= len(rt.events) <= 5000 + 300 + EVENT_BURST + 2


def test_event_and_message_limits_are_separate(rt, lib):
    for _ in range(int(EVENT_BURST)):
        lib.SendEvent(1)
    assert lib.SendEvent(1) == ERR_EVENT_RATE
    assert lib.SendMsgEvent(cstr(rt, b"still fine")) == 0


def test_a_format_in_a_char_array_is_read_again_after_it_changes(rt, lib):
    fmt = cstr(rt, b"%d,", 16)
    dest = cstr(rt, b"", 32)
    assert lib.StringPrint(dest, fmt, 7) == 2
    rt.mem.write_cstr(fmt, b"<%d>")
    assert lib.StringPrint(dest, fmt, 7) == 3
    assert rt.mem.read_cstr(dest) == b"<7>"
    rt.mem.write_cstr(fmt, b"%d")  # shorter: the old text's tail stays after the NUL
    assert lib.StringPrint(dest, fmt, 12) == 2
    assert rt.mem.read_cstr(dest) == b"12"


def test_a_format_in_a_finished_frame_faults(rt, lib):
    from motionvm.lang.hmpl.cmemory import TaskStack, shadow_pattern

    base = rt.mem.alloc_static(256, "stack")
    rt.mem.shadow[base : base + 256] = bytes(256)
    stack = TaskStack(rt.mem, base, 256)
    fp = stack.push(16, shadow_pattern(16))
    rt.mem.write_cstr(fp, b"%d!")
    dest = cstr(rt, b"", 32)
    assert lib.StringPrint(dest, fp, 5) == 2
    stack.pop(fp)
    with pytest.raises(RuntimeFault, match="StringPrint format"):
        lib.StringPrint(dest, fp, 5)


@pytest.mark.parametrize("size", [4, 255, 256, 400])
def test_string_built_ins_use_the_whole_object_and_not_a_byte_more(rt, lib, size):
    dest = cstr(rt, b"", size)
    part = cstr(rt, b"x")
    for _ in range(size - 1):
        assert lib.StringCat(dest, part) == 0
    assert lib.StringLen(dest) == size - 1
    with pytest.raises(RuntimeFault, match="overflow"):
        lib.StringCat(dest, part)
    fmt = cstr(rt, b"%s")
    assert lib.StringPrint(dest, fmt, cstr(rt, b"y" * (size - 1))) == size - 1
    with pytest.raises(RuntimeFault, match="overflow"):
        lib.StringPrint(dest, fmt, cstr(rt, b"y" * size))
    assert lib.StringCopy(dest, cstr(rt, b"z" * (size - 1))) == 0
    with pytest.raises(RuntimeFault, match="overflow"):
        lib.StringCopy(dest, cstr(rt, b"z" * size))
