"""``Histogram`` against ``dptbd.model.segmentation`` (§6.2): counts saturate, a scan clears."""

import random

import numpy as np
import pytest

from dptbd.hw.histogram import Histogram
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import simulate
from helpers.refusals import whole
from helpers.seg_harness import make_config, scan_histogram


def simulate_histogram(cfg, bins, *, gap_probability=0.0, seed=0, scans=2, settle=1,
                       **options):
    """Increment ``bins`` (back to back unless gaps), then, ``settle`` cycles after the last
    increment (1: the first cycle after it, as the segmenter does), scan ``scans`` times.

    Returns the list of scans, each a list of (bin, count) in output order, and the cycles
    from each scan_start to its last count."""
    dut = Histogram(cfg, **options)
    rng = random.Random(seed)
    result = []

    async def bench(ctx):
        for b in bins:
            while rng.random() < gap_probability:
                ctx.set(dut.add_en, 0)
                await ctx.tick()
            ctx.set(dut.add_bin, int(b))
            ctx.set(dut.add_en, 1)
            await ctx.tick()
        ctx.set(dut.add_en, 0)
        for _ in range(settle - 1):
            await ctx.tick()
        result.extend(await scan_histogram(ctx, dut, scans))

    simulate(dut, bench)
    return tuple(result)


@pytest.mark.parametrize("gaps", [0.0, 0.4])
def test_counts_saturate_and_scan_clears(gaps):
    cfg = make_config(width=16, height=16, histogram_bits=4, candidate_count=5,
                      candidate_capacity=5)
    assert cfg.bin_count_bits == 3                    # saturates at 7 >= C + 1 = 6
    rng = np.random.default_rng(1)
    # runs of one bin back to back (read-during-write), a bin far above saturation, bin 0
    bins = np.concatenate([np.full(5, 3), rng.integers(0, 16, 60), np.full(20, 9),
                           [0, 0, 15, 15, 15]])
    scans, spans = simulate_histogram(cfg, bins, gap_probability=gaps, seed=2)
    want = np.minimum(np.bincount(bins, minlength=16), 7)
    assert [b for b, _ in scans[0]] == list(range(15, -1, -1))      # top bin first
    assert [c for _, c in scans[0]][::-1] == want.tolist()
    assert (np.bincount(bins, minlength=16) > 7).any()
    assert all(c == 0 for _, c in scans[1])                         # cleared
    assert spans[0] == 16 + 1                                       # 2**b reads + 1


@pytest.mark.parametrize("settle", [1, 2, 3])
def test_back_to_back_increments_of_near_bins_and_an_early_scan(settle):
    """Increments of one bin one and two cycles apart (the pipeline's hazards: the count is
    taken from the last two writes), with gaps, and the scan started in the first cycle
    after the last increment (``settle=1``, the segmenter's timing) whose last increments
    hit the first bins it reads."""
    cfg = make_config(width=16, height=16, histogram_bits=3, candidate_count=20,
                      candidate_capacity=40)
    top = cfg.n_bins - 1
    rng = np.random.default_rng(settle)
    bins = np.concatenate([rng.choice([top, top - 1, 0], 80), [top - 1, top, top - 1, top]])
    for gaps in (0.0, 0.3):
        scans, spans = simulate_histogram(cfg, bins, gap_probability=gaps, seed=settle,
                                          settle=settle)
        want = np.minimum(np.bincount(bins, minlength=cfg.n_bins), (1 << cfg.bin_count_bits) - 1)
        assert [c for _, c in scans[0]][::-1] == want.tolist()
        assert want[top] > 20 and want[top - 1] > 20
        assert all(c == 0 for _, c in scans[1])
        assert spans == [cfg.n_bins + 1] * 2



@pytest.mark.parametrize("histogram_bits", [4, 11])
def test_dp16kd_style_with_a_model_of_the_block_ram_counts_the_same(histogram_bits):
    """``style="dp16kd"`` (ECP5: the word read in r is the DP16KD's output register in
    r+2) with a behavioural DP16KD: the same scans as the memory style, with the
    read-modify-write hazards of back-to-back increments (18 x 1024 and 9 x 2048)."""
    cfg = make_config(width=16, height=16, histogram_bits=histogram_bits, candidate_count=5,
                      candidate_capacity=5)
    top = cfg.n_bins - 1
    rng = np.random.default_rng(histogram_bits)
    bins = np.concatenate([np.full(9, top), rng.choice([top, top - 1, 3, 0], 80),
                           rng.integers(0, cfg.n_bins, 40)])
    memory = simulate_histogram(cfg, bins, gap_probability=0.3, seed=6)
    block_ram = simulate_histogram(cfg, bins, gap_probability=0.3, seed=6, style="dp16kd",
                                   dp16kd=DP16KDModel)
    assert block_ram == memory
    scans, spans = block_ram
    want = np.minimum(np.bincount(bins, minlength=cfg.n_bins), (1 << cfg.bin_count_bits) - 1)
    assert [c for _, c in scans[0]][::-1] == want.tolist()
    assert all(c == 0 for _, c in scans[1]) and spans == [cfg.n_bins + 1] * 2


def simulate_rounds(cfg, rounds, **options):
    """Rounds of increments, each a list of (bin, idle cycles before it) and the idle
    cycles between its last increment and its scan (0: the scan starts in the next cycle,
    the segmenter's timing); the next round begins in the cycle after the scan's last
    count. Returns each scan's (bin, count + held) list."""
    dut = Histogram(cfg, **options)
    result = []

    async def bench(ctx):
        for increments, settle in rounds:
            for b, gap in increments:
                ctx.set(dut.add_en, 0)
                for _ in range(gap):
                    await ctx.tick()
                ctx.set(dut.add_bin, int(b))
                ctx.set(dut.add_en, 1)
                await ctx.tick()
            ctx.set(dut.add_en, 0)
            for _ in range(settle):
                await ctx.tick()
            scans, _ = await scan_histogram(ctx, dut, 1)
            result.append(scans[0])

    simulate(dut, bench)
    return result


@pytest.mark.parametrize("held_apart", [False, True])
def test_dp16kd_style_increments_at_every_distance_and_around_scans(held_apart):
    """``style="dp16kd"`` (the ECP5 pipeline: an increment of the bin read one cycle before
    adds to that read's amount, the counts formed two to four reads before are forwarded)
    against the reference counts: one bin again after 0-5 other bins back to back, runs,
    random bins with gaps, saturation, the last two or three increments on the scan's
    first bins with the scan in the next cycle, increments right after a scan, with and
    without ``held_apart``."""
    cfg = make_config(width=16, height=16, histogram_bits=3, candidate_count=20,
                      candidate_capacity=40)
    top, full = cfg.n_bins - 1, (1 << cfg.bin_count_bits) - 1
    assert full == 63
    rng = np.random.default_rng(7)
    rounds = []
    for k in range(15):
        distances = [b for d in range(1, 7) for b in [top, *range(1, d), top]]
        runs = np.repeat(rng.choice([top, 0, 5], 4), rng.integers(1, 9, 4)).tolist()
        pattern = [(int(b), int(rng.choice([0, 0, 1, 2, 3]))) for b in
                   rng.choice([top, top - 1, 0, 2], int(rng.integers(1, 30)))]
        tail = [[top, top], [top - 1, top, top], [top, top - 1], [0, top], [top]][k % 5]
        # bin 2 far above saturation; the top bin too, incremented right before the scan
        saturating = {4: [2] * 70, 10: [top] * 70}.get(k, [])
        increments = ([(b, 0) for b in distances + runs + saturating] + pattern
                      + [(b, 0) for b in tail])
        rounds.append((increments, k % 3))
    got = simulate_rounds(cfg, rounds, style="dp16kd", dp16kd=DP16KDModel,
                          held_apart=held_apart)
    want = simulate_rounds(cfg, rounds)
    # held apart, count + held is unsaturated (full + 1) where the count is full, and the
    # scan's first count right after an increment of its bin is that increment's sum
    # (up to 2 * full) where it passes full: above full + 1 after the last increments of
    # round 10 (the held one alone gives full + 1)
    over = max((c for scan in got for _b, c in scan), default=0)
    assert full + 1 < over <= 2 * full if held_apart else over <= full
    got = [[(b, min(c, full)) for b, c in scan] for scan in got]
    counts = [np.bincount([b for b, _ in inc], minlength=cfg.n_bins) for inc, _ in rounds]
    assert got == want == [[(b, min(c[b], full)) for b in range(top, -1, -1)] for c in counts]
    assert sum(c.max() > full for c in counts) == 2


@pytest.mark.parametrize("style", ["memory", "dp16kd"])
def test_held_apart_gives_the_held_increment_beside_the_count(style):
    """``held_apart=True`` (the ECP5 build): the increment the scan's first read displaces
    comes out as ``scan_held`` beside its bin's count, not added to it; count + held is the
    memory style's count, unsaturated when the count is already full."""
    cfg = make_config(width=16, height=16, histogram_bits=4, candidate_count=5,
                      candidate_capacity=5)
    top, full = cfg.n_bins - 1, (1 << cfg.bin_count_bits) - 1
    rng = np.random.default_rng(3)
    for last, held in ((top, 3), (top - 1, full)):      # the held one's bin: 3, or full, before
        bins = np.concatenate([rng.choice([0, 5, 9], 40), np.full(held, last), [last]])
        plain = simulate_histogram(cfg, bins)
        apart = simulate_histogram(cfg, bins, held_apart=True, style=style,
                                   dp16kd=DP16KDModel if style == "dp16kd" else None)
        counts = dict(apart[0][0])
        assert counts[last] == held + 1 and apart[0][1] == plain[0][1]    # held: +1 outside
        assert [(b, min(c, full)) for b, c in apart[0][0]] == plain[0][0]
        assert apart[1] == plain[1] == [cfg.n_bins + 1] * 2


def test_refuses_an_unknown_style_and_too_many_bins_for_a_dp16kd():
    with pytest.raises(ValueError, match=whole(
            "style must be one of ('memory', 'dp16kd'), got 'bram'")):
        Histogram(make_config(width=16, height=16), style="bram")
    cfg = make_config(width=128, height=128, energy_bits=16, histogram_bits=15)
    with pytest.raises(ValueError, match=whole(
            "style 'dp16kd' holds at most 16384 bins, got 32768 (histogram_bits=15); "
            "use 'memory'")):
        Histogram(cfg, style="dp16kd")
