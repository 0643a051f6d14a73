"""The register delay line helper."""

import pytest
from amaranth.back import rtlil
from amaranth.hdl import Module, Signal
from amaranth.lib import data

from dptbd.hw.delay import delayed, delayed_in_memory
from helpers.hw_harness import simulate


def test_delays_values_and_views():
    m = Module()
    value = Signal(8)
    view = Signal(data.StructLayout({"a": 3, "b": 5}))
    late_value = delayed(m, value, 3, name="v")
    late_view = delayed(m, view, 2, name="w")
    assert isinstance(late_view, data.View)
    assert delayed(m, value, 0, name="z") is value
    seen = []

    async def bench(ctx):
        for cycle in range(10):
            ctx.set(value, cycle + 1)
            ctx.set(view.as_value(), 2 * cycle + 1)
            seen.append((ctx.get(late_value), ctx.get(late_view.as_value())))
            await ctx.tick()

    simulate(m, bench)
    assert [v for v, _ in seen] == [0, 0, 0] + list(range(1, 8))
    assert [w for _, w in seen] == [0, 0] + [2 * c + 1 for c in range(8)]


@pytest.mark.parametrize("cycles", [0, 1, 2, 3, 4, 5, 7, 8, 9])
def test_memory_delay_equals_the_register_chain(cycles):
    """Cycle for cycle the ring buffer gives what the registers give (0 before the first
    value arrives); below 3 cycles it is the register chain."""
    m = Module()
    m.d.sync += Signal(name="clocked").eq(1)    # a sync domain also for 0 cycles
    view = Signal(data.StructLayout({"a": 3, "b": 5}))
    by_registers = delayed(m, view, cycles, name="r")
    by_memory = delayed_in_memory(m, view, cycles, name="mem")
    assert isinstance(by_memory, data.View) or cycles == 0
    seen = []

    async def bench(ctx):
        for cycle in range(40):
            ctx.set(view.as_value(), (37 * cycle + 11) % 256)
            seen.append((ctx.get(by_registers.as_value()), ctx.get(by_memory.as_value())))
            await ctx.tick()

    simulate(m, bench)
    assert [r for r, _ in seen] == [mem for _, mem in seen]
    assert [r for r, _ in seen][:cycles] == [0] * cycles


@pytest.mark.parametrize("ram_style", ["block", None])
def test_memory_delay_sets_its_ram_style(ram_style):
    m = Module()
    value = Signal(4)
    late = Signal(4)
    m.d.comb += late.eq(delayed_in_memory(m, value, 5, name="late", ram_style=ram_style))
    text = rtlil.convert(m, ports=[value, late])
    assert ("ram_style" in text) == (ram_style is not None)
    assert ram_style is None or 'attribute \\ram_style "block"' in text


def test_refuses_a_negative_delay():
    m = Module()
    with pytest.raises(ValueError, match=r"^cycles must be an integer in \[0, inf\), got -1$"):
        delayed_in_memory(m, Signal(4), -1, name="x")
    rtlil.convert(m, ports=[])   # elaborates (and silences UnusedElaboratable)
