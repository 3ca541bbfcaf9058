"""Chapter 2 (the bus and every axis at once) and chapter 18 (last errors).

Bus: IsSystemInit/PreOp/Oper follow the simulated EtherCAT master
(`MotionKernel.ecat_state`: Operation from power-on; ScanNetwork takes it through Init,
Pre-Op and Safe-Op, one cycle each). IsSystemError is 1 after EStop. Slaves are the
axes' drives, slave i being axis i's. DisableAll and StopAll clear the axes' path
planning (StopAll brakes at each axis's kill deceleration and keeps it enabled);
DisableAll disables every axis and every axis group (2.7); EStop does too (2.9;
stopping the tasks is the front end's part).

Errors: codes are 32-bit (0x00XXXXXX system, 0x83XXCCCC axis XX, 0x82XXCCCC group XX,
tables 18.1.1-18.1.3) and come back as C ints, so an axis or group code is negative.
Every failing axis function stores its code as the axis's last error; fault reactions
(limits, position error, drive fault) store theirs too. A bad axis or group id stores
eERR_HMPL_ARG_OUT_OF_RANGE as the system's last error and returns it.
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.kernel import ECAT_INIT, ECAT_OP, ECAT_PREOP, N_GROUPS


class BusCommands(CommandBase):
    """Chapter 2.1-2.10, 2.15: IsSystemInit ... EStop."""

    def IsSystemInit(self) -> int:
        return 1 if self.motion.ecat_state == ECAT_INIT else 0

    def IsSystemPreOp(self) -> int:
        return 1 if self.motion.ecat_state == ECAT_PREOP else 0

    def IsSystemOper(self) -> int:
        return 1 if self.motion.ecat_state == ECAT_OP and not self.motion.estopped else 0

    def IsSystemError(self) -> int:
        return 1 if self.motion.estopped else 0

    def GetECATSt(self) -> int:
        """The master's state: 1 Init, 2 Pre-Operation, 4 Safe-Operation, 8 Operation."""
        return self.motion.ecat_state

    def GetSlvECATSt(self, slv_id: int) -> int:
        """Slave `slv_id`'s state; 0 (and the system's last error) if there is no such slave."""
        state = self.motion.slave_state(slv_id)
        if state == 0:
            self.motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return state

    def GetSlaveNum(self) -> int:
        """The drives and the I/O slaves on the bus."""
        return self.motion.n_slaves

    def ScanNetwork(self) -> int:
        return self.motion.scan_network()

    def DisableAll(self) -> int:
        self.motion.disable_all()
        return 0

    def StopAll(self) -> int:
        self.motion.stop_all()
        return 0

    def EStop(self) -> None:
        """Disable every axis and group; IsSystemError then answers 1."""
        self.motion.estop()


class ErrorCommands(CommandBase):
    """Chapter 18: GetSystemLastErr ... GetDriveErr."""

    def GetSystemLastErr(self) -> int:
        return st.as_c_int(self.motion.system_last_error)

    def GetAxisLastErr(self, axis_id: int) -> int:
        a = self.motion.axis(axis_id)
        return self._bad_id() if a is None else a.last_error

    def ClearAxisLastErr(self, axis_id: int) -> int:
        a = self.motion.axis(axis_id)
        if a is None:
            return self._bad_id()
        a.last_error = 0
        return 0

    def GetGrpLastErr(self, group_id: int) -> int:
        if not 0 <= group_id < N_GROUPS:
            return self._bad_id()
        return self.motion.group_last_error[group_id]

    def ClearGrpLastErr(self, group_id: int) -> int:
        if not 0 <= group_id < N_GROUPS:
            return self._bad_id()
        self.motion.group_last_error[group_id] = 0
        return 0

    def GetDriveErr(self, axis_id: int) -> int:
        """The drive's error code object 0x603F (0 if none)."""
        a = self.motion.axis(axis_id)
        return self._bad_id() if a is None else a.drive.error_code
