"""``ThresholdSearch`` against ``dptbd.model.segmentation.threshold_bin`` (§6.3).

Glasgow's pattern: ``cases()`` yields the histograms, ``ref_threshold`` is the golden
model's threshold bin, ``rtl_threshold`` the gateware's (T, primed) after each scan.
"""

import numpy as np

from dptbd.hw.threshold import ThresholdSearch
from dptbd.model.segmentation import threshold_bin
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def cases(cfg):
    """Histograms of 2**b bins: random at three densities, empty, only the top bin (full or
    n), one in every bin."""
    rng = np.random.default_rng(4)
    bins, full = cfg.n_bins, (1 << cfg.bin_count_bits) - 1
    top = np.eye(bins, dtype=int)[bins - 1]
    yield from (rng.integers(0, full + 1, bins) * (rng.random(bins) < p) for p in (0.1, 0.3, 1.0))
    yield from [np.zeros(bins, int), top * full, top * cfg.n_candidates, np.full(bins, 1)]


def ref_threshold(cfg, histogram, count=None) -> int:
    return threshold_bin(histogram, cfg, count)


def rtl_threshold(cfg, histograms, load, counts=None, held=None) -> list[tuple[int, int]]:
    """Scan each histogram from the top bin down (``load[i]``: keep the result; ``counts[i]``:
    the run-time n, on the port with the top bin only, random values with the others);
    (T, primed) after each scan. Before the first: T = 2**b, unprimed. ``held`` (with
    ``held_apart``): per histogram the bins whose count is given as count - 1 on
    ``scan_count`` and 1 on ``scan_held``."""
    apart_ports = held is not None
    dut = ThresholdSearch(cfg, held_apart=apart_ports)
    got = []
    rng = np.random.default_rng(8)
    counts = [cfg.n_candidates] * len(histograms) if counts is None else counts

    held = [()] * len(histograms) if held is None else held

    async def bench(ctx):
        assert ctx.get(dut.threshold) == cfg.n_bins and not ctx.get(dut.primed)
        for hist, keep, n, apart in zip(histograms, load, counts, held):
            ctx.set(dut.load, keep)
            for a in range(cfg.n_bins - 1, -1, -1):
                ctx.set(dut.count, n if a == cfg.n_bins - 1 else
                        int(rng.integers(0, 1 << len(dut.count))))
                ctx.set(dut.scan_valid, 1)
                ctx.set(dut.scan_bin, a)
                ctx.set(dut.scan_count, int(hist[a]) - (a in apart))
                if apart_ports:
                    ctx.set(dut.scan_held, a in apart)
                    ctx.set(dut.scan_first, a == cfg.n_bins - 1)
                ctx.set(dut.scan_last, a == 0)
                await ctx.tick()
            ctx.set(dut.scan_valid, 0)
            assert ctx.get(dut.done)                   # T is loaded at the end of this cycle
            await ctx.tick()
            assert not ctx.get(dut.done)
            got.append((ctx.get(dut.threshold), ctx.get(dut.primed)))

    simulate(dut, bench)
    return got


def test_threshold_search_matches_model():
    cfg = make_config(width=16, height=16, histogram_bits=5, candidate_count=7)
    histograms = list(cases(cfg))
    want = [ref_threshold(cfg, h) for h in histograms]
    assert want[4] == 32 and want[5] == 0 and want[6] == 32 - 7   # n ones from the top
    assert rtl_threshold(cfg, histograms, [True] * len(histograms)) == [(t, 1) for t in want]


def test_a_scan_not_loaded_keeps_the_threshold():
    cfg = make_config(width=16, height=16, histogram_bits=5, candidate_count=7)
    histograms = list(cases(cfg))[:3]
    want = [ref_threshold(cfg, h) for h in histograms]
    assert rtl_threshold(cfg, histograms, [True, False, True]) == \
        [(want[0], 1), (want[0], 1), (want[2], 1)]


def test_run_time_n_is_sampled_with_the_top_bin():
    """n changes from scan to scan (0, C and between; above C clamps to C)."""
    cfg = make_config(width=16, height=16, histogram_bits=5, candidate_count=7,
                      candidate_capacity=12)
    histograms = list(cases(cfg)) * 2
    counts = [0, 12, 3, 7, 1, 11, 12, 5, 15, 2, 9, 0, 6, 4]
    assert len(counts) == len(histograms) and (12).bit_length() == 4   # 15 fits the port
    want = [ref_threshold(cfg, h, min(n, 12)) for h, n in zip(histograms, counts)]
    assert len(set(want)) >= 5
    assert rtl_threshold(cfg, histograms, [True] * len(histograms), counts) == \
        [(t, 1) for t in want]


def test_held_apart_adds_the_held_increment_in_the_search():
    """``held_apart=True`` (the ECP5 build): a bin's count arrives as count - 1 plus
    ``scan_held``; the same thresholds, also where count + held is 2**bits (a full count
    and the held one: the histogram does not saturate it) and where the held one decides
    (n exactly reached with it, exceeded by it)."""
    cfg = make_config(width=16, height=16, histogram_bits=5, candidate_count=7)
    full, top = (1 << cfg.bin_count_bits) - 1, cfg.n_bins - 1
    rng = np.random.default_rng(9)
    histograms, held = [], []
    for h in cases(cfg):
        histograms.append(h)
        held.append(tuple(int(a) for a in np.flatnonzero(h) if rng.random() < 0.5))
    one = np.zeros(cfg.n_bins, int)
    one[top - 2] = full                                 # the search stops there at the latest
    for counts, apart in (((7, 0), (top,)), ((8, 0), (top,)), ((6, 1), (top - 1,)),
                          ((6, 2), (top - 1,)), ((full + 1, 0), (top,))):
        h = one.copy()
        h[top], h[top - 1] = counts
        histograms.append(h)
        held.append(apart)
    model = [np.minimum(h, full) for h in histograms]
    want = [ref_threshold(cfg, h) for h in model]
    assert want[-5:] == [top - 1, cfg.n_bins, top - 1, top, cfg.n_bins]
    assert sum(len(a) for a in held) > 20
    assert rtl_threshold(cfg, histograms, [True] * len(histograms), held=held) == \
        [(t, 1) for t in want]
