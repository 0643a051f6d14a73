"""``DPSegmenterWide`` (the P-pixel DP pipeline + ``SegmenterWide``) against the golden
models, bit for bit: beats of P pixels in, the candidate lists of ``dptbd.model.fixed`` +
``segment_sequence`` out, with input gaps, back-pressure and run-time settings."""

import numpy as np
import pytest

from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.wide import pack_beat
from dptbd.hw.wide.dp_segmenter import DPSegmenterWide, dp_segmenter
from dptbd.model.fixed import run_fixed
from dptbd.model.segmentation import segment_sequence
from dptbd.model.settings import SegmentSettings as S
from dptbd.sim.candidate_scoreboard import expected_lists
from dptbd.sim.scenarios import make_frames
from helpers.seg_harness import make_config, run_lists
from helpers.wide_harness import frames_to_beats

CASES = {
    # name: (config, scenario, frames, seed, (valid, ready))
    "p2-16x12-k3-table1": (dict(width=16, height=12, segment_frames=3, candidate_count=5,
                                histogram_bits=6, histogram_shift=1, pixels_per_clock=2),
                           "table1", 9, 1, (0.8, 0.6)),
    "p4-12x6-k2-cap": (dict(width=12, height=6, segment_frames=2, candidate_count=10,
                            candidate_capacity=10, histogram_bits=5, histogram_shift=4,
                            pixels_per_clock=4), "random", 8, 3, (0.8, 0.6)),
    "p4-16x6-k1": (dict(width=16, height=6, segment_frames=1, candidate_count=20,
                        histogram_bits=4, pixels_per_clock=4), "random", 5, 4, (0.9, 0.7)),
}


def beat_payloads(cfg, frames):
    return [pack_beat(cfg, pixels, first) for pixels, first in frames_to_beats(cfg, frames)]


@pytest.mark.parametrize("name", list(CASES))
def test_matches_golden_model(name):
    kw, scenario, n_frames, seed, (valid, ready) = CASES[name]
    cfg = make_config(**kw)
    frames = make_frames(scenario, cfg, n_frames, seed=seed)
    lists = expected_lists(cfg, frames)
    dut = DPSegmenterWide(cfg)
    run_lists(cfg, dut, dut.pixels, dut.candidates, beat_payloads(cfg, frames), lists,
              valid_probability=valid, ready_probability=ready, seed=n_frames)
    assert len(lists) == n_frames // cfg.segment_frames
    assert sum(lst.count for lst in lists) >= 7
    if "cap" in name:
        assert any(lst.overflow for lst in lists)


def test_run_time_settings_per_segment():
    """Settings driven with a segment's first beat, random elsewhere: the lists of the
    schedule (K, n, s per segment)."""
    cfg = make_config(width=12, height=6, segment_frames=2, max_segment_frames=3,
                      candidate_count=4, candidate_capacity=16, histogram_bits=5,
                      histogram_shift=3, pixels_per_clock=2)
    schedule = [S(2, 8, 5), S(1, 12, 4), S(3, 4, 6), S(1, 16, 3), S(2, 6, 5)]
    frames = make_frames("random", cfg, sum(e.segment_frames for e in schedule), seed=6)
    segments = run_fixed(frames, cfg, schedule)
    lists = segment_sequence(segments.energy.astype(np.int64), segments.direction, cfg,
                             schedule)
    starts, beat = {}, 0
    for entry in schedule:
        starts[beat] = entry
        beat += entry.segment_frames * cfg.frame_beats
    rng = np.random.default_rng(6)
    dut = DPSegmenterWide(cfg)

    def drive(ctx, index):
        entry = starts.get(index)
        for name in ("segment_frames", "candidate_count", "histogram_shift"):
            port = getattr(dut, name)
            ctx.set(port, getattr(entry, name) if entry
                    else int(rng.integers(0, 1 << len(port))))

    run_lists(cfg, dut, dut.pixels, dut.candidates, beat_payloads(cfg, frames), lists,
              valid_probability=0.8, ready_probability=0.7, seed=6, on_cycle=drive)
    assert len(lists) == len(schedule) and len({lst.threshold for lst in lists}) >= 3
    assert sum(lst.count for lst in lists) >= 10


def test_exact_cycles_k2():
    """valid and ready held high, K = 2: one beat per clock (no stall for the scan); the
    last trailer out exactly as the segmenter's timing says after the last beat."""
    cfg = make_config(width=16, height=8, segment_frames=2, candidate_count=2,
                      histogram_bits=4, histogram_shift=6, pixels_per_clock=4)
    frames = make_frames("random", cfg, 6, seed=2)
    lists = expected_lists(cfg, frames)
    dut = DPSegmenterWide(cfg)
    result = run_lists(cfg, dut, dut.pixels, dut.candidates, beat_payloads(cfg, frames),
                       lists)
    accepts = result.accept_cycles
    assert accepts == list(range(accepts[0], accepts[0] + 6 * cfg.frame_beats))
    # the last beat ends a list: the segmenter (L cycles after the DP) accepts it into its
    # selection stage, moves it to the funnel in the next cycle, which hands out its
    # selected lanes and lane P-1 (h lanes) one per cycle from the cycle after; the trailer
    # is out 3 cycles after the last hand-out
    assert dut.latency == dut.schedule.latency + 4
    last = [int(r["col"]) for r in lists[-1].records
            if int(r["row"]) == cfg.height - 1 and int(r["col"]) >= cfg.width - 4]
    hand_outs = len(set(last) | {cfg.width - 1})
    assert result.output_cycles[-1] - accepts[-1] == dut.latency + hand_outs


def test_dp_segmenter_picks_by_p():
    assert isinstance(dp_segmenter(make_config(width=8, height=6, candidate_count=2)),
                      DPSegmenter)
    assert isinstance(dp_segmenter(make_config(width=8, height=6, candidate_count=2,
                                               pixels_per_clock=2)), DPSegmenterWide)
