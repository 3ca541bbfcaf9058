"""HMPL homing functions of manual chapter 20: MoveHome, its settings, IsHomed/IsHoming.

MoveHome is blocking: the calling task waits until the homing has ended, and gets 0 or
the error it failed with (`motionvm.motion.commands.homing` has the codes); the manual's
example 20.1.1 tests IsHoming right after MoveHome returns. Other tasks see IsHoming 1
meanwhile. The other functions are the motion commands of their names.
Semantics: `motionvm.motion.homing`.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command


class HomingLib(Library):
    """Chapter 20: MoveHome, SetHomeMethod ... SetHomeTimeout, IsHomed, IsHoming, SetHomedStatus."""

    @builtin(blocking=True)
    def MoveHome(self, axis_id: int):
        commands = self.rt.commands
        code = commands.MoveHome(axis_id)
        if code:
            return code
        while (result := commands.home_result(axis_id)) is None:
            yield None
        return result

    SetHomeMethod = command()
    SetHomeSwitchVel = command()
    SetHomeZeroVel = command()
    SetHomeAcc = command()
    SetHomeOffset = command()
    SetHomeTimeout = command()
    IsHomed = command()
    IsHoming = command()
    SetHomedStatus = command()
