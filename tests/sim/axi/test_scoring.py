"""Lists that a reset or the stream's end leaves open in ``dptbd_axi``'s runs
(:mod:`dptbd.sim.axi.stimulus` ``CutList``, :mod:`dptbd.sim.axi.scoring`): closed by the
cut trailer at a soft reset, abandoned by ``aresetn``, left open at the end; resets with
words in flight, and the counters across them."""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.hw.candidate_layout import pack_cut_trailer, unpack_candidate
from dptbd.hw.register_map import constants_namespace
from dptbd.sim.verilator import axi as verilator_axi
from dptbd.sim.axi.stimulus import Beats, CutList, clean_beats, expected_outputs
from dptbd.sim.candidate_scoreboard import list_words
from dptbd.sim.coverage import bins
from dptbd.sim.scenarios import make_frames
from dptbd.sim.verilator.axi import check_axi
from helpers.verilator_harness import HAVE_VERILATOR, built, make_config, needs_verilator

# the configuration of tests/sim/axi/test_runs.py and tests/sim/verilator/test_axi.py (one build)
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)

def test_a_soft_reset_in_a_scored_frame_cuts_its_list():
    """K = 2: frame 3 is segment 1's scored frame; a soft reset 6 lines into it closes the
    list of the records sent (rows 3 and 5) with the cut trailer, not counted in LISTS."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    steps = [{"stop": 432}, {"soft_reset": True, "stop": len(beats)}]
    expected = expected_outputs(cfg, beats, steps, cut_lists=True)
    assert [isinstance(lst, CutList) for lst in expected.lists] == [False, True, False]
    cut = expected.lists[1]                             # after segment 0's, before the next
    assert cut.records[["row", "col"]].tolist() == [(3, 9), (5, 6)] and cut.count == 2
    assert list_words(cfg, [cut])[0][-1] == pack_cut_trailer(cfg, 2)
    assert expected.counters()["LISTS"] == len(expected.lists) - 1 == 2
    assert len(expected_outputs(cfg, beats, steps).lists) == 2          # without cut_lists
    assert not any(isinstance(lst, CutList) for lst in expected_outputs(
        cfg, beats, [{"stop": 360}, {"soft_reset": True, "stop": len(beats)}],
        cut_lists=True).lists)                                          # on a frame boundary
    if HAVE_VERILATOR:
        result = check_axi(built(cfg, "axi"), beats, steps, valid_gap=0.2, ready_pause=0.4,
                           seed=3)
        assert result.passed, result.report()


def cut_flags(cfg, words):
    """Per word: the trailer's ``cut`` bit, None for a record."""
    return [unpack_candidate(cfg, int(w))[1].get("cut") for w in words]


@needs_verilator
def test_a_soft_reset_with_words_in_flight_sends_a_prefix_then_the_cut_trailer(monkeypatch):
    """At the end of segment 1's scored frame (beat 480): drained, its list is whole; not
    drained (``"now"``, 90 % back-pressure) the records in the output path are sent, the
    list is closed by the cut trailer, and the words still in the pipeline are lost."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    sim = built(cfg, "axi")
    drained = check_axi(sim, beats, [{"stop": 480}, {"soft_reset": True, "stop": len(beats)}],
                        ready_pause=0.9, seed=5)
    assert drained.passed, drained.report()
    assert cut_flags(cfg, drained.run.out_words) == [0, None, None, 0, 0]
    steps = [{"stop": 480}, {"soft_reset": "now", "stop": len(beats)}]
    now = check_axi(sim, beats, steps, ready_pause=0.9, seed=5)
    assert now.passed, now.report()
    assert cut_flags(cfg, now.run.out_words) == [0, None, None, 1, 0]
    assert now.run.out_words[3] == pack_cut_trailer(cfg, 2)
    # right after the cut FRAMES, SEGMENTS, LISTS, SATURATED read 3, 1, 1, 0 (frame 3 lost
    # in the pipeline); at the end each is that plus the model's count after beat 480
    assert [int(v) for v in now.run.op_data[2:6]] == [3, 1, 1, 0]
    assert [now.expected_counters[k] for k in verilator_axi.CUT_COUNTERS] == [5, 2, 2, 0]
    real = verilator_axi.run_axi

    def miscounted(*args, **kw):
        run = real(*args, **kw)
        words = run.out_words.copy()
        words[3] = pack_cut_trailer(cfg, 1)
        return dataclasses.replace(run, out_words=words)

    monkeypatch.setattr(verilator_axi, "run_axi", miscounted)
    wrong = check_axi(sim, beats, steps, ready_pause=0.9, seed=5)
    got = [hex(int(w)) for w in now.run.out_words[1:3]] + [hex(pack_cut_trailer(cfg, 1))]
    assert wrong.problems == [f"before the soft reset at beat 480: after 1 whole lists of 2, "
                              f"words {got} are not a list's first records closed by the "
                              f"cut trailer"]


def test_aresetn_abandons_the_open_list_and_resets_the_registers():
    """aresetn 6 lines into segment 1's scored frame (after the pipeline drained): the two
    records sent stay without a trailer, the next list starts with tuser[0]; K written 3
    before reads 2 (the build's) after, ERROR (write_refused before) and the counters 0."""
    cfg = make_config(**SMALL)
    regs = constants_namespace(cfg)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    steps = [{"writes": [["HISTOGRAM_SHIFT", 99]], "stop": 400},        # refused
             {"writes": [["SEGMENT_FRAMES", 3]], "stop": 432},            # for segment 2
             {"check": {"ERROR": regs.ERROR_WRITE_REFUSED_MASK, "SEGMENT_FRAMES": 3},
              "aresetn": 2, "stop": 432},                                 # reads, then low
             {"check": {"SEGMENT_FRAMES": 2, "ERROR": 0, "FRAMES": 0, "IRQ_ENABLE": 0},
              "stop": len(beats)}]
    expected = expected_outputs(cfg, beats, steps, cut_lists=True)
    abandoned = [lst for lst in expected.lists if isinstance(lst, CutList)]
    assert [(lst.count, lst.closed) for lst in abandoned] == [(2, False)]
    assert [len(w) for w in list_words(cfg, abandoned)] == [2]              # no trailer
    assert expected.counters()["LISTS"] == len(expected.lists) - 1
    if not HAVE_VERILATOR:
        return
    result = check_axi(built(cfg, "axi"), beats, steps, ready_pause=0.3, seed=2)
    assert result.passed, result.report()
    flags = result.run.out_flags
    assert [(int(f) & 1, int(f) >> 1) for f in flags[:4]] == [(1, 1), (1, 0), (0, 0), (1, 1)]
    assert result.reads["ERROR"] == 0


def test_the_stream_end_leaves_a_list_open(monkeypatch):
    """3.6 frames of K = 2: segment 1's scored frame stops after 6 lines; its records so
    far (rows 3 and 5) are sent, never closed."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 4, seed=1))
    part = Beats(beats.pixel[:432], beats.first[:432], beats.last[:432])
    expected = expected_outputs(cfg, part, [{"stop": 432}], cut_lists=True)
    assert len(expected.lists) == 1 and len(expected.open_records) == 2
    assert [unpack_candidate(cfg, w)[1]["row"] for w in expected.open_records] == [3, 5]
    assert expected_outputs(cfg, part, [{"stop": 432}]).open_records == ()
    if not HAVE_VERILATOR:
        return
    sim = built(cfg, "axi")
    result = check_axi(sim, part, [{"stop": 432}], ready_pause=0.3)
    assert result.passed, result.report()
    real = verilator_axi.run_axi
    monkeypatch.setattr(verilator_axi, "run_axi", lambda *a, **kw: dataclasses.replace(
        real(*a, **kw), out_words=real(*a, **kw).out_words[:-1]))
    wrong = check_axi(sim, part, [{"stop": 432}], ready_pause=0.3)
    records = [hex(w) for w in expected.open_records]
    assert wrong.problems == [f"after the last list: 1 words {records[:1]}, the open list's "
                              f"records {records}"]


@needs_verilator
def test_a_soft_reset_after_j_idle_cycles_finds_l_minus_j_words_in_flight():
    """At full speed, soft resets of "now" 30 beats apart after j = 0 … 18 idle cycles: the
    j-th finds L - j words in flight (0 from j = L on); the write is answered in its
    third cycle (``AXIL_WRITE_CYCLES``) after the beat before it."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    steps = [{"stop": 60}] + [{"soft_reset": "now", "soft_reset_wait": j, "stop": 90 + 30 * j}
                              for j in range(19)] + [{"stop": len(beats)}]
    sim = built(cfg, "axi")
    result = check_axi(sim, beats, steps, seed=1)
    assert result.passed, result.report()
    _, checks = verilator_axi.step_operations(cfg, steps, 0, [])
    first = next(i for i, c in enumerate(checks) if c[0] == "wait") - 1
    assert result.run.op_cycles[first] - result.run.accept_cycles[59] == bins.AXIL_WRITE_CYCLES
    counts = bins.axi_bins(cfg, beats, steps, passed=True, latency=sim.latency,
                           run=result.run)
    assert sim.latency == 17
    assert [counts[bins.soft_reset_bin(k)] for k in range(18)] == [2] + [1] * 17



def _dropping(monkeypatch, cfg, index):
    """``run_axi`` with output word ``index`` (and its flags and cycle) removed."""
    real = verilator_axi.run_axi

    def dropped(*args, **kw):
        run = real(*args, **kw)
        keep = np.arange(len(run.out_words)) != index
        return dataclasses.replace(run, out_words=run.out_words[keep],
                                   out_flags=run.out_flags[keep],
                                   out_cycles=run.out_cycles[keep])

    monkeypatch.setattr(verilator_axi, "run_axi", dropped)


@needs_verilator
def test_aresetn_with_words_in_flight_sends_a_prefix_without_trailer(monkeypatch):
    """aresetn at beat 480 (segment 1's scored frame just ended), 90 % back-pressure: the
    records in the output path are sent (two of them), no trailer, the next list starts
    with tuser[0]; the words still in the pipeline are lost; the counters from 0 after it.
    A trailer after those records is caught."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    sim = built(cfg, "axi")
    steps = [{"stop": 480}, {"aresetn": 2, "aresetn_wait": 0, "stop": len(beats)}]
    expected = expected_outputs(cfg, beats, steps, cut_lists=True)
    assert not any(isinstance(lst, CutList) for lst in expected.lists)   # list 1 whole
    result = check_axi(sim, beats, steps, ready_pause=0.9, seed=5)
    assert result.passed, result.report()
    assert [int(f) for f in result.run.out_flags] == [3, 1, 0, 3]
    whole = list_words(cfg, expected.lists[1:2])[0]                   # 2 records, trailer
    assert len(whole) == 3 and [int(w) for w in result.run.out_words[1:3]] == whole[:2]
    assert [result.expected_counters[k] for k in verilator_axi.CUT_COUNTERS] == [2, 1, 1, 0]
    real = verilator_axi.run_axi

    def closed(*args, **kw):
        run = real(*args, **kw)
        words = run.out_words.copy()
        words[2] = pack_cut_trailer(cfg, 1)
        return dataclasses.replace(run, out_words=words)

    monkeypatch.setattr(verilator_axi, "run_axi", closed)
    wrong = check_axi(sim, beats, steps, ready_pause=0.9, seed=5)
    got = [hex(int(w)) for w in result.run.out_words[1:2]] + [hex(pack_cut_trailer(cfg, 1))]
    assert wrong.problems == [f"before the aresetn at beat 480: after 1 whole lists of 2, "
                              f"words {got} are not a list's first records"]


@needs_verilator
def test_a_list_missing_before_a_soft_reset_with_words_in_flight_is_caught(monkeypatch):
    """A soft reset of "now" at beat 300: segment 0's list came out before it (LISTS read
    1 right after); without that list the words alone would pass (the reset may have
    lost it), LISTS against the lists delivered does not."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    sim = built(cfg, "axi")
    steps = [{"stop": 300}, {"soft_reset": "now", "stop": len(beats)}]
    result = check_axi(sim, beats, steps, seed=5)
    assert result.passed, result.report()
    assert [int(v) for v in result.run.op_data[2:6]] == [2, 1, 1, 0]
    _dropping(monkeypatch, cfg, 0)
    wrong = check_axi(sim, beats, steps, seed=5)
    assert wrong.problems == ["after the soft reset at beat 300: LISTS went from 0 to 1, 0 "
                              "lists were delivered"]
