"""Fixtures of the GDL tests: a run that may jump the clock next to one that steps."""

from __future__ import annotations

import io

import pytest

from motionvm.lang.gdl import run_app
from motionvm.lang.gdl.app import App
from motionvm.runtime.clients import PassiveClient
from motionvm.sim.controller import Controller


class Stepper(PassiveClient):
    """A client whose next event is always the current cycle: the controller steps."""

    def __init__(self, controller: Controller) -> None:
        self.controller = controller

    def next_event(self) -> int | None:
        return self.controller.cycle


def run_jumped_and_stepped(app: App, scenario: str | None, until: float | None = None) -> list:
    """[(output, exit code, final cycle)] of a run that may jump and of one that steps."""
    runs = []
    for stepped in (False, True):
        controller = Controller()
        if stepped:
            controller.add_client(Stepper(controller))
        out = io.StringIO()
        rc = run_app(app, scenario, until, out, controller=controller)
        runs.append((out.getvalue(), rc, controller.cycle))
    return runs


@pytest.fixture(scope="session")
def jumped_and_stepped():
    """`run_jumped_and_stepped`: compare its two results."""
    return run_jumped_and_stepped
