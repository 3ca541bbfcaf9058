"""HMPL slave object functions of manual 17.2: ReadSDO ... ReleasePDO.

The semantics -- slaves by id, the object dictionaries, SDO abort codes stored as the
system's last error, PDO mapping and forcing -- are the motion commands'
(`motionvm.motion.commands.objects`, `motionvm.drives.dictionary`). The *Ex functions
move the object's bytes, little-endian, through their `uint8_t *obj_value`: ReadSDOEx
writes `obj_length` bytes there, ReadPDOEx as many as the object's size, WriteSDOEx
reads `obj_length` bytes from it. A pointer that cannot hold them stops the task.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command


class ObjectLib(Library):
    """Chapter 17.2: ReadSDO ... ReleasePDO."""

    ReadSDO = command()
    WriteSDO = command()
    ReadPDO = command()
    WritePDO = command()
    ForceWritePDO = command()
    ReleasePDO = command()

    @builtin()
    def ReadSDOEx(
        self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int, obj_value: int
    ) -> int:
        status, data = self.rt.commands.ReadSDOEx(slv_id, obj_index, obj_subindex, obj_length)
        if status == 0:
            self.mem.write_bytes(obj_value, data, "ReadSDOEx obj_value")
        return status

    @builtin()
    def WriteSDOEx(
        self, slv_id: int, obj_index: int, obj_subindex: int, obj_length: int, obj_value: int
    ) -> int:
        n = max(0, obj_length)
        self.mem.check(obj_value, n, "WriteSDOEx obj_value")
        data = self.mem.read_bytes(obj_value, n)
        return self.rt.commands.WriteSDOEx(slv_id, obj_index, obj_subindex, obj_length, data)

    @builtin()
    def ReadPDOEx(self, slv_id: int, obj_index: int, obj_subindex: int, obj_value: int) -> int:
        status, data = self.rt.commands.ReadPDOEx(slv_id, obj_index, obj_subindex)
        if status == 0:
            self.mem.write_bytes(obj_value, data, "ReadPDOEx obj_value")
        return status
