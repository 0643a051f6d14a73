"""``ThermometerCounter``: random up/down events against a Python counter; ``ref_*`` is the
flags a saturating counter gives, ``rtl_*`` records the component's flags every cycle."""

import random

import pytest

from dptbd.errors import DptbdError
from dptbd.hw.thermometer_counter import ThermometerCounter
from helpers.hw_harness import refused, simulate


def cases():
    """(limit, events: a list of (up, down) per cycle)."""
    out = []
    for limit, seed in [(1, 1), (2, 2), (5, 3), (17, 4)]:
        rng = random.Random(seed)
        # Runs biased up, then down, then even, so the counter visits 0 and limit often.
        bias = [0.8] * 40 + [0.2] * 40 + [0.5] * 60
        out.append((limit, [(rng.random() < p, rng.random() < 1 - p) for p in bias]))
    return out


def ref_thermometer(limit, events):
    """Flags (bit k - 1 = count >= k) before each cycle's edge; the count saturates."""
    count, flags = 0, []
    for up, down in events:
        flags.append(sum(1 << k for k in range(count)))
        count = min(limit, max(0, count + up - down))
    return flags


def rtl_thermometer(limit, events):
    dut = ThermometerCounter(limit)
    flags = []

    async def bench(ctx):
        for up, down in events:
            ctx.set(dut.up, up)
            ctx.set(dut.down, down)
            flags.append(ctx.get(dut.at_least))
            await ctx.tick()

    simulate(dut, bench)
    return flags


@pytest.mark.parametrize("limit, events", cases(), ids=[f"limit{c[0]}" for c in cases()])
def test_flags_follow_a_saturating_counter(limit, events):
    flags = rtl_thermometer(limit, events)
    assert flags == ref_thermometer(limit, events)
    assert 0 in flags and (1 << limit) - 1 in flags   # both ends visited


def test_refuses_a_limit_below_one():
    with refused(DptbdError, r"^limit must be an integer in \[1, inf\), got 0$"):
        ThermometerCounter(0)
