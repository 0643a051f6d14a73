"""``ThresholdSearch`` against ``dptbd.model.segmentation.threshold_bin`` (§6.3)."""

import numpy as np

from dptbd.hw.threshold import ThresholdSearch
from dptbd.model.segmentation import threshold_bin
from hw_harness import simulate
from seg_harness import make_config


def test_threshold_search_matches_model():
    cfg = make_config(width=16, height=16, histogram_bits=5, candidate_count=7)
    rng = np.random.default_rng(4)
    full = (1 << cfg.bin_count_bits) - 1
    cases = [rng.integers(0, full + 1, 32) * (rng.random(32) < p) for p in (0.1, 0.3, 1.0)]
    cases += [np.zeros(32, int), np.eye(32, dtype=int)[31] * full,       # top bin > n: T = 32
              np.eye(32, dtype=int)[31] * 7, np.full(32, 1)]
    dut = ThresholdSearch(cfg)
    got = []

    async def bench(ctx):
        assert ctx.get(dut.threshold) == 32 and not ctx.get(dut.primed)
        for index, hist in enumerate(cases):
            load = index != 1                                  # one discarded scan
            ctx.set(dut.load, load)
            for a in range(31, -1, -1):
                ctx.set(dut.scan_valid, 1)
                ctx.set(dut.scan_bin, a)
                ctx.set(dut.scan_count, int(hist[a]))
                ctx.set(dut.scan_last, a == 0)
                await ctx.tick()
            ctx.set(dut.scan_valid, 0)
            assert ctx.get(dut.done)                   # T is loaded at the end of this cycle
            await ctx.tick()
            assert not ctx.get(dut.done)
            got.append((ctx.get(dut.threshold), ctx.get(dut.primed)))

    simulate(dut, bench)
    want = [threshold_bin(h, cfg) for h in cases]
    assert got[0] == (want[0], 1)
    assert got[1] == (want[0], 1)                              # load = 0 keeps T
    assert [t for t, _ in got[2:]] == want[2:]
    assert want[4] == 32 and want[5] == 0 and want[6] == 32 - 7   # n ones from the top
