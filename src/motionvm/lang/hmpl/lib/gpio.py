"""HMPL GPIO functions of manual chapter 9: SetGPO ... GetSlvAllGPO.

Each is the I/O command of its name (`motionvm.io.commands`); the inputs, outputs and
slaves are in `motionvm.io`. Inputs and outputs are numbered from 1 as the manual
numbers them; HIMC_GPI/HIMC_GPO (chapter 19) are compiled inline and use the same
numbers (rtapi.py).
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, io_command


class GpioLib(Library):
    """Chapter 9: controller and slave digital I/O."""

    SetGPO = io_command()
    ToggleGPO = io_command()
    SetAllGPO = io_command()
    SetGPIInvert = io_command()
    SetGPOInvert = io_command()
    BindEMO = io_command()
    SetSlvGPO = io_command()
    ToggleSlvGPO = io_command()
    SetSlvAllGPO = io_command()
    GetGPI = io_command()
    GetGPO = io_command()
    GetAllGPI = io_command()
    GetAllGPO = io_command()
    GetAllGPIInvertSt = io_command()
    GetAllGPOInvertSt = io_command()
    GetSlvGPI = io_command()
    GetSlvGPO = io_command()
    GetSlvAllGPI = io_command()
    GetSlvAllGPO = io_command()
