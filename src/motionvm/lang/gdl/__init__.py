"""GDL (GD language): compiler front end and event-driven run-time support (RTS).

Public entry points: `compile_app` (files -> checked `App`), `load_scenario`,
`GdlApplication` (an application as a client of the controller's cycle), `run_app` (run
an `App` against a scenario on a controller), and `main_check`, `main_run`, `main_dump`
for the command line.
"""

from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.client import GdlApplication
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.driver import main_check, main_dump, main_run, run_app
from motionvm.lang.gdl.scenario import load_scenario

__all__ = [
    "App",
    "GdlApplication",
    "compile_app",
    "load_scenario",
    "main_check",
    "main_dump",
    "main_run",
    "run_app",
]
