"""``BankedHistogram``: P banks merged at the scan give the counts one ``Histogram`` of every
increment gives (§6.2), saturation included."""

import random

import numpy as np
import pytest

from dptbd.hw.banked_histogram import BankedHistogram
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import simulate
from helpers.refusals import whole
from helpers.seg_harness import make_config, scan_histogram


def ref_counts(cfg, beats):
    """What one histogram of every increment holds: saturating counts per bin."""
    full = (1 << cfg.bin_count_bits) - 1
    flat = [b for beat in beats for b in beat if b is not None]
    return np.minimum(np.bincount(np.array(flat, dtype=np.int64), minlength=cfg.n_bins), full)


def rtl_scans(cfg, beats, *, seed=0, scans=2, style="memory", held_apart=False):
    """Increment ``beats`` (each a P-tuple of bins, ``None`` for an idle lane), one per
    cycle with random idle cycles, then scan ``scans`` times with banks of ``style`` (a
    behavioural DP16KD for ``"dp16kd"``), the first scan started in the cycle after the
    last beat (whose increments the banks hold): the scans' (bin, count) lists (with
    ``held_apart``, count + ``scan_held``) and the cycles from each scan_start to its last
    count."""
    dut = BankedHistogram(cfg, style=style, dp16kd=DP16KDModel if style == "dp16kd" else None,
                          held_apart=held_apart)
    rng = random.Random(seed)
    result = []

    async def bench(ctx):
        for beat in beats:
            while rng.random() < 0.3:
                ctx.set(dut.add_en, 0)
                await ctx.tick()
            ctx.set(dut.add_en, sum(1 << k for k, b in enumerate(beat) if b is not None))
            for k, b in enumerate(beat):
                ctx.set(dut.add_bin[k], 0 if b is None else int(b))
            await ctx.tick()
        ctx.set(dut.add_en, 0)
        result.extend(await scan_histogram(ctx, dut, scans))

    simulate(dut, bench)
    return tuple(result)


def cases():
    """(name, P, beats): a lane idle at random, one bin hit by every lane of a beat (the
    banks' counts add up), a bin saturated in one bank only, one saturated only in the sum;
    the last beat increments a bin in every bank (the increments the scan holds)."""
    rng = np.random.default_rng(4)
    out = []
    for p in (1, 2, 4):
        free = [b for b in range(16) if b not in (5, 9)]
        beats = [tuple(None if rng.random() < 0.2 else int(rng.choice(free))
                       for _ in range(p)) for _ in range(40)]
        beats += [(5,) * p] * 3                     # 3P hits of bin 5 in three cycles
        beats += [(9,) + (None,) * (p - 1)] * 9     # bank 0 alone saturates bin 9
        beats += [tuple(12 if k % 2 else None for k in range(p))] * 3   # odd lanes: bin 12
        beats += [tuple(range(p))]                  # held: bins 0 … P-1, one per bank
        out.append((f"p{p}", p, beats))
    return out


@pytest.mark.parametrize("style, held_apart", [("memory", False), ("dp16kd", False),
                                               ("memory", True), ("dp16kd", True)])
@pytest.mark.parametrize("name, p, beats", cases(), ids=[c[0] for c in cases()])
def test_merged_counts_equal_one_histogram(name, p, beats, style, held_apart):
    """The counts of one histogram; held apart (the ECP5 build), count + held is one more
    where the clamped count is already all ones (a count above every n either way)."""
    cfg = make_config(width=16, height=16, histogram_bits=4, candidate_count=5,
                      candidate_capacity=5, pixels_per_clock=p)
    assert cfg.bin_count_bits == 3                              # saturates at 7
    scans, spans = rtl_scans(cfg, beats, seed=p, style=style, held_apart=held_apart)
    if held_apart:
        assert max(c for scan in scans for _, c in scan) <= 8
        scans = [[(b, min(c, 7)) for b, c in scan] for scan in scans]
    want = ref_counts(cfg, beats)
    assert [b for b, _ in scans[0]] == list(range(15, -1, -1))  # top bin first
    assert [c for _, c in scans[0]][::-1] == want.tolist()
    assert want[9] == 7 and want[5] == min(3 * p, 7)   # saturated in a bank; at P = 4 in the sum only
    assert all(c == 0 for _, c in scans[1])                     # every bank cleared
    # Histogram's scan timing at P = 1; one cycle more at P = 2 (the merge register), two
    # at P = 4 (the pairs' register too)
    assert spans == [16 + 1 + {1: 0, 2: 1, 4: 2}[p]] * 2


def test_refuses_an_unknown_style():
    cfg = make_config(width=16, height=16, histogram_bits=4, pixels_per_clock=2)
    with pytest.raises(ValueError, match=whole("style must be one of ('memory', 'dp16kd'), "
                                               "got 'bram'")):
        BankedHistogram(cfg, style="bram")
