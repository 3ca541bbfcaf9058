"""PDL, the language of HIWIN mega-fabs servo drives: front end, lowering and run side.

`compile_front` runs the preprocessor, parser and checker on one file; `program.compile_pdl`
lowers it to Python. The run side: `drive_rt.Drive` (4 tasks on the 15 kHz phase clock,
`drive_loop.py`), its profile `drive_axis.py`, and `machine_drives.PdlDrives`, the cycle
client that runs drives on the controller's clock and moves the machine's axes with them.
"""

from motionvm.lang.pdl.front import FrontResult, compile_front, front_end

__all__ = ["FrontResult", "compile_front", "front_end"]
