"""Every input, output, analog value and slave state is a scope channel."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.runtime.scope import ScopeError
from motionvm.sim.scope_sources import registry_for

MACHINE = """axes = 1
[[slave]]
kind = "digital"
inputs = 2
outputs = 1
[[slave]]
kind = "analog"
ai = 1
ao = 1
[[slave]]
kind = "digital"
slots = [{inputs = 1}, {outputs = 1}]
"""


def test_slave_channels_are_listed_and_recorded(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text(MACHINE)
    sim = Simulation.from_source(
        """void main() {
            SetSlvGPO(1, 1, 1); SetSlvAOType(2, 1, HMPL_DAC_P0_P10); SetSlvAO(2, 1, 5.0);
            SetSlvGPO(3 | HMPL_SLOT_2, 1, 1); Sleep(2);
        }""",
        machine=str(m),
    )
    names = set(registry_for(sim.controller, sim.runtime).names())
    assert {
        "slv0.state", "slv1.state", "slv1.di1", "slv1.di2", "slv1.do1", "slv2.ai1",
        "slv2.ai1.value", "slv2.ao1", "slv2.ao1.value", "slv3.s1.di1", "slv3.s2.do1",
        "gpi8", "gpo8", "himc_gpi_bits",
    } <= names  # fmt: skip
    assert "slv1.do2" not in names and "gpi9" not in names
    rec = sim.scope(["slv1.do1", "slv2.ao1", "slv2.ao1.value", "slv3.s2.do1", "slv1.state"])
    sim.run()
    data = rec.as_dict()
    assert data["slv1.do1"][-1] == 1 and data["slv2.ao1"][-1] == 32768
    assert data["slv2.ao1.value"][-1] == 5.0 and data["slv3.s2.do1"][-1] == 1
    assert data["slv1.state"][-1] == 8
    assert rec.units["slv1.do1"] == "bool" and rec.units["slv2.ao1"] == "raw"


@pytest.mark.parametrize("name", ["slv1.do2", "slv9.di1", "slv0.di1", "slv2.ai1.value.x"])
def test_a_missing_slave_channel_is_named(tmp_path, name):
    m = tmp_path / "m.toml"
    m.write_text(MACHINE)
    sim = Simulation.from_source("void main() { }", machine=str(m))
    with pytest.raises(ScopeError):
        registry_for(sim.controller, sim.runtime).resolve(name)
