"""Chapter 17.2, slave objects: ReadSDO ... ReleasePDO, on the bus's object dictionaries.

Slaves are addressed by slave id (`MotionKernel.slaves`: the axes' drives are slaves
0..N-1, I/O modules follow). Every function returns -1 on failure, as the manual says;
why it failed is stored as the system's last error (GetSystemLastErr): a bad slave id
eERR_HMPL_ARG_OUT_OF_RANGE (0x138F), a bus not in Pre-Operational or above (SDO) or
not in Operational (PDO), or a slave that left the bus (it is in Init),
eERR_HMPL_NOT_IN_OP_MODE (0x14B4), an access the slave
refuses its CiA 301 SDO abort code (0x06020000 no such object, 0x06090011 no such
subindex, 0x06070010 length mismatch, 0x06010002 read-only, 0x06040041 not mapped,
0x06090030 value refused).

Values: ReadSDO and ReadPDO return the object's value as an int64 (signed or unsigned
as the object's type; a string's first 8 bytes, little-endian). WriteSDO writes the
`obj_length` low bytes of its int64 value, WritePDO and ForceWritePDO the object's size
of it, as C copies a value of a wider type (a -1 written to a u16 object is 0xFFFF).
The *Ex functions move raw little-endian bytes: ReadSDOEx returns `(status, bytes)`,
WriteSDOEx takes the bytes.
"""

from __future__ import annotations

import struct

from motionvm.drives.dictionary import (
    SIZES,
    STRING_MAX,
    ObjectDictionary,
    SdoAbort,
    decode,
    wrap,
)
from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.kernel import ECAT_OP, ECAT_PREOP

FAILED = -1


class ObjectCommands(CommandBase):
    """Chapter 17.2: ReadSDO ... ReleasePDO."""

    def _slave(self, slv_id: int, state: int) -> ObjectDictionary | None:
        motion = self.motion
        d = motion.slaves.get(slv_id)
        if d is None:
            motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
            return None
        if motion.ecat_state < state or slv_id in motion.lost_slaves:  # a lost one is in Init
            motion.system_last_error = st.SYS_HMPL_NOT_IN_OP_MODE
            return None
        return d

    def _abort(self, exc: SdoAbort) -> int:
        self.motion.system_last_error = exc.code
        return FAILED

    # ---- SDO --------------------------------------------------------------------------

    def ReadSDOEx(
        self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int
    ) -> tuple[int, bytes]:
        """(0, the object's `obj_length` bytes), or (-1, b"")."""
        d = self._slave(slv_id, ECAT_PREOP)
        if d is None:
            return FAILED, b""
        try:
            return 0, d.sdo_read(obj_index, obj_subindex, obj_length)
        except SdoAbort as exc:
            return self._abort(exc), b""

    def ReadSDO(self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int) -> int:
        status, data = self.ReadSDOEx(slv_id, obj_index, obj_subindex, obj_length)
        if status:
            return FAILED
        obj = self.motion.slaves.get(slv_id).entry(obj_index, obj_subindex)
        if obj.dtype == "str":
            return decode("i64", data)
        return decode(obj.dtype, data)

    def WriteSDOEx(
        self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int, obj_value: bytes
    ) -> int:
        d = self._slave(slv_id, ECAT_PREOP)
        if d is None:
            return FAILED
        try:
            d.sdo_write(obj_index, obj_subindex, obj_length, obj_value)
        except SdoAbort as exc:
            return self._abort(exc)
        return 0

    def WriteSDO(
        self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int, obj_value: int
    ) -> int:
        # zeros past the int64's 8 bytes, no more than any object holds: the dictionary
        # refuses a length that is not its object's (obj_length 2**31 allocated 2 GB)
        data = struct.pack("<q", wrap("i64", obj_value)) + bytes(
            min(max(0, obj_length - 8), STRING_MAX)
        )
        return self.WriteSDOEx(slv_id, obj_index, obj_subindex, obj_length, data)

    # ---- PDO --------------------------------------------------------------------------

    def ReadPDO(self, slv_id: int, obj_index: int, obj_subindex: int) -> int:
        d = self._slave(slv_id, ECAT_OP)
        if d is None:
            return FAILED
        try:
            return d.pdo_read(obj_index, obj_subindex)
        except SdoAbort as exc:
            return self._abort(exc)

    def ReadPDOEx(self, slv_id: int, obj_index: int, obj_subindex: int) -> tuple[int, bytes]:
        """(0, the object's bytes, as many as its size), or (-1, b"")."""
        d = self._slave(slv_id, ECAT_OP)
        if d is None:
            return FAILED, b""
        try:
            value = d.pdo_read(obj_index, obj_subindex)
        except SdoAbort as exc:
            return self._abort(exc), b""
        dtype = d.entry(obj_index, obj_subindex).dtype
        return 0, value.to_bytes(SIZES[dtype], "little", signed=dtype[0] == "i")

    def _pdo_store(self, how: str, slv_id: int, index: int, sub: int, value: int) -> int:
        d = self._slave(slv_id, ECAT_OP)
        if d is None:
            return FAILED
        try:
            dtype = d.entry(index, sub).dtype
            if dtype != "str":
                value = wrap(dtype, value)
            getattr(d, how)(index, sub, value)
        except SdoAbort as exc:
            return self._abort(exc)
        return 0

    def WritePDO(self, slv_id: int, obj_index: int, obj_subindex: int, obj_value: int) -> int:
        """A write the controller's own cyclic write of the object may overwrite."""
        return self._pdo_store("pdo_write", slv_id, obj_index, obj_subindex, obj_value)

    def ForceWritePDO(self, slv_id: int, obj_index: int, obj_subindex: int, obj_value: int) -> int:
        """The value wins over the controller's writes until ReleasePDO."""
        return self._pdo_store("force", slv_id, obj_index, obj_subindex, obj_value)

    def ReleasePDO(self, slv_id: int, obj_index: int, obj_subindex: int) -> int:
        d = self._slave(slv_id, ECAT_OP)
        if d is None:
            return FAILED
        try:
            d.release(obj_index, obj_subindex)
        except SdoAbort as exc:
            return self._abort(exc)
        return 0
