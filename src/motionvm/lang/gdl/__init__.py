"""GDL (GD language): compiler front end and event-driven run-time support (RTS).

Public entry points: `compile_app` (files -> checked `App`), `load_scenario`, and
`GdlApplication` (an application as a client of the controller's cycle). A run of GDL
files, alone or with HMPL and PDL programs, is assembled by `motionvm.session`: the
command line (`motionvm run|check|dump`) and `motionvm.api.Simulation` both use it.
"""

from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.client import GdlApplication
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.scenario import load_scenario

__all__ = [
    "App",
    "GdlApplication",
    "compile_app",
    "load_scenario",
]
