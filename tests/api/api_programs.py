"""Programs shared by the host API tests."""

from __future__ import annotations

from pathlib import Path

COUNTER = """\
int count;
int table[5];
double speed = 1.5;
void main() {
    int i;
    for (i = 0; i < 10; i++) {
        count += 1;
        Sleep(1);
    }
    Print("count %d table[3] %d", count, table[3]);
}
"""
"""Task 0 counts one per cycle for 10 ms, then prints."""

CELL_GDL = """\
MODULE cell;
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT start [ BOARD$NAME = io, CHANNEL = 1 ];
  INTEGER$VARIABLE runs [ ];
  INTEGER$VARIABLE zero [ ];

  PROCEDURE counter;
  DECLARE { STATUS OF start };
  BEGIN
    VALUE OF runs = VALUE OF runs + 1;
    IF VALUE OF runs = 2 THEN
      VALUE OF runs = 10 / VALUE OF zero;
    END$IF;
  END$PROCEDURE;
END$MODULE;
"""
"""A procedure run by each change of `start.STATUS`; its second run divides by zero."""

DRIVE_PDL = """\
#long n;
#long _lp(0, 100) lim;
#task/0;
loop(3) do
  sleep 1;
  n++;
end;
n = n / lim;
halt;
"""
"""A drive task that counts to 3, then divides by `lim` (0 unless written)."""


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path
