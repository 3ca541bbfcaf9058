"""The drive's system variables and states that PDL programs use.

The manual has no table of them; this catalog holds every name its text and
examples use, with a type, an element count and whether a program may write it. The
checker reads it to resolve names; the drive run time implements the same names.
Lookup ignores case: the manual itself writes `X_vel_max` and `x_jvl`, `X_LL` and
`x_run` for one axis, so the drive's compiler cannot have been case-sensitive for
these names. States are bits of one status array; `address` is the bit index, the
value of `<state>`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class SysVar:
    """One system variable or state.

    kind: 'long' | 'short' | 'float' | 'state'. `size` is the element count. `address`
    is the bit index in the status array for states, the catalog index otherwise.
    `is_input` marks states the drive refreshes from its inputs or internal logic.
    """

    name: str
    kind: str
    size: int = 1
    read_only: bool = False
    doc: str = ""
    address: int = 0
    is_input: bool = False


# (name, kind, size, read_only, doc) — units follow the drive: counts, counts/s, ms.
_VARIABLES: list[tuple[str, str, int, bool, str]] = [
    ("X_vel_max", "long", 1, False, "maximum velocity of the X profile [count/s]"),
    ("X_acc", "long", 1, False, "acceleration of the X profile [count/s^2]"),
    ("X_dcc", "long", 1, False, "deceleration of the X profile [count/s^2]"),
    ("X_new_sm_fac", "long", 1, False, "smoothing factor of the X profile [ms]"),
    ("X_trg", "long", 1, False, "target position of X; writing it starts a move [count]"),
    ("X_jvl", "long", 1, False, "jog velocity of X; writing a non-zero value jogs [count/s]"),
    ("X_stop_m", "long", 1, False, "writing 1 stops the X motor"),
    ("x_ref_pos", "long", 1, True, "reference (commanded) position of X [count]"),
    ("vel_max", "long", 4, False, "maximum velocity per axis [count/s]"),
    ("abspos", "long", 4, False, "absolute target position per axis [count]"),
    ("ref_pos", "float", 4, True, "reference position per axis [count]"),
    ("fclk", "long", 1, True, "free-running phase counter, 15000 Hz, wraps as signed 32-bit"),
    ("lcdout", "long", 1, False, "LCD output register: each write sends the low byte"),
    ("task_num", "long", 1, True, "number (0..3) of the executing task"),
    ("task_prior", "long", 4, False, "phases per scheduling cycle of each task (<= 0 means 1)"),
]
_VARIABLES += [(f"ltest{i}", "long", 1, False, "host-visible test variable") for i in range(1, 17)]
_VARIABLES += [
    (f"ff{i}", "float", 1, False, "host-visible float test variable") for i in range(1, 17)
]

_STATES: list[tuple[str, bool, str]] = [
    ("x_run", True, "X axis is moving"),
    ("y1_run", True, "axis Y1 is moving"),
    ("x_home", True, "X home switch found"),
    ("LEFT_LIM", True, "left limit switch"),
    ("X_LL", True, "X left-limit signal"),
    ("vacum_sl", False, "output: vacuum solenoid (manual §2.4.3)"),
    ("anysensor", True, "placeholder sensor of the manual's §2.1.4 example"),
    ("s1", False, "placeholder state of the manual's sttovar examples"),
    ("s2", False, "placeholder state of the manual's sttovar examples"),
    ("s3", False, "placeholder state of the manual's sttovar examples"),
]
_STATES += [(f"IN{i}", True, f"digital input {i}") for i in range(1, 17)]
_STATES += [(f"OUT{i}", False, f"digital output {i}") for i in range(1, 17)]


def _build() -> dict[str, SysVar]:
    table: dict[str, SysVar] = {}
    for i, (name, kind, size, ro, doc) in enumerate(_VARIABLES):
        table[name.lower()] = SysVar(name, kind, size, ro, doc, i)
    for bit, (name, is_input, doc) in enumerate(_STATES):
        # Inputs and internal states may be written, but the drive refreshes them.
        table[name.lower()] = SysVar(name, "state", 1, False, doc, bit, is_input)
    return table


SYSVARS: dict[str, SysVar] = _build()


def lookup(name: str) -> SysVar | None:
    """The system variable or state of that name (any case), or None."""
    return SYSVARS.get(name.lower())


def is_state(name: str) -> bool:
    """True if `name` is a system state."""
    sv = SYSVARS.get(name.lower())
    return sv is not None and sv.kind == "state"


def names() -> list[str]:
    """Every catalog name in its canonical spelling (for 'did you mean')."""
    return [sv.name for sv in SYSVARS.values()]
