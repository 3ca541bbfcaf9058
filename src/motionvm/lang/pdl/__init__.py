"""PDL, the language of HIWIN mega-fabs servo drives: front end (and, later, lowering).

`compile_front` runs the preprocessor, parser and checker on one file.
"""

from motionvm.lang.pdl.front import FrontResult, compile_front, front_end

__all__ = ["FrontResult", "compile_front", "front_end"]
