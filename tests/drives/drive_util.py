"""What the drive tests share: a drive brought up to Operation enabled in CSP."""

from __future__ import annotations

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.objects import CONTROLWORD, MODES_OF_OPERATION, State

DT = 0.001


def enabled_csp(config: dict) -> Cia402Drive:
    """A drive of `config` in CSP, Operation enabled, its target where it stands."""
    drive = Cia402Drive.create(config)
    drive.write(MODES_OF_OPERATION, 0, 8)
    drive.target_position = drive.position_actual
    for controlword, cycles in ((0x06, 4), (0x0F, 12)):
        drive.write(CONTROLWORD, 0, controlword)
        for _ in range(cycles):
            drive.step(DT)
    assert drive.state is State.OPERATION_ENABLED
    return drive
