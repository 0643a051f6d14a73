"""``dptbd_seg`` at P = 2 and 4 pixels per clock on Verilator (``DPSegmenterWide``): the
candidate lists bit for bit against the golden model (``check_frames`` / ``check_stream``
with beats of P pixels in), exact cycle counts, gaps and back-pressure, run-time settings,
resets mid-frame, a resynchronisation (a frame cut short); and 4-state Icarus right after
reset at P = 2 (``dptbd.sim.reset_x``)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.hw.wide import pack_beat
from dptbd.model.settings import SegmentSettings as S
from dptbd.sim import verilator as V
from dptbd.sim.candidate_scoreboard import expected_lists
from dptbd.sim.reset_x import run_reset_x_check
from dptbd.sim.rtl.check import Stimulus, check_frames, check_stream
from dptbd.sim.scenarios import make_frames
from helpers.verilator_harness import SEG, built, make_config, needs_verilator

pytestmark = needs_verilator

#: 16 x 12, K = 3 (the P = 1 tests' SEG) at P = 2 with K up to 4 (test_run_time_settings
#: writes K = 4; one P = 2 build for every test here); P = 4 with 16-bit pixels: 65-bit beats
P2 = dict(SEG, pixels_per_clock=2, max_segment_frames=4)
P4 = dict(SEG, pixels_per_clock=4, input_bits=16, energy_bits=18, histogram_shift=9)
#: The P = 4 build's tests under ``-m slow``: the default suite runs ``dptbd_seg`` at P = 4
#: on Verilator in the campaign (``tests/sim/campaign/test_campaign.py``: bit-exact with
#: stalls, resets and faults), and 65-bit beats in ``test_wide.py``.
P4_SLOW = pytest.param(P4, marks=pytest.mark.slow, id="p4-wide")


def beats(cfg, sim, frames):
    """``pixels`` beats of whole frames, as uint64 words for the harness."""
    p = cfg.pixels_per_clock
    values = [pack_beat(cfg, frame.ravel()[i:i + p], i == 0)
              for frame in np.asarray(frames) for i in range(0, frame.size, p)]
    return V.beat_words(values, V.payload_words(sim, "pixels"))


@pytest.mark.parametrize("kw, words", [pytest.param(P2, 1, id="p2"),
                                      pytest.param(P4, 2, marks=pytest.mark.slow,
                                                   id="p4-wide")])
def test_exact_cycles_and_bits(kw, words):
    """valid and ready high, K = 3, (K-1)·W·H/P >= 2^b + 4: one beat per clock through the
    first segment (its list is empty and unprimed: nothing to funnel) and the first list
    out K·W·H/P + L cycles after the first acceptance (its last beat's end lane one cycle
    after the segmenter accepts it, the trailer 3 later); later, a beat of j >= 2 records
    holds the segmenter for j - 1 cycles, which the DP's input feels."""
    cfg = make_config(**kw)
    sim = built(cfg, "segmenter")
    assert V.payload_words(sim, "pixels") == words
    assert V.payload_words(sim, "candidates") == 1
    k, frame = cfg.segment_frames, cfg.frame_beats
    assert (k - 1) * frame >= cfg.n_bins + 4
    frames = make_frames("two-targets", cfg, 3 * k, seed=3)
    raw = V.run(sim, beats(cfg, sim, frames))
    accept = raw.accept_cycles.astype(np.int64)
    out = raw.out_cycles.astype(np.int64)
    assert raw.status == "done" and len(accept) == 3 * k * frame
    assert (np.diff(accept[:k * frame + 1]) == 1).all()
    kind, fields = unpack_candidate(cfg, int(raw.out_words[0]))
    assert kind == "trailer" and fields["primed"] == 0 and fields["count"] == 0
    assert out[0] - accept[0] == k * frame + sim.latency
    result = check_frames(sim, frames)
    assert result.passed, result.report
    lists = expected_lists(cfg, frames)
    assert sum(lst.count for lst in lists) >= 5
    assert result.words_out == sum(lst.count + 1 for lst in lists)


@pytest.mark.parametrize("kw", [pytest.param(P2, id="p2"), P4_SLOW])
@pytest.mark.parametrize("valid_gap, ready_pause", [(0.3, 0.0), (0.0, 0.7), (0.5, 0.5)])
def test_gaps_and_back_pressure(kw, valid_gap, ready_pause):
    cfg = make_config(**kw)
    sim = built(cfg, "segmenter")
    frames = make_frames("two-targets", cfg, 9, seed=cfg.pixels_per_clock)
    result = check_frames(sim, frames, Stimulus(valid_gap=valid_gap, ready_pause=ready_pause,
                                                seed=7))
    assert result.passed, result.report
    assert result.words_in == frames.size
    assert result.raw.counters["events_list_done"] == 3


def test_run_time_settings():
    """K, n, s changed between segments (the word indices count beats)."""
    cfg = make_config(**P2)
    sim = built(cfg, "segmenter")
    schedule = [S(3, 6, 1), S(2, 4, 2), S(4, 9, 1), S(1, 3, 0), S(3, 6, 1)]
    frames = make_frames("two-targets", cfg, sum(e.segment_frames for e in schedule), seed=5)
    changes, beat = [], 0
    for entry in schedule:
        changes.append((beat, entry))
        beat += entry.segment_frames * cfg.frame_beats
    result = check_frames(sim, frames, Stimulus(valid_gap=0.2, ready_pause=0.3, seed=2,
                                                settings_changes=tuple(changes)))
    assert result.passed, result.report
    assert result.raw.counters["events_list_done"] == len(schedule)


@pytest.mark.parametrize("kw", [pytest.param(P2, id="p2"), P4_SLOW])
def test_resets_mid_frame(kw):
    """Resets at chosen cycles: before each, a prefix of the model's lists; after the last,
    the model's lists of the beats accepted since."""
    cfg = make_config(**kw)
    sim = built(cfg, "segmenter")
    frames = make_frames("two-targets", cfg, 9, seed=11)
    span = 9 * cfg.frame_beats
    resets = ((span // 5, 3), (span // 2 + 7, 1), (span - 40, 2))
    result = check_frames(sim, frames, Stimulus(valid_gap=0.1, ready_pause=0.2, seed=4,
                                                resets=resets))
    assert result.passed, result.report
    assert result.epochs == 4


def test_a_frame_cut_short_resynchronises():
    """A frame cut after 20 beats (the next frame's ``first`` comes early): the lists
    carry ``aligned`` = 0 until the segmenter realigns, as the model says."""
    cfg = make_config(**P2)
    sim = built(cfg, "segmenter")
    frames = make_frames("two-targets", cfg, 10, seed=8)
    words = beats(cfg, sim, frames)
    frame = cfg.frame_beats
    words = np.concatenate([words[:4 * frame + 20], words[5 * frame:]])
    result = check_stream(sim, words, Stimulus(valid_gap=0.2, ready_pause=0.2, seed=9))
    assert result.passed, result.report
    flags = {lst.aligned for _, exp, board in result.scored for lst in board.lists}
    assert flags == {True, False}


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")
def test_reset_x_at_p2():
    """4-state: a beat offered in every cycle, in reset and right after it; no X on any
    output of dptbd_seg, ready low where promised, every list after the reset exact."""
    cfg = DPConfig(width=16, height=9, segment_frames=2, candidate_count=4,
                   histogram_bits=4, histogram_shift=4, pixels_per_clock=2).build_config()
    results = run_reset_x_check(cfg, 4, top="seg", resets=[(0, 4), (0, 1), (1, 1), (5, 2)],
                                seed=2)
    assert [r.ok for r in results] == [True] * 4, "\n".join(r.report for r in results)
    assert min(r.words for r in results) >= 2                     # two lists' trailers
