"""The register delay line helper."""

from amaranth.hdl import Module, Signal
from amaranth.lib import data

from dptbd.hw.delay import delayed
from hw_harness import simulate


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
