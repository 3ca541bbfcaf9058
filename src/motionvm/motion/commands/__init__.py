"""The controller's motion functions in manual units and error codes, for any front end.

`MotionCommands(motion_kernel)` has one method per function of the HIMC manual that
concerns the bus, the axes and what drives them, named as the manual names it, with
the manual's parameters in the manual's order and units (mm or deg, mm/s, mm/s^2, ms):

| chapter | module | functions |
|---|---|---|
| 2 system (bus) | `system.py` | IsSystemInit ... GetSlaveNum, ScanNetwork, DisableAll, StopAll, EStop |
| 5 axis | `axis.py` | Enable ... GetCmdNum, IsEnabled ... IsAcc |
| 6 gear, 7 gantry | `sync.py` | EnableGear ... IsGearSlave, EnableGantryPair ... IsGantryPair |
| 8 axis groups | `group.py`, `group_settings.py` | EnableGroup ... IsGrpErrorStop, LineAbs ... CircleRel |
| 13 touch probe | `touchprobe.py` | EnableTouchProbe ... SetTouchProbeFunc |
| 14 compensation | `compensation.py` | EnableComp ... SetCompAlgType, GetPosFbComp, IsCompActive |
| 15 filters | `filters.py` | EnableAxisVsf ... SetGrpInShape |
| 17.2 slave objects | `objects.py` | ReadSDO ... ReleasePDO |
| 17.3 controller variables | `config.py` | GetConfigVar, SetConfigVar |
| 18 errors | `system.py` | GetSystemLastErr ... GetDriveErr |
| 20 homing | `homing.py` | MoveHome, SetHomeMethod ... SetHomedStatus |

Conventions (the C functions' own, so that a front end only marshals arguments):
- A method returns what the C function returns: an `int` status (0, or the manual's
  error code as a 32-bit C int, so that an axis error 0x83XXCCCC is negative), a `float`
  for a `double` getter, an `int` 0/1 for an Is* function.
- A C out-parameter becomes part of the result: the method returns a tuple
  `(status, value)`, the value being 0.0 when the status is not 0
  (`GetTouchProbePos(axis_id) -> (0, 12.5)`).
- A C array argument is a Python sequence (`MovePVT(axis_id, time, pos, vel)`, its
  length the point count).
- A failing axis command stores its code as that axis's last error (GetAxisLastErr); a
  bad axis or group id stores eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) as the system's last
  error (GetSystemLastErr) and returns it, or 0 (getters and Is* functions), or -1
  (GetGantryPairID).
- Nothing blocks: MoveHome starts the homing and returns at once. A front end whose
  MoveHome waits (HMPL) polls `home_result(axis_id)`: None while the homing runs, then
  its status. Stopping tasks (EStop) is the front end's part, as are strings, task
  functions and the HMI scope.
Helpers that are not functions of the manual are lower-case (`home_result`).

The state these functions change lives in the motion kernel (axes, gears, gantry pairs,
homing, touch probes, bus, last errors), so any number of front ends may each hold a
`MotionCommands` of the same kernel.
"""

from __future__ import annotations

from motionvm.motion.commands.axis import AxisCommands
from motionvm.motion.commands.compensation import CompensationCommands
from motionvm.motion.commands.config import ConfigCommands
from motionvm.motion.commands.filters import FilterCommands
from motionvm.motion.commands.group import GroupCommands
from motionvm.motion.commands.group_settings import GroupSettingsCommands
from motionvm.motion.commands.homing import HomingCommands
from motionvm.motion.commands.objects import ObjectCommands
from motionvm.motion.commands.sync import GantryCommands, GearCommands
from motionvm.motion.commands.system import BusCommands, ErrorCommands
from motionvm.motion.commands.touchprobe import TouchProbeCommands

__all__ = ["MotionCommands"]


class MotionCommands(
    BusCommands,
    AxisCommands,
    GearCommands,
    GantryCommands,
    TouchProbeCommands,
    ErrorCommands,
    HomingCommands,
    CompensationCommands,
    FilterCommands,
    ObjectCommands,
    ConfigCommands,
    GroupCommands,
    GroupSettingsCommands,
):
    """Every motion function of the manual, on one motion kernel (see the module docstring)."""
