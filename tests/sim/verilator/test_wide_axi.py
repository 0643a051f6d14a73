"""``dptbd_axi`` at P = 2 and 4 pixels per clock on Verilator (``AXITopWide``, the AXI
harness with P pixels per ``s_axis_video`` beat: :func:`dptbd.sim.verilator.axi.wide_beat_words`):
every candidate word, flag, register response and counter against the golden model
(:func:`~dptbd.sim.verilator.axi.check_axi`), with gaps, back-pressure, register writes
and a soft reset; cycles per pixel at full rate; the harness's refusals."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.sim.axi.stimulus import Beats, clean_beats
from dptbd.sim.scenarios import make_frames
from dptbd.sim.verilator.axi import check_axi, run_axi, wide_beat_words
from helpers.refusals import whole
from helpers.verilator_harness import built, make_config, needs_verilator

pytestmark = needs_verilator

# 16 x 12, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4: lists with records
SMALL = dict(width=16, height=12, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)


#: P = 2, and P = 4 under ``-m slow``: the default suite runs ``dptbd_axi`` at P = 4 on
#: Verilator in the campaign (``tests/sim/campaign/test_campaign.py``: bit-exact with stalls,
#: resets and faults) and with the AXI4 store (``test_axi_store.py``).
P_VALUES = [2, pytest.param(4, marks=pytest.mark.slow)]


def frames_of(cfg, n, seed):
    return make_frames("two-targets", cfg, n, seed=seed)


def wide_config(p):
    """SMALL at P pixels per clock with 2^(7 - P/2) bins: at P = 4 the 48 beats of a frame
    scan the 32 bins without a stall (test_full_rate_bit_exact); one build per P for every
    test here."""
    return make_config(**{**SMALL, "histogram_bits": 7 - p // 2}, pixels_per_clock=p)


@pytest.mark.parametrize("p", P_VALUES)
def test_full_rate_bit_exact(p):
    """tvalid and tready held high: bit-exact lists and counters; one beat per clock
    through the first segment (nothing to funnel: its list is empty), and every stall
    after it a beat of several records."""
    cfg = wide_config(p)
    assert (cfg.segment_frames - 1) * cfg.frame_beats >= cfg.n_bins + 4   # no scan stall
    sim = built(cfg, "axi")
    frames = frames_of(cfg, 8, seed=p)
    beats = clean_beats(frames)
    result = check_axi(sim, beats, [{"stop": len(beats)}])
    assert result.passed, result.report()
    assert sum(lst.count for lst in result.lists) >= 6
    accept = result.run.accept_cycles[::p].astype(np.int64)
    assert len(accept) == 8 * cfg.frame_beats
    first_segment = cfg.segment_frames * cfg.frame_beats
    assert (np.diff(accept[:first_segment + 1]) == 1).all()


@pytest.mark.parametrize("p", P_VALUES)
def test_gaps_back_pressure_settings_and_soft_reset(p):
    cfg = wide_config(p)
    sim = built(cfg, "axi")
    frames = frames_of(cfg, 10, seed=3 + p)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    steps = [{"writes": [["CANDIDATE_COUNT", 5], ["HISTOGRAM_SHIFT", 3]], "stop": 3 * frame},
             {"soft_reset": True, "stop": 5 * frame + 8 * p},
             {"writes": [["SEGMENT_FRAMES", 3]], "stop": len(beats)}]
    result = check_axi(sim, beats, steps, valid_gap=0.3, ready_pause=0.4, seed=p)
    assert result.passed, result.report()
    assert result.run.counters["stalled_input_cycles"] > 0


def test_wide_beat_words_and_refusals():
    cfg = wide_config(4)
    beats = clean_beats(frames_of(cfg, 1, seed=1))
    words = wide_beat_words(cfg, beats)
    assert len(words) == cfg.frame_beats
    pixels = beats.pixel[:4]
    assert int(words[0]) == (sum(int(v) << (8 * k) for k, v in enumerate(pixels))
                             | 1 << 32)                                   # tuser[0]
    assert int(words[3]) >> 32 == 2                                       # tlast: row's end
    with pytest.raises(ValueError, match=whole("190 pixels do not fill beats of "
                                               "pixels_per_clock=4")):
        wide_beat_words(cfg, Beats(beats.pixel[:190], beats.first[:190], beats.last[:190]))
    inside = Beats(beats.pixel, beats.first.copy(), beats.last.copy())
    inside.last[5] = True
    with pytest.raises(ValueError, match=whole(
            "at pixels_per_clock=4 tuser[0] (start of frame) may be set on the first pixel "
            "of a beat of 4 and tlast (end of line) on its last only")):
        wide_beat_words(cfg, inside)
    # the run's refusal on the P = 2 build the other tests here use (P = 4's: -m slow)
    narrow = wide_config(2)
    with pytest.raises(ValueError, match=whole(
            "operation 'r' before pixel 3: at pixels_per_clock=2 operations come between "
            "beats, before a pixel index that is a multiple of 2")):
        run_axi(built(narrow, "axi"), clean_beats(frames_of(narrow, 1, seed=1)),
                [(3, "r", 0, 0)])


def test_tdata_wider_than_the_harness_is_refused():
    from dptbd.sim import verilator as V
    cfg = make_config(**SMALL, pixels_per_clock=4, input_bits=10, energy_bits=16)
    with pytest.raises(ValueError, match=whole(
            "design 'axi' at pixels_per_clock=4: s_axis_video_tdata of 64 bits; the AXI "
            "harness drives at most 32")):
        V.build(cfg, "axi")


@pytest.mark.skipif(__import__("shutil").which("iverilog") is None,
                    reason="needs Icarus Verilog")
def test_reset_x_at_p2():
    """4-state (``dptbd.sim.reset_x``): a beat of 2 pixels offered in every cycle, in reset
    and right after it; no X on any output of dptbd_axi, tready low where promised, every
    list after the reset exact."""
    from dptbd.config import DPConfig
    from dptbd.sim.reset_x import run_reset_x_check

    cfg = DPConfig(width=16, height=9, segment_frames=2, candidate_count=4,
                   histogram_bits=4, histogram_shift=4, pixels_per_clock=2).build_config()
    results = run_reset_x_check(cfg, 4, top="axi", resets=[(0, 4), (1, 1), (5, 2)], seed=2)
    assert [r.ok for r in results] == [True] * 3, "\n".join(r.report for r in results)
    assert min(r.words for r in results) >= 2
