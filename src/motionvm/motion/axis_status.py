"""Status bits, error codes and variable names of an axis (HIMC manual 5.1.1, 18.1).

`fault_status` bits are table 5.1.1.4, `motion_status` bits table 5.1.1.5. Axis error
codes (table 18.1.2.1) are 0x83XXCCCC with XX the axis id; `axis_error(code, axis_id)`
builds the 32-bit value and returns it as a C `int` (negative: bit 31 is set), as an
HMPL function returns it. System error codes (table 18.1.1.1) carry no id.
"""

from __future__ import annotations

# ---- fault_status (table 5.1.1.4) ------------------------------------------------
FS_ERROR_STOP = 1 << 0
FS_DRIVE_FAULT = 1 << 1
FS_POSITION_ERROR = 1 << 2
FS_HW_RIGHT = 1 << 3
FS_HW_LEFT = 1 << 4
FS_SW_RIGHT = 1 << 5
FS_SW_LEFT = 1 << 6

# ---- motion_status (table 5.1.1.5) -----------------------------------------------
MS_ENABLED = 1 << 0
MS_MOVING = 1 << 1
MS_IN_POSITION = 1 << 2
MS_SYNC = 1 << 3
MS_GROUP = 1 << 4
MS_GANTRY = 1 << 5
MS_INPUT_SHAPE = 1 << 6
MS_VSF = 1 << 7
MS_GEAR = 1 << 8
MS_CAM = 1 << 9
MS_ACCELERATING = 1 << 10
MS_HOMED = 1 << 11
MS_HOMING = 1 << 12

# ---- axis error codes, low 16 bits (table 18.1.2.1) ------------------------------
CMD_UNKNOWN = 0x000A
CMD_QUEUE_FULL = 0x001E
CMD_INVALID_STATE = 0x0064
CMD_INVALID_ENABLED = 0x006E
CMD_INVALID_DISABLED = 0x0078
CMD_INVALID_MOVING = 0x0082
CMD_INVALID_STOPPING = 0x008C
CMD_INVALID_ERROR_STATE = 0x0096
CMD_INVALID_IN_SYNC = 0x00A0
CMD_INVALID_INPUTSHAPING_ENABLED = 0x00C8
CMD_INVALID_COMP_ENABLED = 0x00D2
CMD_INVALID_GROUPED = 0x00E6
CMD_INVALID_CONTROL_MODE = 0x00F0
CMD_INVALID_OP_MODE = 0x00FA
CMD_INVALID_BUFFER_MODE = 0x0104
CMD_INVALID_SETBUFFERMODE = 0x0105
CMD_INVALID_PARAMETER = 0x012C
CMD_INVALID_POS = 0x0136
CMD_INVALID_VEL = 0x0140
CMD_INVALID_ACC = 0x014A
CMD_INVALID_DEC = 0x0154
CMD_INVALID_SM_TIME = 0x0168
CMD_INVALID_KILL_DEC = 0x0172
CMD_INVALID_VEL_SCALE = 0x017C
COMP_NOT_CNFG = 0x0190
CMD_INVALID_ROLLOVER_POS = 0x01F4
DRIVE_FAULT = 0x03F2
DRIVE_ABNORMAL_DISABLE = 0x03FC
DRIVE_ENABLE_TOUT = 0x0406
DRIVE_CLEAR_ERROR_TOUT = 0x0410
DAMPINGRATIO_LIMIT = 0x0474
FREQUENCY_LIMIT = 0x047E
SWRL = 0x07DA
SWLL = 0x07E4
HWRL = 0x07EE
HWLL = 0x07F8
COMP_LIMIT = 0x0802
PERR = 0x083E
PVT_VEL_LIMIT = 0x08A2
PVT_ACC_LIMIT = 0x08AC
PVT_INVALID_TIME = 0x08B6

# ---- group error codes, low 16 bits (table 18.1.3.1) -----------------------------
CRD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE = 0x005A
CRD_INVALID_DAMPINGRATIO = 0x010E
CRD_INVALID_FREQUENCY = 0x0118

# ---- system error codes (table 18.1.1.1) -----------------------------------------
SYS_EMERGENCY_STOP = 0x00000064
SYS_NOT_VALID_TASKID = 0x00000107
SYS_TASK_IS_RUNNING = 0x00000108
SYS_FUNC_NOT_IN_TASK = 0x00000109
SYS_TASK_EMPTY = 0x0000010A
SYS_NIC_INIT_TOUT = 0x0000012C
SYS_HMPL_INVALID_ARG = 0x00001388
SYS_HMPL_INVALID_PTR = 0x00001389
SYS_HMPL_ARG_OUT_OF_RANGE = 0x0000138F
SYS_HMPL_NOT_IN_OP_MODE = 0x000014B4


def as_c_int(value: int) -> int:
    """`value` as a 32-bit two's complement C int."""
    return ((value + 0x80000000) & 0xFFFFFFFF) - 0x80000000


def axis_error(code: int, axis_id: int) -> int:
    """The axis error 0x83XXCCCC (XX = axis id) as a C int."""
    return as_c_int(0x83000000 | (axis_id & 0xFF) << 16 | code)


def group_error(code: int, group_id: int) -> int:
    """The group error 0x82XXCCCC (XX = group id) as a C int."""
    return as_c_int(0x82000000 | (group_id & 0xFF) << 16 | code)


class AxisCommandError(Exception):
    """A command the axis refuses; `code` is the low 16 bits of its axis error code."""

    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


# ---- axis variables of 5.1.1, readable with Axis.variable(name) ------------------
VARIABLES: dict[str, str] = {
    # table 5.1.1.1, motion command variables
    "sync_pos_set": "mm or deg",
    "pg_pos_cmd": "mm or deg",
    "ref_pos": "mm or deg",
    "ref_vel": "mm/s or deg/s",
    "ref_acc": "mm/s^2 or deg/s^2",
    "comp_pos_set": "mm or deg",
    "pos_comp": "mm or deg",
    "pos_offset": "mm or deg",
    "pos_out": "mm or deg",
    "vel_out": "mm/s or deg/s",
    "acc_out": "mm/s^2 or deg/s^2",
    "offset_pos_out": "mm or deg",
    "pos_fb_raw": "mm or deg",
    "offset_pos_fb": "mm or deg",
    "pos_fb": "mm or deg",
    "vel_fb": "mm/s or deg/s",
    "pos_err": "mm or deg",
    "vel_err": "mm/s or deg/s",
    "movetime": "ms",
    "settlingtime": "ms",
    # table 5.1.1.2, motion profile variables
    "max_vel": "mm/s or deg/s",
    "max_acc": "mm/s^2 or deg/s^2",
    "max_dec": "mm/s^2 or deg/s^2",
    "sm_factor": "ms",
    # table 5.1.1.3, status variables
    "fault_status": "",
    "motion_status": "",
    # table 5.1.1.6, CoE object variables
    "power_drive_st": "",
    "coe_controlword": "",
    "coe_statusword": "",
    "servo_type": "",
    "coe_op_modes_display": "",
    "coe_pos_cmd": "count",
    "coe_vel_cmd": "count/s",
    "coe_trq_cmd": "",
    "coe_pos_fb": "count",
    "coe_vel_fb": "count/s",
    "coe_trq_fb": "",
    "tp_function": "",
    "tp_status": "",
    "tp1_positive_edge": "count",
    "tp1_negative_edge": "count",
    "tp2_positive_edge": "count",
    "tp2_negative_edge": "count",
    "di_bit_HWLL": "",
    "di_bit_HWRL": "",
    "di_bit_HOME": "",
}
"""Variable name -> unit, for every axis variable of manual 5.1.1 (a scope's channels)."""
