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


def test_elaborated_rows_read_a_fifos_storage_and_refuse_a_non_memory():
    from amaranth.lib.fifo import SyncFIFO
    from amaranth.sim import Simulator

    fifo = Elaborated(SyncFIFO(width=4, depth=3))
    rows = fifo.rows("storage")
    assert [r.name for r in rows] == ["storage_row0", "storage_row1", "storage_row2"]
    seen = []

    async def bench(ctx):
        f = fifo.component
        for value, write, read in ((5, 1, 0), (9, 1, 0), (12, 1, 0), (0, 0, 1), (7, 1, 0)):
            ctx.set(f.w_data, value)                     # 7 wraps to row 0, read before
            ctx.set(f.w_en, write)
            ctx.set(f.r_en, read)
            await ctx.tick()
            seen.append([ctx.get(r) for r in rows])

    sim = Simulator(fifo.fragment)
    sim.add_clock(1e-6)
    sim.add_testbench(bench)
    sim.run()
    assert seen == [[5, 0, 0], [5, 9, 0], [5, 9, 12], [5, 9, 12], [7, 9, 12]]
    sync = Elaborated(InputCredit(3))
    with pytest.raises(KeyError, match=whole("\"InputCredit's submodule 'committed' is not a "
                                             "memory\"")):
        sync.rows("committed")
