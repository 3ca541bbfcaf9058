"""HMPL AIO functions of manual chapter 10: SetSlvAIType ... IsSlvAOBound.

Each is the I/O command of its name (`motionvm.io.commands`); the conversions of table
10.1.1 are in `motionvm.io.analog`, the AO bindings of 10.4 are updated each cycle by
the I/O system (`motionvm.io.system`).
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, io_command


class AnalogLib(Library):
    """Chapter 10: slave analog inputs and outputs."""

    SetSlvAIType = io_command()
    SetSlvAOType = io_command()
    SetSlvAORaw = io_command()
    SetSlvAO = io_command()
    GetSlvAIType = io_command()
    GetSlvAOType = io_command()
    GetSlvAIRaw = io_command()
    GetSlvAI = io_command()
    GetSlvAORaw = io_command()
    GetSlvAO = io_command()
    SetSlvAOMonitor = io_command()
    SetSlvAOParam = io_command()
    GetSlvAOScale = io_command()
    GetSlvAOOffset = io_command()
    IsSlvAOBound = io_command()
