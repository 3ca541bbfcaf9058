"""A function's check, kept for the next check of a changed program.

`motionvm check` lowers every function to find its diagnostics. A language server checks
a file again after every edit, and an edit changes one function: every other function
would report what it reported before. Lowering a function (and linting it) reads only
its own tree and what the program declares around it, so its diagnostics are kept under
a key of both:

- the function (`function_keys`): its tokens after preprocessing (text, line counted from
  its first token, column; with tokens of another file, the files and absolute lines)
  and the parser's state where it starts (typedef names, enum constants): what its tree
  is made of. A function that an edit above it moved is the same function; its
  diagnostics move by as many lines;
- the program around it (`environment`): the trees of every file-scope declaration that
  is not a function body, without their positions; the type, parameter names, definition
  and waiting of every function; the names whose address is taken and how each name is
  used as an array anywhere (both decide how globals are stored); the task files.
  Positions are left out so that an edit that adds a line keeps the other functions'
  checks: no kept entry points at or names a place outside its function (`put` keeps
  none that does).

Besides diagnostics, lowering asks for static memory (static locals, string literals);
a later function's message about a full memory counts it. So an entry also keeps those
requests, and a reused entry makes them again, in the compile's order: the memory, the
messages and the errors-per-file limit come out as lowering would make them. An entry
whose requests might not fit in the free memory is not reused (lowering reports what
then happens), nor kept when a request failed.

Only `check` uses it (no generated code is kept). At most MAX_ENTRIES functions are
kept, the least recently used dropped first.
"""

from __future__ import annotations

import re
from collections import OrderedDict
from dataclasses import dataclass
from hashlib import blake2b
from operator import attrgetter, itemgetter, sub
from struct import pack
from threading import Lock

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import FuncFacts, scan
from motionvm.lang.hmpl.cmemory import ALIGN, RED_ZONE
from motionvm.lang.hmpl.symbols import FuncSym
from motionvm.source.diagnostics import Diagnostic
from motionvm.source.files import SourcePos

MAX_ENTRIES = 50_000
"""Functions kept (all open files of a language server together); an entry holds a
digest, the function's messages and its memory requests: some hundred bytes."""

_PLACE = re.compile(r":\d+:\d+|\bline \d")  # a message that names a place
_POS = itemgetter(2)  # a Token's position
_LINE = attrgetter("line")
_COL = attrgetter("col")
_FILE = attrgetter("file")


def _digest(value: object) -> bytes:
    return blake2b(repr(value).encode(), digest_size=16).digest()


@dataclass(frozen=True, slots=True)
class FunctionKey:
    """What a function's tree is made of; `first` is the line of its first token."""

    digest: bytes
    file: str
    first: int
    last: int
    movable: bool
    """False when tokens of other files are in it: its lines are then absolute."""


def parser_state(typedefs: set[str], enumerators: dict[str, int]) -> tuple:
    """The parser's state that shapes the next tree: typedef names, enum constants."""
    return tuple(sorted(typedefs)), tuple(enumerators.items())


def function_keys(tokens: list, texts: list[str], spans: list[tuple]) -> dict[int, FunctionKey]:
    """The key of each function definition: `texts` are the tokens' texts, `spans` holds
    (FuncDef, first token index, index after its last token, `parser_state` at its
    start); by `id` of the FuncDef."""
    out: dict[int, FunctionKey] = {}
    if not spans:
        return out
    where = list(map(_POS, tokens))
    lines = list(map(_LINE, where))
    count = len(lines)
    # 8 bytes a token: its line less the line of the token before it (moves with the
    # function); its line; its column
    steps = pack(f"{count}q", 0, *map(sub, lines[1:], lines[:-1]))
    absolute = pack(f"{count}q", *lines)
    cols = pack(f"{count}q", *map(_COL, where))
    files = list(map(_FILE, where))
    last_state, state_digest = None, b""
    for fd, start, end, state in spans:
        if state != last_state:
            last_state, state_digest = state, _digest(state)
        file = files[start]
        movable = files[start:end].count(file) == end - start
        text = "\x00".join(texts[start:end]).encode()
        h = blake2b(state_digest, digest_size=16)
        h.update(f"{end - start} {len(text)} {file!r}".encode())
        h.update(text)
        if movable:
            h.update(steps[8 * start + 8 : 8 * end])
        else:
            h.update(repr(files[start:end]).encode())
            h.update(absolute[8 * start : 8 * end])
        h.update(cols[8 * start : 8 * end])
        out[id(fd)] = FunctionKey(h.digest(), file, lines[start], lines[end - 1], movable)
    return out


def environment(units: list, scopes: list, addr_taken: set[str], array_uses: dict) -> bytes:
    """The digest of what a function's lowering reads besides its own tree (see above).
    `units`: the program's task units; `scopes`: the global scope, then each task's.
    Positions are left out: a kept entry names no place outside its function (`put`)."""
    parts: list = []
    for u in units:
        parts.append((u.task, u.path))
        parts.extend(
            _shape(item)
            for item in u.tu.items
            if not (type(item) is n.FuncDef and item.body is not None)
        )
    for scope in scopes:
        for name, sym in scope.names.items():
            if isinstance(sym, FuncSym):
                parts.append(
                    (name, sym.task, str(sym.type), sym.param_names, sym.defined, sym.is_generator)
                )
    parts.append(sorted(addr_taken))
    parts.append(sorted((k, sorted(map(str, v))) for k, v in array_uses.items()))
    return _digest(parts)


def _shape(node: object) -> object:
    """A tree without its positions: its node kinds, names and values."""
    if type(node) is SourcePos:
        return None
    if isinstance(node, tuple | list):
        return tuple(map(_shape, node))
    names = getattr(node, "__dataclass_fields__", None)
    if names is None:
        return node
    return (type(node).__name__, *(_shape(getattr(node, k)) for k in names))


@dataclass(frozen=True, slots=True)
class Entry:
    """A function's check: its messages and static memory requests, as first made."""

    first: int
    diagnostics: tuple[Diagnostic, ...]
    requests: tuple[tuple, ...]
    """(pos, size, name, align) of a static object; (pos, data) of a string literal."""
    need: int
    """Static memory [bytes] the requests take at most."""


class FunctionMemo:
    """Kept function checks by (environment, task, function key), least recent first.
    Checks on several threads (the studio's) may share it: a lock guards its tables."""

    def __init__(self, limit: int = MAX_ENTRIES) -> None:
        self.limit = limit
        self._entries: OrderedDict[tuple, Entry] = OrderedDict()
        # a function body's facts by its key's digest: (waits, callees, address-taken
        # names, its array uses)
        self._scans: OrderedDict[bytes, tuple] = OrderedDict()
        self.reused = 0
        """Entries found so far (a count for tests and benchmarks)."""
        self._lock = Lock()

    def __len__(self) -> int:
        return len(self._entries)

    def clear(self) -> None:
        with self._lock:
            self._entries.clear()
            self._scans.clear()

    def get(self, env: bytes, task: int, key: FunctionKey) -> Entry | None:
        with self._lock:
            found = self._entries.get((env, task, key.digest))
            if found is not None:
                if not key.movable and found.first != key.first:
                    return None
                self._entries.move_to_end((env, task, key.digest))
                self.reused += 1
            return found

    def scan(self, key: FunctionKey, body, uses: dict[str, set], blocking) -> FuncFacts:
        """The facts of a function body (`analysis.scan`) with its array uses added to
        `uses`, from the kept scan of the same tokens when there is one. Kept facts have
        no `assigned` (lowering scans again a function it lowers)."""
        with self._lock:
            kept = self._scans.get(key.digest)
            if kept is not None:
                self._scans.move_to_end(key.digest)
        if kept is None:
            facts, mine = FuncFacts(), {}
            scan(body, mine, facts, blocking)
            kept = (
                facts.waits,
                tuple(facts.callees),
                frozenset(facts.addr_taken),
                tuple((name, frozenset(found)) for name, found in mine.items()),
            )
            with self._lock:
                self._scans[key.digest] = kept
                while len(self._scans) > self.limit:
                    self._scans.popitem(last=False)
        else:
            facts = FuncFacts(kept[0], list(kept[1]), set(kept[2]))
        for name, found in kept[3]:
            has = uses.get(name)
            if has is None:
                uses[name] = set(found)
            else:
                has |= found
        return facts

    def put(
        self,
        env: bytes,
        task: int,
        key: FunctionKey,
        diagnostics: list[Diagnostic],
        requests: list[tuple | None],
    ) -> None:
        """Keep what lowering the function reported and asked for; not when a message
        points outside the function or names a place (it would not move with it)."""
        for d in diagnostics:
            if d.pos.file != key.file or not key.first <= d.pos.line <= key.last:
                return
            if _PLACE.search(d.message):
                return
        if None in requests:  # a request failed: lowering stopped there
            return
        need = 0
        for r in requests:
            size = r[1] if len(r) == 4 else len(r[1]) + 1
            align = r[3] if len(r) == 4 else 1
            need += max(size, 1) + max(align, ALIGN) + ALIGN + RED_ZONE
        entry = Entry(key.first, tuple(diagnostics), tuple(requests), need)
        with self._lock:
            self._entries[(env, task, key.digest)] = entry
            self._entries.move_to_end((env, task, key.digest))
            while len(self._entries) > self.limit:
                self._entries.popitem(last=False)


def moved(pos: SourcePos, file: str, delta: int) -> SourcePos:
    """`pos` of a kept entry in a function now `delta` lines further down."""
    if delta == 0 or pos.file != file:
        return pos
    return SourcePos(pos.file, pos.line + delta, pos.col)


CHECKS = FunctionMemo()
"""The process's kept function checks (content-addressed: any program may share them)."""
