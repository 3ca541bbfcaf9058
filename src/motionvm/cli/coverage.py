"""`--cov-report FORMAT:PATH` of `motionvm run` and `motionvm test`: LCOV and Cobertura XML.

The data is `motionvm.lang.coverage`'s (`{file: {"lines": {line: hits}, "branches":
{line: [[arm 0, arm 1], ...]}}}`, merged over the cases of a test run). LCOV (`DA:`,
`BRDA:`) is what VS Code's Coverage Gutters, genhtml and Codecov read; Cobertura XML is
what GitLab's coverage report and most CI servers read. `json` is the data itself
(for merging runs elsewhere). Paths are relative to the working directory where they
lie under it. Each file is written to a temporary file and renamed into place.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

from motionvm.cli.exits import UsageError

FORMATS = ("lcov", "xml", "json")


def parse_reports(values: list[str]) -> list[tuple[str, str]]:
    """(format, path) of each `--cov-report FORMAT:PATH`; UsageError for a bad one."""
    out = []
    for value in values:
        kind, colon, path = value.partition(":")
        if not colon or kind not in FORMATS or not path:
            raise UsageError(
                f"--cov-report wants FORMAT:PATH with FORMAT one of {', '.join(FORMATS)} "
                f"(lcov:coverage.info, xml:coverage.xml), got '{value}'"
            )
        out.append((kind, path))
    return out


def _shown(path: str) -> str:
    p = Path(path)
    try:
        return p.relative_to(Path.cwd()).as_posix()
    except ValueError:
        return p.as_posix()


def lcov(data: dict) -> str:
    """The LCOV tracefile of `data`."""
    out = ["TN:"]
    for path in sorted(data):
        d = data[path]
        out.append(f"SF:{_shown(path)}")
        taken_total = found = 0
        for line in sorted(d["branches"]):
            hits = d["lines"].get(line, 0)
            for block, arms in enumerate(d["branches"][line]):
                for branch, taken in enumerate(arms):
                    found += 1
                    taken_total += taken > 0
                    shown = "-" if hits == 0 and sum(arms) == 0 else str(taken)
                    out.append(f"BRDA:{line},{block},{branch},{shown}")
        out.append(f"BRF:{found}")
        out.append(f"BRH:{taken_total}")
        lines = d["lines"]
        for line in sorted(lines):
            out.append(f"DA:{line},{lines[line]}")
        out.append(f"LF:{len(lines)}")
        out.append(f"LH:{sum(1 for h in lines.values() if h > 0)}")
        out.append("end_of_record")
    return "\n".join(out) + "\n"


def _rate(hit: int, total: int) -> str:
    return f"{hit / total:.4f}" if total else "1"


def cobertura(data: dict) -> str:
    """The Cobertura XML report of `data`: one class per program file."""
    all_lines = sum(len(d["lines"]) for d in data.values())
    all_hit = sum(1 for d in data.values() for h in d["lines"].values() if h > 0)
    arms = [
        a for d in data.values() for blocks in d["branches"].values() for b in blocks for a in b
    ]
    root = ET.Element(
        "coverage",
        {
            "line-rate": _rate(all_hit, all_lines),
            "branch-rate": _rate(sum(1 for a in arms if a > 0), len(arms)),
            "lines-covered": str(all_hit),
            "lines-valid": str(all_lines),
            "branches-covered": str(sum(1 for a in arms if a > 0)),
            "branches-valid": str(len(arms)),
            "complexity": "0",
            "version": "motionvm",
            "timestamp": "0",
        },
    )
    ET.SubElement(ET.SubElement(root, "sources"), "source").text = "."
    classes = ET.SubElement(
        ET.SubElement(ET.SubElement(root, "packages"), "package", name="programs"), "classes"
    )
    for path in sorted(data):
        d = data[path]
        lines = d["lines"]
        mine = [a for b in d["branches"].values() for blk in b for a in blk]
        c = ET.SubElement(
            classes,
            "class",
            name=Path(path).name,
            filename=_shown(path),
            complexity="0",
            **{
                "line-rate": _rate(sum(1 for h in lines.values() if h > 0), len(lines)),
                "branch-rate": _rate(sum(1 for a in mine if a > 0), len(mine)),
            },
        )
        ET.SubElement(c, "methods")
        xlines = ET.SubElement(c, "lines")
        for line in sorted(lines):
            attrs = {"number": str(line), "hits": str(lines[line])}
            blocks = d["branches"].get(line)
            if blocks:
                flat = [a for blk in blocks for a in blk]
                covered = sum(1 for a in flat if a > 0)
                attrs["branch"] = "true"
                attrs["condition-coverage"] = (
                    f"{100 * covered // len(flat)}% ({covered}/{len(flat)})"
                )
            else:
                attrs["branch"] = "false"
            ET.SubElement(xlines, "line", attrs)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


def write_reports(reports: list[tuple[str, str]], data: dict) -> None:
    """Write each (format, path) report of `data`; UsageError if one cannot be written."""
    for kind, path in reports:
        if kind == "lcov":
            text = lcov(data)
        elif kind == "xml":
            text = cobertura(data)
        else:
            text = json.dumps(data, sort_keys=True) + "\n"
        try:
            _write_atomic(path, text)
        except OSError as exc:
            raise UsageError(f"--cov-report {kind}:{path}: {exc.strerror or exc}") from None


def read_json(path: str) -> dict:
    """Coverage data written as `json:PATH` (line numbers back to ints)."""
    raw = json.loads(Path(path).read_text(encoding="utf-8"))
    return {
        f: {
            "lines": {int(k): v for k, v in d["lines"].items()},
            "branches": {int(k): v for k, v in d["branches"].items()},
        }
        for f, d in raw.items()
    }


def _write_atomic(path: str, text: str) -> None:
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or Path("."))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
