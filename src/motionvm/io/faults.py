"""Faults injected into the machine (a scenario's fault events, `Simulation.inject_fault`).

| fault | target | what happens |
|---|---|---|
| `drive` | `axis`, `code` (default 0x1000) | the drive raises an alarm with that error code (0x603F): the axis reacts as to a drive fault (table 5.1.1.4: disabled, error stop); IsDriveErr / GetDriveErr report it |
| `encoder_loss` | `axis` | the drive's encoder is lost: its position freezes and it faults with 0x7305 |
| `following_error` | `axis` | the position error exceeds its limit: the axis is disabled (eERR_AXIS_POS_ERR) |
| `hw_limit` | `axis`, `side` ("left" or "right") | the limit switch of that side is on from now on (0x60FD bit 0 or 1): the axis reacts as to a limit switch |
| `slave_lost` | `slave` | the slave leaves the bus for good: GetSlvECATSt answers 1 (Init), a drive's axis faults, an I/O slave's outputs drop to 0 |
| `estop` | - | the E-stop: every axis is disabled and every task stops, as with the E-stop input |

`check_fault` validates a fault's arguments against the machine (ValueError naming the
key); `inject_fault` applies it at once.
"""

from __future__ import annotations

from motionvm.drives.objects import DI_NEGATIVE_LIMIT, DI_POSITIVE_LIMIT, ERR_GENERIC

FAULTS = ("drive", "encoder_loss", "following_error", "hw_limit", "slave_lost", "estop")
"""The kinds of fault, as a scenario's `fault = "..."` names them."""
TARGET_KEYS = {
    "drive": ("axis",),
    "encoder_loss": ("axis",),
    "following_error": ("axis",),
    "hw_limit": ("axis", "side"),
    "slave_lost": ("slave",),
    "estop": (),
}
OPTIONAL_KEYS = {"drive": ("code",)}
SIDES = {"left": DI_NEGATIVE_LIMIT, "right": DI_POSITIVE_LIMIT}


def _int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def check_fault(io, kind: object, args: dict) -> list[tuple[str | None, str]]:
    """The problems of a fault (key or None, message); [] if it can be injected.
    `args`: axis, slave, code, side as given (absent keys missing)."""
    if not isinstance(kind, str) or kind not in FAULTS:
        return [("fault", f"fault = {kind!r}: must be one of {', '.join(FAULTS)}")]
    problems: list[tuple[str | None, str]] = []
    allowed = set(TARGET_KEYS[kind]) | set(OPTIONAL_KEYS.get(kind, ()))
    for key in ("axis", "slave", "code", "side"):
        if key in args and key not in allowed:
            problems.append((key, f"'{key}' does not apply to fault = {kind!r}"))
    for key in TARGET_KEYS[kind]:
        if key not in args:
            problems.append((None, f"fault = {kind!r} needs '{key}'"))
    n_axes = io.motion.n_axes
    if "axis" in args and "axis" in allowed:
        axis = args["axis"]
        if not _int(axis) or not 0 <= axis < n_axes:
            problems.append(("axis", f"axis = {axis!r}: must be an axis id from 0 to {n_axes - 1}"))
    if "slave" in args and "slave" in allowed:
        slave = args["slave"]
        n = len(io.bus)
        if not _int(slave) or not 0 <= slave < n:
            problems.append(("slave", f"slave = {slave!r}: must be a slave id from 0 to {n - 1}"))
    if "code" in args and "code" in allowed:
        code = args["code"]
        if not _int(code) or not 1 <= code <= 0xFFFF:
            problems.append(
                ("code", f"code = {code!r}: must be a drive error code from 1 to 0xFFFF")
            )
    side = args.get("side")
    if "side" in args and "side" in allowed and (not isinstance(side, str) or side not in SIDES):
        problems.append(("side", f'side = {args["side"]!r}: must be "left" or "right"'))
    return problems


def inject_fault(io, kind: str, **args) -> None:
    """Apply a fault now (see the module docstring); ValueError for a bad one."""
    problems = check_fault(io, kind, args)
    if problems:
        raise ValueError("; ".join(message for _, message in problems))
    if kind == "estop":
        io.estop(0)
        return
    if kind == "slave_lost":
        io.lose_slave(args["slave"])
        return
    axis = io.motion.axes[args["axis"]]
    drive = axis.drive
    if kind == "drive":
        drive.inject_fault(args.get("code", ERR_GENERIC))
    elif kind == "encoder_loss":
        drive.encoder_loss()
    elif kind == "following_error":
        axis.position_error_fault()
    else:  # hw_limit: the switch's input is on for good (the sensors' external inputs)
        drive.sensors.external = drive.sensors.external | SIDES[args["side"]]
    axis.wake()
