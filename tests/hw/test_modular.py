"""``increment_mod``: a counter's next value, wrapping at its modulus."""

import pytest
from amaranth.hdl import Module, Signal

from dptbd.hw.modular import increment_mod
from helpers.hw_harness import simulate


@pytest.mark.parametrize("modulus", [1, 2, 5, 8, 12, 16])
def test_counts_through_every_state_and_wraps(modulus):
    m = Module()
    counter = Signal(range(modulus))
    m.d.sync += counter.eq(increment_mod(counter, modulus))
    seen = []

    async def bench(ctx):
        for _ in range(3 * modulus + 2):
            seen.append(ctx.get(counter))
            await ctx.tick()

    simulate(m, bench)
    assert seen == [n % modulus for n in range(3 * modulus + 2)]


def test_power_of_two_has_no_comparator():
    """A power-of-two modulus is the counter's own wrap: a plain truncated increment."""
    counter = Signal(range(128))
    assert len(increment_mod(counter, 128)) == 7
    assert "==" not in repr(increment_mod(counter, 128))
    assert "==" in repr(increment_mod(Signal(range(100)), 100))


def test_refuses_an_empty_modulus():
    with pytest.raises(ValueError, match=r"^modulus must be an integer in \[1, inf\), got 0$"):
        increment_mod(Signal(1), 0)
