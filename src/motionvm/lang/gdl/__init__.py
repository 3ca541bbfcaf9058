"""GDL (GD language): compiler front end and event-driven run-time support (RTS).

Public entry points: `compile_app` (files -> checked `App`), `run_app` (run an `App`
against a scenario), and `main_check`, `main_run`, `main_dump` for the command line.
"""

from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.driver import main_check, main_dump, main_run, run_app

__all__ = ["App", "compile_app", "main_check", "main_dump", "main_run", "run_app"]
