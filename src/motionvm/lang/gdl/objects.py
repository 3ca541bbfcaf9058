"""The GDL object-type table: parameters, state variables, operators and activators.

The GDL description defines checks "per type" but lists almost no type in full,
so the compiler and the RTS are driven by this one table (shapes in `objspec`).
Entries marked [T] come from the description; everything else is motionvm's proposal.
`doc.py` renders the table into docs/lang/gdl.md.
"""

from __future__ import annotations

from motionvm.lang.gdl.objspec import (
    INT_LIMIT,
    ArgSpec,
    DeviceSpec,
    ObjType,
    OperatorSpec,
    ParamSpec,
    StateSpec,
    format_value,
)

__all__ = [
    "INT_LIMIT",
    "ArgSpec",
    "DeviceSpec",
    "ObjType",
    "OperatorSpec",
    "ParamSpec",
    "StateSpec",
    "format_value",
]

# ---------------------------------------------------------------- shared pieces

PRESENCE = ("PRESENT", "ABSENT")
DIAGN = ("NO$FAULT", "FAULT")
MOTION = ("STOPPED", "RUNNING")
POWER = ("ENABLED", "DISABLED")
DESCRIPTION = ParamSpec("DESCRIPTION", "string")
ARRAY_SIZE = ParamSpec("ARRAY$SIZE", "int", 1, 64, role="size")


def _diagn(force: bool = True) -> StateSpec:
    return StateSpec(
        "DIAGN$STATUS",
        "set",
        "rf" if force else "r",
        DIAGN,
        activator=True,
        default="NO$FAULT",
        machine=True,
    )


def _on_board(board: str, hi: int) -> tuple[ParamSpec, ParamSpec]:
    return (
        ParamSpec("BOARD$NAME", "name", types=(board,), role="parent", mandatory=True),
        ParamSpec("CHANNEL", "int", 1, hi, role="channel", mandatory=True),
    )


_SPEED_ARG = ArgSpec("speed", "int", 0, 3000, limit="max_speed")
_MOTOR_STATES = (
    StateSpec("CONSTANT$STATUS", "set", "rw", POWER, default="DISABLED"),
    _diagn(),
    StateSpec("OPERATING$CONDITION", "set", "r", MOTION, activator=True, default="STOPPED"),
    StateSpec("SPEED", "int", "r", lo=-3000, hi=3000, default=0),
)
_MOTION_PARAMS = (
    ParamSpec("MAX$SPEED", "int", 1, 3000, default=3000),
    ParamSpec("ACCELERATION", "int", 1, 1_000_000, default=30000),
)
_RUN = OperatorSpec("RUN$AT$SPEED", (_SPEED_ARG,), "ramp to `speed` [units/s] and keep it")
_STOP = OperatorSpec("STOP", (), "ramp down to standstill")
_MOVE = OperatorSpec(
    "MOVE$TO",
    (ArgSpec("position", "int", limit="travel"),),
    "trapezoidal move to `position` [units]; OPERATING$CONDITION STOPPED on arrival",
)

# ---------------------------------------------------------------- the catalogue

TYPES: tuple[ObjType, ...] = (
    ObjType(
        "MACHINE",
        "hardware",
        "the machine as a whole: mode and emergency stop",
        params=(DESCRIPTION,),
        states=(
            StateSpec(
                "OPERATING$MODE",
                "set",
                "rwf",
                ("MANUAL", "AUTOMATIC"),
                activator=True,
                default="MANUAL",
            ),
            StateSpec(
                "EMERGENCY$STOP", "digital", "rf", activator=True, default=False, machine=True
            ),
            StateSpec("CONSTANT$STATUS", "set", "rw", POWER + ("STANDBY",), default="DISABLED"),
            _diagn(),
        ),
    ),
    ObjType(
        "IO$BOARD",
        "hardware",
        "I/O board: parent of digital inputs, outputs and PWM outputs",
        params=(
            ParamSpec("SLOT", "int", 1, 16, mandatory=True),
            ParamSpec("INPUT$MODULE", "config", values=PRESENCE, default="PRESENT"),
            ParamSpec("OUTPUT$MODULE", "config", values=PRESENCE, default="PRESENT"),
            ParamSpec("PWM$MODULE", "config", values=PRESENCE, default="ABSENT"),
            DESCRIPTION,
        ),
        states=(_diagn(),),
        devices=(
            DeviceSpec("INPUT$MODULE", (1, 16), ("DIGITAL$INPUT",)),
            DeviceSpec("OUTPUT$MODULE", (1, 16), ("DIGITAL$OUTPUT",)),
            DeviceSpec("PWM$MODULE", (1, 4), ("PWM$OUTPUT",)),
        ),
    ),
    ObjType(
        "STEPPER$BOARD",
        "hardware",
        "stepper-motor board: parent of motors, axes, home inputs",
        params=(
            ParamSpec("SLOT", "int", 1, 16, mandatory=True),
            ParamSpec(
                "AXIS$MODULE",
                "config",
                values=PRESENCE + ("STEPPER$MOTOR", "STP$MOTOR$AXIS"),
                default="PRESENT",
            ),
            ParamSpec("HOME$MODULE", "config", values=PRESENCE, default="PRESENT"),
            DESCRIPTION,
        ),
        states=(_diagn(),),
        devices=(
            DeviceSpec("AXIS$MODULE", (1, 4), ("STEPPER$MOTOR", "STP$MOTOR$AXIS")),
            DeviceSpec("HOME$MODULE", (1, 4), ("STP$MOTOR$AXIS$HOME$INPUT",)),
        ),
    ),
    ObjType(
        "STEPPER$MOTOR",
        "hardware",
        "stepper motor run at speed (no positioning)",
        params=(*_on_board("STEPPER$BOARD", 4), *_MOTION_PARAMS, DESCRIPTION),
        states=_MOTOR_STATES,
        operators=(_RUN, _STOP),
    ),
    ObjType(
        "STP$MOTOR$AXIS",
        "hardware",
        "positioning stepper axis with travel limits and homing",
        params=(
            *_on_board("STEPPER$BOARD", 4),
            ParamSpec("LOWER$TRAVEL$LIMIT", "int", default=-INT_LIMIT),
            ParamSpec("UPPER$TRAVEL$LIMIT", "int", default=INT_LIMIT),
            *_MOTION_PARAMS,
            ParamSpec("HOME$SPEED", "int", 1, 3000, default=100),
            DESCRIPTION,
        ),
        states=(
            *_MOTOR_STATES,
            StateSpec("POSITION", "int", "r", default=0),
            StateSpec("HOMED", "digital", "r", default=False),
        ),
        operators=(
            _MOVE,
            _RUN,
            _STOP,
            OperatorSpec(
                "HOME$SEARCH",
                (),
                "move down at HOME$SPEED until the home input is ON, "
                "then POSITION = 0 and HOMED = ON",
            ),
        ),
    ),
    ObjType(
        "STP$MOTOR$AXIS$HOME$INPUT",
        "hardware",
        "home switch of a stepper axis",
        params=(
            ParamSpec(
                "STEPPERMOTOR$BOARD$NAME",
                "name",
                types=("STEPPER$BOARD",),
                role="parent",
                mandatory=True,
            ),
            ParamSpec("CHANNEL", "int", 1, 4, role="channel", mandatory=True),
            ParamSpec(
                "STPMOTOR$NAME", "name", types=("STP$MOTOR$AXIS",), role="ref", mandatory=True
            ),
            ParamSpec("SWITCH$POSITION", "int", default=0),
            DESCRIPTION,
        ),
        states=(StateSpec("STATUS", "digital", "rf", activator=True, default=False, machine=True),),
    ),
    ObjType(
        "DC$MOTOR$AXIS",
        "hardware",
        "DC motor axis (speed and position) [T type, activators]",
        params=(
            ParamSpec("AXIS$NUMBER", "int", 1, 8, mandatory=True),
            *_MOTION_PARAMS,
            DESCRIPTION,
        ),
        states=(
            *_MOTOR_STATES,
            StateSpec("POSITION", "int", "r", default=0),
            StateSpec("CONTROL$STATUS", "set", "rw", ("LOCAL", "REMOTE"), default="REMOTE"),
        ),
        operators=(_RUN, _STOP, _MOVE),
    ),
    ObjType(
        "ABSOLUTE$ENCODER",
        "hardware",
        "absolute encoder, optionally mounted on an axis",
        params=(
            ParamSpec("ENCODER$NUMBER", "int", 1, 8, mandatory=True),
            ParamSpec("AXIS$NAME", "name", types=("DC$MOTOR$AXIS", "STP$MOTOR$AXIS"), role="ref"),
            DESCRIPTION,
        ),
        states=(
            _diagn(),
            StateSpec("OPERATING$CONDITION", "set", "r", MOTION, activator=True, default="STOPPED"),
            StateSpec(
                "CFG$STATUS",
                "set",
                "r",
                ("CONFIGURED", "NOT$CONFIGURED"),
                activator=True,
                default="CONFIGURED",
            ),
            StateSpec(
                "CFG$UPDATE$REQUEST", "digital", "rf", activator=True, default=False, machine=True
            ),
            StateSpec("POSITION", "int", "rf", default=0),
        ),
        operators=(
            OperatorSpec("CONFIGURE", (), "CFG$STATUS = CONFIGURED, CFG$UPDATE$REQUEST = OFF"),
            OperatorSpec("PRESET", (ArgSpec("position", "int"),), "POSITION = position now"),
        ),
    ),
    ObjType(
        "DIGITAL$INPUT",
        "hardware",
        "digital input channel(s) of an I/O board [T]",
        params=(*_on_board("IO$BOARD", 16), ARRAY_SIZE, DESCRIPTION),
        states=(StateSpec("STATUS", "digital", "rf", activator=True, default=False, machine=True),),
        array=True,
    ),
    ObjType(
        "DIGITAL$OUTPUT",
        "hardware",
        "digital output channel(s) of an I/O board",
        params=(*_on_board("IO$BOARD", 16), ARRAY_SIZE, DESCRIPTION),
        states=(StateSpec("STATUS", "digital", "rwf", default=False),),
        array=True,
    ),
    ObjType(
        "PWM$OUTPUT",
        "hardware",
        "PWM output, VALUE per mille 0..1000 [T]",
        params=(*_on_board("IO$BOARD", 4), ARRAY_SIZE, DESCRIPTION),
        states=(StateSpec("VALUE", "int", "rwf", lo=0, hi=1000, default=0),),
        array=True,
    ),
    ObjType(
        "SYNOPTIC",
        "software",
        "display synoptic: logical parent of graphic objects [T]",
        params=(ParamSpec("PAGE", "int", 1, 99, mandatory=True), DESCRIPTION),
        states=(
            StateSpec("DISPLAYED", "digital", "rw", default=False),
            StateSpec(
                "SELECTION", "int", "rf", lo=0, hi=99, activator=True, default=0, machine=True
            ),
            StateSpec("MESSAGE", "int", "w", lo=0, hi=999, default=0),
        ),
    ),
    *(
        ObjType(
            kind,
            "software",
            f"graphic {what} on a SYNOPTIC (logical child, no channel)",
            params=(
                ParamSpec(
                    "SYNOPTIC$NAME", "name", types=("SYNOPTIC",), role="parent", mandatory=True
                ),
                *(ParamSpec(p, "int", 0, 1023, mandatory=True) for p in coords),
                DESCRIPTION,
            ),
            states=(
                StateSpec("VISIBLE", "digital", "rw", default=True),
                StateSpec("BLINKING", "digital", "rw", default=False),
            ),
        )
        for kind, what, coords in (
            ("GRAPHIC$CIRCLE", "circle", ("X$POS", "Y$POS", "RADIUS")),
            ("GRAPHIC$LINE", "line", ("X$POS", "Y$POS", "X$END", "Y$END")),
            ("GRAPHIC$TEXT", "text", ("X$POS", "Y$POS")),
        )
    ),
    ObjType(
        "DIGITAL$FLAG",
        "user",
        "auxiliary flag whose STATUS is also its activator [T]",
        params=(ParamSpec("INITIAL$VALUE", "digital", default=False), ARRAY_SIZE),
        states=(
            StateSpec(
                "STATUS",
                "digital",
                "rwf",
                activator=True,
                default=False,
                init_param="INITIAL$VALUE",
            ),
        ),
        array=True,
    ),
    ObjType(
        "DIGITAL$VARIABLE",
        "user",
        "program variable holding ON/OFF [T]",
        params=(ParamSpec("INITIAL$VALUE", "digital", default=False), ARRAY_SIZE),
        states=(StateSpec("VALUE", "digital", "rwf", default=False, init_param="INITIAL$VALUE"),),
        array=True,
    ),
    ObjType(
        "INTEGER$VARIABLE",
        "user",
        "program variable holding an integer [T]",
        params=(ParamSpec("INITIAL$VALUE", "int", default=0), ARRAY_SIZE),
        states=(StateSpec("VALUE", "int", "rwf", default=0, init_param="INITIAL$VALUE"),),
        array=True,
    ),
    ObjType(
        "INTEGER$CONSTANT",
        "user",
        "integer fixed by its declaration [T]",
        params=(ParamSpec("VALUE", "int", mandatory=True),),
        states=(StateSpec("VALUE", "int", "r", init_param="VALUE"),),
    ),
)

TYPE_BY_NAME: dict[str, ObjType] = {t.name: t for t in TYPES}

GLOBAL_ACTIVATORS: dict[str, tuple[str, ...]] = {
    "ANY$DIAGN$STATUS": ("DIAGN$STATUS",),  # [T]
    "ANY$OPERATING$CONDITION": ("OPERATING$CONDITION",),  # [P] the lost second one
}

DIGITAL_CONSTANTS = ("ON", "OFF")


def _catalog_words() -> set[str]:
    words: set[str] = set(TYPE_BY_NAME) | set(GLOBAL_ACTIVATORS) | set(DIGITAL_CONSTANTS)
    for t in TYPES:
        for p in t.params:
            words.add(p.keyword)
            words.update(p.values)
        for s in t.states:
            words.add(s.keyword)
            words.update(s.values)
        words.update(o.keyword for o in t.operators)
    return words


CATALOG_WORDS: frozenset[str] = frozenset(_catalog_words())
"""Every reserved word the catalogue introduces."""

SET_CONSTANTS: frozenset[str] = frozenset(
    v for t in TYPES for s in t.states if s.kind == "set" for v in s.values
)
CONFIG_WORDS: frozenset[str] = frozenset(
    v for t in TYPES for p in t.params if p.kind == "config" for v in p.values
)
STATE_WORDS: frozenset[str] = frozenset(s.keyword for t in TYPES for s in t.states)
OPERATOR_WORDS: frozenset[str] = frozenset(o.keyword for t in TYPES for o in t.operators)
PARAM_WORDS: frozenset[str] = frozenset(p.keyword for t in TYPES for p in t.params)
