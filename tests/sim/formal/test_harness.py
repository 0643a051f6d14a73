"""The harness base: free inputs become ports, the first cycle is a reset, and
``Elaborated`` reaches inner signals (refusing names that do not exist)."""

from __future__ import annotations

import pytest
from amaranth.back import rtlil
from amaranth.hdl import Fragment

from helpers.refusals import whole

from dptbd.hw.input_credit import InputCredit
from dptbd.sim.formal.harness import Elaborated, Harness


class CreditOnly(Harness):
    def check(self, m, past):
        m.submodules.credit = credit = InputCredit(3)
        self.free_inputs(m, credit, "credit", skip=("handed_out",))


def test_free_inputs_become_ports_and_the_first_cycle_is_a_reset():
    harness = CreditOnly()
    fragment = Fragment.get(harness, None)
    assert [s.name for s in harness.ports()] == ["clk", "rst", "credit__accept"]
    il = rtlil.convert(fragment, name="top", ports=harness.ports())
    assert "wire width 1 input 2  \\credit__accept" in il
    assert 'parameter \\FLAVOR "assume"' in il


def test_elaborated_reaches_inner_signals_and_refuses_unknown_names():
    credit = Elaborated(InputCredit(3))
    assert len(credit.sub("committed").component.at_least) == 3
    with pytest.raises(KeyError, match=whole("\"InputCredit has no submodule 'nope'\"")):
        credit.sub("nope")
    with pytest.raises(KeyError, match=whole("\"InputCredit drives no signal 'nope'\"")):
        credit.signal("nope")
    assert credit.signal("ready").name == "ready"
