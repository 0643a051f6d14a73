"""RegisteredPorts: one register on every port, the core's signature and properties."""

from amaranth.back import rtlil
from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out
from amaranth.sim import Simulator

from dptbd.config import DPConfig
from dptbd.hw.dp_core import DPCore
from dptbd.hw.flow.registered_ports import RegisteredPorts


class Adder(wiring.Component):
    """``total = a + b[0] + b[1]``, combinational."""

    a: In(8)
    b: In(8).array(2)
    total: Out(10)

    def elaborate(self, platform):
        m = Module()
        m.d.comb += self.total.eq(self.a + self.b[0] + self.b[1])
        return m


def test_inputs_and_outputs_take_one_register_each():
    core = Adder()
    dut = RegisteredPorts(core)
    assert dut.signature == core.signature
    seen = []

    async def bench(ctx):
        for cycle in range(8):
            ctx.set(dut.a, cycle)
            ctx.set(dut.b[0], 10 * cycle)
            ctx.set(dut.b[1], 100)
            seen.append(ctx.get(dut.total))
            await ctx.tick()

    sim = Simulator(dut)
    sim.add_clock(1e-6)
    sim.add_testbench(bench)
    sim.run()
    # Input registered at the end of cycle c, the sum registered at the end of c + 1.
    assert seen == [0, 0] + [11 * c + 100 for c in range(6)]


def test_core_properties_pass_through():
    core = DPCore(DPConfig(width=8, height=6), max_tree="split")
    dut = RegisteredPorts(core)
    assert (dut.latency, dut.schedule, dut.core_options) == \
        (core.latency, core.schedule, core.core_options)
    assert "core" in rtlil.convert(dut)    # elaborated: the core is its submodule
