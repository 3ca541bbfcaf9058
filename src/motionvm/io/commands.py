"""The controller's I/O functions (manual chapters 9 and 10) in manual numbers and error
codes, for any front end: `IOCommands(io_system)`.

Conventions, as for the motion commands (motion/commands/__init__.py):
- Numbers are the manual's: controller inputs and outputs from 1 (`GetGPI(4)` is the
  4th input), slave channels from 1 (`GetSlvGPI(1, 3)` the 3rd input of slave 1),
  `slv_slot_id` = slave id | HMPL_SLOT_n (io/slaves.py).
- Chapter 9 setters return 0, or -1 for a bad input, output, slave, slot or channel, or
  a slave that is not in Operation (the manual's "-1 on failure"); getters of a bad one
  return 0 (FALSE). Either way a bad id stores eERR_HMPL_ARG_OUT_OF_RANGE as the
  system's last error.
- Chapter 10 setters return 0 or a non-zero code: eERR_HMPL_ARG_OUT_OF_RANGE (0x138F)
  for a bad slave, slot, channel, type or variable, -1 when the channel's conversion
  type is HMPL_DAC_NONE (SetSlvAO: "only the Raw functions") or the slave is lost;
  GetSlvAIType/GetSlvAOType of a bad channel return -1, the other getters 0.
- Digital slave functions work on I/O slaves of kind "digital" and on drives, which have
  the general-purpose channels `[io] drive_inputs/drive_outputs` gives them (none by
  default); analog ones on kind "analog".
Helpers that are not functions of the manual are lower-case.
"""

from __future__ import annotations

import math

from motionvm.io.analog import (
    AXIS_SHIFT,
    AXIS_VARIABLES,
    DAC_NONE,
    DAC_SIGNED,
    raw_of_word,
    valid_type,
    value_of_word,
    word_of_raw,
    word_of_value,
)
from motionvm.io.gpio import bits_of
from motionvm.io.slaves import ANALOG, DIGITAL, DRIVE, Module
from motionvm.motion.axis_status import SYS_HMPL_ARG_OUT_OF_RANGE

FAIL = -1


class IOCommands:
    """Chapters 9 and 10 on one I/O system (see the module docstring)."""

    def __init__(self, io) -> None:
        self.io = io
        self.gpio = io.gpio
        self.motion = io.motion

    def _bad(self, result: int | float = FAIL):
        self.motion.system_last_error = SYS_HMPL_ARG_OUT_OF_RANGE
        return result

    # ---- 9.2 controller outputs and inversion ----------------------------------------

    def SetGPO(self, gpo_idx: int, on_off: int) -> int:
        if not self.gpio.has_output(gpo_idx):
            return self._bad()
        self.gpio.set_output(gpo_idx, on_off)
        return 0

    def ToggleGPO(self, gpo_idx: int) -> int:
        if not self.gpio.has_output(gpo_idx):
            return self._bad()
        self.gpio.set_output(gpo_idx, not self.gpio.output(gpo_idx))
        return 0

    def SetAllGPO(self, all_gpo_state: int) -> int:
        self.gpio.set_output_bits(all_gpo_state)
        return 0

    def SetGPIInvert(self, gpi_idx: int, invert: int) -> int:
        if not self.gpio.has_input(gpi_idx):
            return self._bad()
        self.gpio.set_input_invert(gpi_idx, invert)
        return 0

    def SetGPOInvert(self, gpo_idx: int, invert: int) -> int:
        if not self.gpio.has_output(gpo_idx):
            return self._bad()
        self.gpio.set_output_invert(gpo_idx, invert)
        return 0

    def BindEMO(self, gpi_idx: int) -> int:
        """Bind the E-stop to input `gpi_idx` (0: to none)."""
        if gpi_idx != 0 and not self.gpio.has_input(gpi_idx):
            return self._bad()
        self.gpio.estop_input = gpi_idx
        return 0

    # ---- 9.4 controller states ---------------------------------------------------------

    def GetGPI(self, gpi_idx: int) -> int:
        if not self.gpio.has_input(gpi_idx):
            return self._bad(0)
        return self.gpio.inputs[gpi_idx - 1]

    def GetGPO(self, gpo_idx: int) -> int:
        if not self.gpio.has_output(gpo_idx):
            return self._bad(0)
        return self.gpio.outputs[gpo_idx - 1]

    def GetAllGPI(self) -> int:
        return self.gpio.input_bits

    def GetAllGPO(self) -> int:
        return self.gpio.output_bits

    def GetAllGPIInvertSt(self) -> int:
        return self.gpio.input_invert_bits

    def GetAllGPOInvertSt(self) -> int:
        return self.gpio.output_invert_bits

    # ---- 9.3, 9.5 slave digital I/O --------------------------------------------------

    def _module(self, slv_slot_id: int, kind: str) -> tuple[object, Module] | None:
        """The slave and module addressed, if it is of `kind` (digital functions also
        take a drive with general-purpose channels: `[io] drive_inputs/drive_outputs`)."""
        found = self.io.bus.address(slv_slot_id)
        if found is None:
            return None
        if found[0].kind != kind and not (kind == DIGITAL and found[0].kind == DRIVE):
            return None
        return found

    def _digital(self, slv_slot_id: int, outputs: bool, idx: int | None):
        """(slave, channel list, index) or None (a bad address: last error set)."""
        found = self._module(slv_slot_id, DIGITAL)
        if found is None:
            return None
        slave, module = found
        values = module.outputs if outputs else module.inputs
        if idx is not None and not 1 <= idx <= len(values):
            return None
        return slave, values, (idx - 1 if idx is not None else -1)

    def _write_digital(self, slv_slot_id: int, gpo_idx: int | None, write) -> int:
        """Apply `write(values, index)` to the outputs addressed: -1 for a bad address
        (last error set) or a slave that is not online, else 0."""
        found = self._digital(slv_slot_id, True, gpo_idx)
        if found is None:
            return self._bad()
        slave, values, i = found
        if not slave.online:
            return FAIL
        write(values, i)
        return 0

    def SetSlvGPO(self, slv_slot_id: int, gpo_idx: int, on_off: int) -> int:
        def write(values, i):
            values[i] = 1 if on_off else 0

        return self._write_digital(slv_slot_id, gpo_idx, write)

    def ToggleSlvGPO(self, slv_slot_id: int, gpo_idx: int) -> int:
        def write(values, i):
            values[i] ^= 1

        return self._write_digital(slv_slot_id, gpo_idx, write)

    def SetSlvAllGPO(self, slv_slot_id: int, all_gpo_state: int) -> int:
        def write(values, _):
            for i in range(len(values)):
                values[i] = (all_gpo_state >> i) & 1

        return self._write_digital(slv_slot_id, None, write)

    def GetSlvGPI(self, slv_slot_id: int, gpi_idx: int) -> int:
        found = self._digital(slv_slot_id, False, gpi_idx)
        if found is None:
            return self._bad(0)
        return found[1][found[2]]

    def GetSlvGPO(self, slv_slot_id: int, gpo_idx: int) -> int:
        found = self._digital(slv_slot_id, True, gpo_idx)
        if found is None:
            return self._bad(0)
        return found[1][found[2]]

    def GetSlvAllGPI(self, slv_slot_id: int) -> int:
        found = self._digital(slv_slot_id, False, None)
        return self._bad(0) if found is None else bits_of(found[1])

    def GetSlvAllGPO(self, slv_slot_id: int) -> int:
        found = self._digital(slv_slot_id, True, None)
        return self._bad(0) if found is None else bits_of(found[1])

    # ---- chapter 10 analog I/O -------------------------------------------------------

    def _analog(self, slv_slot_id: int, output: bool, idx: int):
        """(slave, module, index) or None (a bad address)."""
        found = self._module(slv_slot_id, ANALOG)
        if found is None:
            return None
        slave, module = found
        n = len(module.ao if output else module.ai)
        if not 1 <= idx <= n:
            return None
        return slave, module, idx - 1

    def SetSlvAIType(self, slv_slot_id: int, ai_idx: int, range_type: int) -> int:
        found = self._analog(slv_slot_id, False, ai_idx)
        if found is None or not valid_type(range_type):
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        found[1].ai_type[found[2]] = range_type
        return 0

    def SetSlvAOType(self, slv_slot_id: int, ao_idx: int, range_type: int) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None or not valid_type(range_type):
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        found[1].ao_type[found[2]] = range_type
        return 0

    def GetSlvAIType(self, slv_slot_id: int, ai_idx: int) -> int:
        found = self._analog(slv_slot_id, False, ai_idx)
        return self._bad(FAIL) if found is None else found[1].ai_type[found[2]]

    def GetSlvAOType(self, slv_slot_id: int, ao_idx: int) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        return self._bad(FAIL) if found is None else found[1].ao_type[found[2]]

    def SetSlvAORaw(self, slv_slot_id: int, ao_idx: int, ao_raw_val: int) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None:
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        slave, module, k = found
        if not slave.online:
            return FAIL
        module.ao[k] = word_of_raw(ao_raw_val, module.bits)
        return 0

    def SetSlvAO(self, slv_slot_id: int, ao_idx: int, ao_val: float) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None:
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        slave, module, k = found
        if not slave.online or module.ao_type[k] & ~DAC_SIGNED == DAC_NONE:
            return FAIL
        module.ao[k] = word_of_value(ao_val, module.bits, module.ao_type[k])
        return 0

    def _read_analog(self, slv_slot_id: int, output: bool, idx: int, convert, bad):
        """`convert(word, bits, type)` of the channel addressed, or `bad` for a bad
        address (last error set)."""
        found = self._analog(slv_slot_id, output, idx)
        if found is None:
            return self._bad(bad)
        _, module, k = found
        if output:
            return convert(module.ao[k], module.bits, module.ao_type[k])
        return convert(module.ai[k], module.bits, module.ai_type[k])

    def GetSlvAIRaw(self, slv_slot_id: int, ai_idx: int) -> int:
        return self._read_analog(slv_slot_id, False, ai_idx, raw_of_word, 0)

    def GetSlvAORaw(self, slv_slot_id: int, ao_idx: int) -> int:
        return self._read_analog(slv_slot_id, True, ao_idx, raw_of_word, 0)

    def GetSlvAI(self, slv_slot_id: int, ai_idx: int) -> float:
        return self._read_analog(slv_slot_id, False, ai_idx, value_of_word, 0.0)

    def GetSlvAO(self, slv_slot_id: int, ao_idx: int) -> float:
        return self._read_analog(slv_slot_id, True, ao_idx, value_of_word, 0.0)

    # ---- 10.4 AO bound to a controller variable --------------------------------------

    def SetSlvAOMonitor(self, slv_slot_id: int, ao_idx: int, var_id: int) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None or self.io.read_variable(var_id) is None:
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        _, module, k = found
        module.ao_bind[k].var_id = var_id
        self.io.rebind()
        return 0

    def SetSlvAOParam(
        self, slv_slot_id: int, ao_idx: int, ao_en_bind: int, ao_scale: float, ao_offset: float
    ) -> int:
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None or not (math.isfinite(ao_scale) and math.isfinite(ao_offset)):
            return self._bad(SYS_HMPL_ARG_OUT_OF_RANGE)
        _, module, k = found
        b = module.ao_bind[k]
        b.enabled, b.scale, b.offset = bool(ao_en_bind), ao_scale, ao_offset
        self.io.rebind()
        return 0

    def GetSlvAOScale(self, slv_slot_id: int, ao_idx: int) -> float:
        found = self._analog(slv_slot_id, True, ao_idx)
        return self._bad(0.0) if found is None else found[1].ao_bind[found[2]].scale

    def GetSlvAOOffset(self, slv_slot_id: int, ao_idx: int) -> float:
        found = self._analog(slv_slot_id, True, ao_idx)
        return self._bad(0.0) if found is None else found[1].ao_bind[found[2]].offset

    def IsSlvAOBound(self, slv_slot_id: int, ao_idx: int) -> int:
        """1 while the AO follows a controller variable: a variable chosen and the
        binding switched on (SetSlvAOParam with ao_en_bind 1)."""
        found = self._analog(slv_slot_id, True, ao_idx)
        if found is None:
            return self._bad(0)
        b = found[1].ao_bind[found[2]]
        return 1 if b.enabled and b.var_id >= 0 else 0


__all__ = ["IOCommands", "AXIS_SHIFT", "AXIS_VARIABLES"]
