"""A compensation table holding NaN or an infinity is refused by SetupComp
(eERR_AXIS_CMD_INVALID_PARAMETER); it used to be accepted, and the first move stopped
the axis at its compensation limit with the compensation held at +1 mm."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation

PROGRAM = """void main() {{
    int i;
    for (i = 0; i < 10; i++) system_user_table[i] = 0.001 * i;
    system_user_table[{index}] = {value};
    Print("%x", SetupComp(0, 0, 0.0, 1.0, 10, 0));
}}
"""


@pytest.mark.parametrize("value", ["0.0 / 0.0", "1.0 / 0.0", "-1.0 / 0.0"])
@pytest.mark.parametrize("index", [0, 9])
def test_a_table_value_that_is_not_a_number_is_an_invalid_parameter(index, value):
    with Simulation.from_source(PROGRAM.format(index=index, value=value)) as sim:
        sim.run()
        assert sim.messages == ["8300012c"]


def test_a_finite_table_is_still_accepted():
    with Simulation.from_source(PROGRAM.format(index=5, value="0.5")) as sim:
        sim.run()
        assert sim.messages == ["0"]
