"""CiA 402 object dictionary of the simulated drive: indices, types, bits, states, codes.

Values follow CiA 402 / ETG.6010: positions [counts] as int32 (wrapping), velocities
[counts/s], torques in per mille of the rated torque, decelerations [counts/s^2].
"""

from __future__ import annotations

import enum
from typing import NamedTuple

from motionvm.drives.dictionary import SdoAbort  # noqa: F401 (re-exported)

# ---- indices ------------------------------------------------------------------------
DEVICE_TYPE = 0x1000
ERROR_CODE = 0x603F
CONTROLWORD = 0x6040
STATUSWORD = 0x6041
QUICK_STOP_OPTION = 0x605A
MODES_OF_OPERATION = 0x6060
MODES_DISPLAY = 0x6061
POSITION_DEMAND = 0x6062
POSITION_ACTUAL = 0x6064
FOLLOWING_ERROR_WINDOW = 0x6065
VELOCITY_ACTUAL = 0x606C
TARGET_TORQUE = 0x6071
MAX_TORQUE = 0x6072
RATED_TORQUE = 0x6076
TORQUE_ACTUAL = 0x6077
TARGET_POSITION = 0x607A
QUICK_STOP_DECEL = 0x6085
TOUCH_PROBE_FUNCTION = 0x60B8
TOUCH_PROBE_STATUS = 0x60B9
TOUCH_PROBE_1_POS = 0x60BA
TOUCH_PROBE_1_NEG = 0x60BB
TOUCH_PROBE_2_POS = 0x60BC
TOUCH_PROBE_2_NEG = 0x60BD
FOLLOWING_ERROR_ACTUAL = 0x60F4
DIGITAL_INPUTS = 0x60FD
TARGET_VELOCITY = 0x60FF
SUPPORTED_MODES = 0x6502

# ---- modes of operation (0x6060) --------------------------------------------------
MODE_NONE, MODE_HOMING, MODE_CSP, MODE_CSV, MODE_CST = 0, 6, 8, 9, 10
MODES = (MODE_NONE, MODE_HOMING, MODE_CSP, MODE_CSV, MODE_CST)
SUPPORTED_MODES_VALUE = (1 << 5) | (1 << 7) | (1 << 8) | (1 << 9)  # hm, csp, csv, cst

# ---- digital inputs (0x60FD) --------------------------------------------------------
DI_NEGATIVE_LIMIT = 1 << 0
DI_POSITIVE_LIMIT = 1 << 1
DI_HOME_SWITCH = 1 << 2
DI_INDEX_PULSE = 1 << 16
"""Manufacturer-specific: the encoder index (zero) pulse was crossed in the last cycle."""
DI_PROBE_INPUT = 1 << 17
"""Manufacturer-specific: the external touch probe 2 input."""

# ---- statusword bits (0x6041) -------------------------------------------------------
SW_READY_TO_SWITCH_ON = 1 << 0
SW_SWITCHED_ON = 1 << 1
SW_OPERATION_ENABLED = 1 << 2
SW_FAULT = 1 << 3
SW_VOLTAGE_ENABLED = 1 << 4
SW_QUICK_STOP = 1 << 5  # 0 = quick stop active
SW_SWITCH_ON_DISABLED = 1 << 6
SW_WARNING = 1 << 7
SW_REMOTE = 1 << 9
SW_TARGET_REACHED = 1 << 10
SW_INTERNAL_LIMIT = 1 << 11
SW_FOLLOWS_TARGET = 1 << 12  # CSP/CSV/CST: the drive follows the cyclic target
SW_FOLLOWING_ERROR = 1 << 13  # CSP: following error window exceeded

# ---- controlword (0x6040) -----------------------------------------------------------
CW_FAULT_RESET = 1 << 7
CW_HALT = 1 << 8
CMD_SHUTDOWN = 0x06
CMD_SWITCH_ON = 0x07
CMD_ENABLE_OPERATION = 0x0F
CMD_DISABLE_VOLTAGE = 0x00
CMD_QUICK_STOP = 0x02


class Command(enum.Enum):
    """Device control commands decoded from controlword bits 0-3 and 7."""

    SHUTDOWN = "shutdown"
    SWITCH_ON = "switch on"  # also "disable operation"
    ENABLE_OPERATION = "enable operation"  # "switch on + enable operation"
    DISABLE_VOLTAGE = "disable voltage"
    QUICK_STOP = "quick stop"


def decode_command(controlword: int) -> Command | None:
    """The state-machine command in `controlword`, or None (e.g. bit 7 fault reset set)."""
    if controlword & 0x82 == 0x00:
        return Command.DISABLE_VOLTAGE
    if controlword & 0x86 == 0x02:
        return Command.QUICK_STOP
    if controlword & 0x87 == 0x06:
        return Command.SHUTDOWN
    if controlword & 0x8F == 0x07:
        return Command.SWITCH_ON
    if controlword & 0x8F == 0x0F:
        return Command.ENABLE_OPERATION
    return None


class State(enum.Enum):
    """Power drive states of CiA 402, valued by their statusword bits (mask 0x6F)."""

    NOT_READY_TO_SWITCH_ON = 0x00
    SWITCH_ON_DISABLED = 0x40
    READY_TO_SWITCH_ON = 0x21
    SWITCHED_ON = 0x23
    OPERATION_ENABLED = 0x27
    QUICK_STOP_ACTIVE = 0x07
    FAULT_REACTION_ACTIVE = 0x0F
    FAULT = 0x08


def state_of(statusword: int) -> State | None:
    """Decode the power state from a statusword, as a master does."""
    for state in State:
        mask = 0x4F if state in _MASK_4F else 0x6F
        if statusword & mask == state.value & mask:
            return state
    return None


_MASK_4F = {
    State.NOT_READY_TO_SWITCH_ON,
    State.SWITCH_ON_DISABLED,
    State.FAULT_REACTION_ACTIVE,
    State.FAULT,
}

# ---- error codes (0x603F) -----------------------------------------------------------
ERR_NONE = 0x0000
ERR_GENERIC = 0x1000
ERR_ENCODER = 0x7305  # incremental sensor 1 fault
ERR_FOLLOWING = 0x8611  # following error too big

# ---- SDO access ---------------------------------------------------------------------


class Entry(NamedTuple):
    """One object: the drive attribute holding it, its data type and access."""

    attr: str
    dtype: str  # "i8", "u8", "i16", "u16", "i32", "u32"
    writable: bool
    name: str


RANGES = {
    "i8": (-(1 << 7), (1 << 7) - 1),
    "u8": (0, (1 << 8) - 1),
    "i16": (-(1 << 15), (1 << 15) - 1),
    "u16": (0, (1 << 16) - 1),
    "i32": (-(1 << 31), (1 << 31) - 1),
    "u32": (0, (1 << 32) - 1),
}

DICTIONARY: dict[int, Entry] = {
    DEVICE_TYPE: Entry("device_type", "u32", False, "Device type"),
    ERROR_CODE: Entry("error_code", "u16", False, "Error code"),
    CONTROLWORD: Entry("controlword", "u16", True, "Controlword"),
    STATUSWORD: Entry("statusword", "u16", False, "Statusword"),
    QUICK_STOP_OPTION: Entry("quick_stop_option", "i16", True, "Quick stop option code"),
    MODES_OF_OPERATION: Entry("mode", "i8", True, "Modes of operation"),
    MODES_DISPLAY: Entry("mode_display", "i8", False, "Modes of operation display"),
    POSITION_DEMAND: Entry("position_demand", "i32", False, "Position demand value"),
    POSITION_ACTUAL: Entry("position_actual", "i32", False, "Position actual value"),
    FOLLOWING_ERROR_WINDOW: Entry("following_error_window", "u32", True, "Following error window"),
    VELOCITY_ACTUAL: Entry("velocity_actual", "i32", False, "Velocity actual value"),
    TARGET_TORQUE: Entry("target_torque", "i16", True, "Target torque"),
    MAX_TORQUE: Entry("max_torque", "u16", True, "Max torque"),
    RATED_TORQUE: Entry("rated_torque", "u32", False, "Motor rated torque"),
    TORQUE_ACTUAL: Entry("torque_actual", "i16", False, "Torque actual value"),
    TARGET_POSITION: Entry("target_position", "i32", True, "Target position"),
    QUICK_STOP_DECEL: Entry("quick_stop_decel", "u32", True, "Quick stop deceleration"),
    TOUCH_PROBE_FUNCTION: Entry("tp_function", "u16", True, "Touch probe function"),
    TOUCH_PROBE_STATUS: Entry("tp_status", "u16", False, "Touch probe status"),
    TOUCH_PROBE_1_POS: Entry("tp1_positive_edge", "i32", False, "Touch probe 1 positive edge"),
    TOUCH_PROBE_1_NEG: Entry("tp1_negative_edge", "i32", False, "Touch probe 1 negative edge"),
    TOUCH_PROBE_2_POS: Entry("tp2_positive_edge", "i32", False, "Touch probe 2 positive edge"),
    TOUCH_PROBE_2_NEG: Entry("tp2_negative_edge", "i32", False, "Touch probe 2 negative edge"),
    FOLLOWING_ERROR_ACTUAL: Entry("following_error", "i32", False, "Following error actual value"),
    DIGITAL_INPUTS: Entry("digital_inputs", "u32", False, "Digital inputs"),
    TARGET_VELOCITY: Entry("target_velocity", "i32", True, "Target velocity"),
    SUPPORTED_MODES: Entry("supported_modes", "u32", False, "Supported drive modes"),
}


def wrap_i32(value: int) -> int:
    """Wrap an integer to int32, as a 32-bit encoder counter does."""
    return ((value + 0x80000000) & 0xFFFFFFFF) - 0x80000000
