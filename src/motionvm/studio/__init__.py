"""`motionvm studio`: a local page to edit, run, watch, debug and scrub a run.

A face of the debug engine (`motionvm.debug`), like the DAP server: `app.py` serves the
page and one WebSocket on 127.0.0.1 with a token, `protocol.py` maps the protocol's
methods (docs/studio.md) to the run, `run.py` paces the engine in simulated time and
streams what the page shows, `history.py` records the run for the time slider, `views.py`
says which channels each panel shows, `workspace.py` holds the files and their
diagnostics. The page itself is built from `frontend/` into `static/` (committed).
"""

from motionvm.studio.protocol import Studio

__all__ = ["Studio"]
