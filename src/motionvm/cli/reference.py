"""`motionvm builtins | errors`: the manual's built-ins and error codes, looked up.

Both read the package's copies of the manual's tables (`data/hmpl_api.json`,
`data/hmpl_errors.json`); nothing here runs a program.
"""

from __future__ import annotations

import fnmatch
import json
import re
import sys
import textwrap
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

from motionvm.cli.exits import EXIT_OK, UsageError
from motionvm.lang import language_named
from motionvm.source.suggest import ranked

WIDTH = 79
"""Text is wrapped to this many columns (fixed, so the output does not depend on the terminal)."""


def _data(name: str):
    return json.loads(resources.files("motionvm.data").joinpath(name).read_text("utf-8"))


def _did_you_mean(word: str, names: list[str]) -> str:
    close = ranked(word, names)
    return f"; did you mean {', '.join(close)}?" if close else ""


# ------------------------------------------------------------------ builtins


def _chapter_of(section: str) -> int:
    return int(section.split(".")[0])


def builtin_rows() -> list[dict]:
    """Every built-in in manual order, with the manual's description and whether
    motionvm implements it."""
    docs = language_named("HMPL").docs()
    rows = []
    for e in _data("hmpl_api.json"):
        name = e["name"]
        doc = docs[name]
        rows.append(
            {
                "name": name,
                "prototype": doc.signature,
                "section": doc.section,
                "chapter": _chapter_of(doc.section),
                "chapter_title": e["chapter"],
                "implemented": doc.implemented,
                "purpose": e["purpose"],
                "returns": e["returns"],
                "returns_desc": e["returns_desc"],
                "params": e["params"],
                "remarks": e["remarks"],
                "min_version": e["min_version"],
            }
        )
    return rows


_LIST_FIELDS = (
    "name",
    "prototype",
    "section",
    "chapter",
    "chapter_title",
    "implemented",
    "purpose",
)


def cmd_builtins(args) -> int:
    rows = builtin_rows()
    search = None
    if args.name is not None:
        if not any(r["name"] == args.name for r in rows) and _is_search(args.name, rows):
            search = args.name
        elif args.missing or args.chapter is not None:
            raise UsageError(
                "builtins NAME describes one built-in; --missing and --chapter filter the list"
            )
        else:
            row = _find_builtin(args.name, rows)
            if args.json:
                _write_json(row)
            else:
                sys.stdout.write(describe_builtin(row))
            return EXIT_OK
    if args.chapter is not None:
        chapters = sorted({r["chapter"] for r in rows})
        if args.chapter not in chapters:
            raise UsageError(
                f"chapter {args.chapter} of the manual has no built-ins; chapters with "
                f"built-ins: {', '.join(map(str, chapters))}"
            )
        rows = [r for r in rows if r["chapter"] == args.chapter]
    shown = [r for r in rows if not r["implemented"]] if args.missing else rows
    if search is not None:
        shown = matching(search, shown)
        if not shown:
            names = [r["name"] for r in rows]
            raise UsageError(f"no HMPL built-in matches '{search}'{_did_you_mean(search, names)}")
    if args.json:
        _write_json([{k: r[k] for k in _LIST_FIELDS} for r in shown])
        return EXIT_OK
    if shown:
        width = max(len(r["name"]) for r in shown)
        for r in shown:
            mark = "yes" if r["implemented"] else "no "
            sys.stdout.write(f"{r['name']:<{width}}  {mark}  {r['section']:<7} {r['prototype']}\n")
    if search is not None:
        plural = "" if len(shown) == 1 else "s"
        sys.stdout.write(f"{len(shown)} built-in{plural} match '{search}', the closest first\n")
        return EXIT_OK
    done = sum(r["implemented"] for r in rows)
    where = f" of chapter {args.chapter} ({rows[0]['chapter_title']})" if args.chapter else ""
    if args.missing:
        sys.stdout.write(f"{len(rows) - done} of {len(rows)} built-ins{where} not implemented\n")
    else:
        sys.stdout.write(f"{done} of {len(rows)} built-ins{where} implemented\n")
    return EXIT_OK


_GLOB = re.compile(r"[*?\[]")


def _is_search(word: str, rows: list[dict]) -> bool:
    """Whether `builtins WORD` lists the built-ins WORD finds rather than describing one:
    a glob (`Move*`), or a word that names no built-in but is part of some name or
    purpose. A name in the wrong case (`moveabs`: HMPL tells case) or of a constant
    (`PI`) is no search."""
    if _GLOB.search(word):
        return True
    lower = word.lower()
    if any(r["name"].lower() == lower for r in rows) or word in language_named("HMPL").docs():
        return False  # a name in the wrong case, or a constant: `_find_builtin` says so
    return bool(matching(word, rows))


def matching(word: str, rows: list[dict]) -> list[dict]:
    """The rows `word` finds, the closest names first (`ranked`): with `*`, `?` or `[...]`
    the names that match it as a glob, case-insensitively; else the names that contain
    it, then the built-ins whose purpose mentions it."""
    lower = word.lower()
    if _GLOB.search(word):
        found = [r for r in rows if fnmatch.fnmatchcase(r["name"].lower(), lower)]
        return _by_closeness(word.strip("*?"), found)
    by_name = [r for r in rows if lower in r["name"].lower()]
    by_purpose = [
        r
        for r in rows
        if r not in by_name and re.search(rf"\b{re.escape(lower)}", r["purpose"].lower())
    ]
    return _by_closeness(word, by_name) + _by_closeness(word, by_purpose)


def _by_closeness(word: str, rows: list[dict]) -> list[dict]:
    order = ranked(word, [r["name"] for r in rows], n=len(rows), cutoff=0.0)
    at = {name: i for i, name in enumerate(order)}
    return sorted(rows, key=lambda r: at[r["name"]])


def _find_builtin(name: str, rows: list[dict]) -> dict:
    for r in rows:
        if r["name"] == name:
            return r
    names = [r["name"] for r in rows]
    hint = _did_you_mean(name, names)
    const = language_named("HMPL").docs().get(name)
    if const is not None and const.kind == "constant":
        hint = f"; {name} is a constant (= {const.value:g}, manual {const.section})" + hint
    raise UsageError(f"no HMPL built-in is called '{name}'{hint}")


def _write_json(value) -> None:
    json.dump(value, sys.stdout, indent=1, ensure_ascii=False)
    sys.stdout.write("\n")


def _para(text: str, indent: str = "  ") -> str:
    return textwrap.fill(text, WIDTH, initial_indent=indent, subsequent_indent=indent) + "\n"


def describe_builtin(row: dict) -> str:
    """What `motionvm builtins NAME` prints: the manual's entry and motionvm's status."""
    status = "implemented" if row["implemented"] else "NOT implemented by motionvm"
    out = [
        f"{row['name']}  (manual {row['section']}, {row['chapter_title']}): {status}\n",
        f"  {row['prototype']}\n",
        "\n",
        _para(row["purpose"]),
    ]
    if not row["implemented"]:
        out.append(_para("A call compiles with a warning; the task stops with an error there."))
    params = row["params"]
    if params:
        out.append("\nParameters:\n")
        nw = max(len(p["name"]) for p in params)
        tw = max(len(p["type"]) for p in params)
        for p in params:
            head = f"  {p['name']:<{nw}}  {p['type']:<{tw}}  {p['dir'] or 'in':<3}  "
            text = (p["desc"] or "").strip()
            if p["unit"]:
                text += f" Unit: {p['unit']}."
            out.append(
                textwrap.fill(text, WIDTH, initial_indent=head, subsequent_indent=" " * len(head))
                + "\n"
            )
    if row["returns"] is not None:
        out.append(f"\nReturns: {row['returns']}\n")
    elif row["returns_desc"]:
        out.append("\nValue (a macro):\n")
    if row["returns_desc"] and row["returns"] != "void":
        out.append(_para(row["returns_desc"]))
    if row["remarks"]:
        out.append("\nRemarks:\n")
        for r in row["remarks"]:
            out.append(
                textwrap.fill(r, WIDTH, initial_indent="  - ", subsequent_indent="    ") + "\n"
            )
    if row["min_version"]:
        out.append(f"\nSince: {row['min_version']}\n")
    return "".join(out)


# ------------------------------------------------------------------ error codes

_TABLES = {
    "system": ("18.1.1", "system error"),
    "axis": ("18.1.2", "axis error"),
    "group": ("18.1.3", "group error"),
}
_PREFIX = {0x83: "axis", 0x82: "group"}
"""The top byte of an axis or group code: 0x83XXCCCC, XX = the axis id, CCCC the error."""


@dataclass(frozen=True)
class ErrorCode:
    """One row of the manual's chapter 18 tables (`XX` in an axis or group code: the id)."""

    code: str
    name: str
    table: str
    desc: str
    section: str


@lru_cache(maxsize=1)
def error_tables() -> tuple[dict[int, ErrorCode], dict[tuple[str, int], ErrorCode]]:
    """(system codes by value, axis and group codes by (table, CCCC))."""
    system: dict[int, ErrorCode] = {}
    per_id: dict[tuple[str, int], ErrorCode] = {}
    for e in _data("hmpl_errors.json"):
        entry = ErrorCode(e["code"], e["name"], e["table"], e["desc"], e["section"])
        if entry.table in ("axis", "group"):
            per_id[(entry.table, int(entry.code[-4:], 16))] = entry
        elif entry.table == "system":
            system[int(entry.code, 16)] = entry
    return system, per_id


def _parse_code(text: str) -> int | None:
    """A code as hex (0x...) or decimal (signed or not); None if it is neither."""
    t = text.strip().lower()
    try:
        value = int(t, 16) if t.startswith(("0x", "-0x")) else int(t, 10)
    except ValueError:
        return None
    if not -(2**31) <= value < 2**32:
        return None
    return value & 0xFFFFFFFF


def lookup_error(text: str) -> tuple[int | None, ErrorCode, int | None]:
    """(the code's value, its table row, the axis or group id) for a code or a name;
    UsageError for what the tables do not have (with a hint when the text, read as hex,
    is a code: `83000136` is decimal, `0x83000136` meant)."""
    try:
        return _lookup_error(text)
    except UsageError as exc:
        t = text.strip()
        if re.fullmatch(r"[0-9a-fA-F]+|[0-9a-fA-F]{2}[xX]{2}[0-9a-fA-F]{4}", t):
            try:
                _lookup_error(f"0x{t}")
            except UsageError:
                pass
            else:
                raise UsageError(f"{exc} (did you mean 0x{t}, in hex?)") from None
        raise


def _lookup_error(text: str) -> tuple[int | None, ErrorCode, int | None]:
    system, per_id = error_tables()
    generic = re.fullmatch(r"0x(8[23])xx([0-9a-f]{4})", text.strip().lower())
    if generic:  # the manual's own spelling, 0x83XX0136: any axis
        table = _PREFIX[int(generic.group(1), 16)]
        found = per_id.get((table, int(generic.group(2), 16)))
        if found is not None:
            return None, found, None
        raise UsageError(
            f"{text} is not in the manual's {_TABLES[table][1]} table ({_TABLES[table][0]})"
        )
    value = _parse_code(text)
    if value is None:
        every = [*system.values(), *per_id.values()]
        for e in every:
            if e.name.lower() == text.strip().lower():
                return None, e, None
        hint = _did_you_mean(text.strip(), [e.name for e in every])
        raise UsageError(
            f"'{text}' is neither an error code (0x83000136, 2197815606) nor the name of one{hint}"
        )
    if value in system:
        return value, system[value], None
    table = _PREFIX.get(value >> 24)
    if table is not None:
        ident, low = (value >> 16) & 0xFF, value & 0xFFFF
        found = per_id.get((table, low))
        if found is not None:
            return value, found, ident
        section, what = _TABLES[table]
        raise UsageError(
            f"0x{value:08x} has the form of {'an' if table == 'axis' else 'a'} {what} code ({table} {ident}), but 0x{low:04x} "
            f"is not in the manual's table {section}"
        )
    raise UsageError(f"0x{value:08x} is not an error code of the manual's chapter 18")


def describe_error(value: int | None, entry: ErrorCode, ident: int | None) -> str:
    section, what = _TABLES[entry.table]
    if value is None:
        head = f"{entry.code}  {entry.name}"
    else:
        head = f"0x{value:08x}  {entry.name}"
        if ident is not None:
            head += f"  ({entry.table} {ident})"
    out = [head + "\n", _para(entry.desc)]
    if entry.table in ("axis", "group"):
        shape = f"0x{entry.code[2:4]}XX{entry.code[-4:]}"
        out.append(_para(f"Manual {section}, {what}s: {shape}, XX = the {entry.table} id in hex."))
    else:
        out.append(_para(f"Manual {section}, {what}s."))
    if value is not None:
        signed = value - 2**32 if value >= 2**31 else value
        shown = "" if signed == value else f" (Print's %d shows {signed})"
        out.append(_para(f"In decimal: {value}{shown}."))
    return "".join(out)


def cmd_errors(args) -> int:
    if args.code is None:
        system, per_id = error_tables()
        for e in [*system.values(), *per_id.values()]:
            code = e.code if e.table == "system" else f"0x{e.code[2:4]}XX{e.code[-4:]}"
            sys.stdout.write(f"{code}  {e.name:<40} {e.desc}\n")
        return EXIT_OK
    if _parse_code(args.code) == 0:
        sys.stdout.write("0x00000000  no error: built-ins return 0 on success\n")
        return EXIT_OK
    sys.stdout.write(describe_error(*lookup_error(args.code)))
    return EXIT_OK
