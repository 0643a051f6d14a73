"""RegisteredPorts: one register on every port, the core's signature and properties."""

import numpy as np
from amaranth.back import rtlil
from amaranth.hdl import Cat, ClockDomain, Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out
from amaranth.sim import Simulator

from dptbd.config import DPConfig
from dptbd.hw.dp_core import DPCore
from dptbd.hw.flow.registered_ports import FoldedPorts, RegisteredPorts
from helpers.axil_harness import simulate_top


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


class Toy(wiring.Component):
    """A top level with its own clock: ``y`` = ``Cat(a, b)`` registered on ``aclk``."""

    aclk: In(1)
    aresetn: In(1)
    a: In(3)
    b: In(2)
    y: Out(5)

    def elaborate(self, platform):
        m = Module()
        m.domains.sync = sync = ClockDomain("sync")
        m.d.comb += [sync.clk.eq(self.aclk), sync.rst.eq(~self.aresetn)]
        m.d.sync += self.y.eq(Cat(self.a, self.b))
        return m


def test_folded_ports_shift_the_inputs_in_and_fold_the_outputs():
    """Inputs: a shift register on ``fold_in`` (the newest bit in ``a[0]``); outputs:
    registered, then XOR-folded four bits to a register per level (5 bits: 2, then 1), so
    ``fold_out`` is the parity of ``y`` three cycles earlier."""
    dut = FoldedPorts(Toy())
    assert list(dut.signature.members) == ["aclk", "aresetn", "fold_in", "fold_out"]
    rng = np.random.default_rng(1)
    bits = [int(b) for b in rng.integers(0, 2, 40)]
    seen = []

    async def bench(ctx):
        ctx.set(dut.aresetn, 1)
        for bit in bits:
            await ctx.delay(2e-9)           # away from the rising edges (at 5, 15, … ns)
            ctx.set(dut.fold_in, bit)
            seen.append(ctx.get(dut.fold_out))
            await ctx.delay(8e-9)

    simulate_top(dut, bench)
    # model: chain (5), y (5), the level register (5), folds (2, 1), each one edge later
    chain = y = level = 0
    fold2 = fold1 = 0
    expect = []
    for bit in bits:
        expect.append(fold1)
        fold1 = bin(fold2).count("1") & 1
        fold2 = (bin(level & 0xF).count("1") & 1) | ((level >> 4 & 1) << 1)
        level = y
        y = chain
        chain = ((chain << 1) | bit) & 0x1F
    assert seen == expect and any(seen)


class SyncToy(wiring.Component):
    """A core on the sync domain (as DPCore): ``y`` = ``Cat(a, b)`` registered."""

    a: In(3)
    b: In(2)
    y: Out(5)

    def elaborate(self, platform):
        m = Module()
        m.d.sync += self.y.eq(Cat(self.a, self.b))
        return m


def test_folded_ports_of_a_sync_core_are_on_its_domain():
    """Without ``aclk`` the wrapper has ``fold_in`` / ``fold_out`` only and runs on the sync
    domain: the same chain, level and folds as above, one edge each."""
    dut = FoldedPorts(SyncToy())
    assert list(dut.signature.members) == ["fold_in", "fold_out"]
    bits = [int(b) for b in np.random.default_rng(2).integers(0, 2, 40)]
    seen = []

    async def bench(ctx):
        for bit in bits:
            ctx.set(dut.fold_in, bit)
            seen.append(ctx.get(dut.fold_out))
            await ctx.tick()

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
    chain = y = level = fold2 = fold1 = 0
    expect = []
    for bit in bits:
        expect.append(fold1)
        fold1 = bin(fold2).count("1") & 1
        fold2 = (bin(level & 0xF).count("1") & 1) | ((level >> 4 & 1) << 1)
        level = y
        y = chain
        chain = ((chain << 1) | bit) & 0x1F
    assert seen == expect and any(seen)


def test_registered_ports_of_a_top_with_its_own_clock():
    """``aclk`` / ``aresetn`` pass straight to the core; every other port takes a register
    on ``aclk``, cleared while ``aresetn`` is low: ``y`` is ``Cat(a, b)`` three edges later
    (input register, the core's, output register)."""
    dut = RegisteredPorts(Toy())
    assert dut.signature == Toy().signature
    values = [int(v) for v in np.random.default_rng(3).integers(0, 32, 30)]
    seen = []

    async def bench(ctx):
        for i, v in enumerate(values):
            await ctx.delay(2e-9)           # away from the rising edges (at 5, 15, … ns)
            ctx.set(dut.aresetn, int(i not in (10, 11)))
            ctx.set(dut.a, v & 7)
            ctx.set(dut.b, v >> 3)
            seen.append(ctx.get(dut.y))
            await ctx.delay(8e-9)

    simulate_top(dut, bench)
    # three registers, each cleared by an edge with aresetn low (cycles 10 and 11)
    regs = [0, 0, 0]
    expect = []
    for i, v in enumerate(values):
        expect.append(regs[2])
        regs = [0, 0, 0] if i in (10, 11) else [v, regs[0], regs[1]]
    assert seen == expect and any(seen)
