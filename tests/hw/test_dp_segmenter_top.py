"""``DPSegmenter`` (DP pipeline + segmenter) against the golden models, bit for bit: pixels in,
candidate lists out, compared with ``dptbd.model.fixed`` + ``segment_sequence``."""

import numpy as np
import pytest
from amaranth.hdl import Elaboratable, Fragment, Module
from amaranth.lib import wiring

from dptbd.hw.dp_core import DPCore
from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.state_store import StateStore
from dptbd.sim.scenarios import make_frames
from dptbd.sim.candidate_scoreboard import expected_lists
from helpers.hw_harness import event_counter, refused
from dptbd.model.fixed import run_fixed, saturation_counts
from dptbd.model.segmentation import segment_sequence
from dptbd.model.settings import SegmentSettings
from helpers.seg_harness import make_config, pack_frames, run_lists

CASES = {
    # name: (config, scenario, frames, seed, (valid, ready))
    "16x12-k3-table1": (dict(width=16, height=12, segment_frames=3, candidate_count=5,
                             histogram_bits=6, histogram_shift=1), "table1", 9, 1, (0.8, 0.6)),
    "8x6-k3-random": (dict(width=8, height=6, segment_frames=3, candidate_count=4,
                           histogram_bits=5), "random", 12, 2, (0.7, 0.5)),
    "7x6-r2-k2-half_up-cap": (dict(width=7, height=6, segment_frames=2, radius=2,
                                   rounding="half_up", candidate_count=3, candidate_capacity=5,
                                   histogram_bits=5, histogram_shift=4), "random", 9, 3, (0.8, 0.6)),
    "6x5-k1-random": (dict(width=6, height=5, segment_frames=1, candidate_count=3,
                           histogram_bits=4), "random", 5, 4, (0.9, 0.7)),
}


@pytest.mark.parametrize("name", list(CASES))
def test_matches_golden_model(name):
    kw, scenario, n_frames, seed, (valid, ready) = CASES[name]
    cfg = make_config(**kw)
    frames = make_frames(scenario, cfg, n_frames, seed=seed)
    lists = expected_lists(cfg, frames)
    dut = DPSegmenter(cfg)
    run_lists(cfg, dut, dut.pixels, dut.candidates, pack_frames(cfg, frames), lists,
              valid_probability=valid, ready_probability=ready, seed=n_frames)
    assert len(lists) == n_frames // cfg.segment_frames
    assert sum(lst.count for lst in lists) >= 7
    if "cap" in name:
        assert any(lst.overflow for lst in lists)


def schedule_driver(dut, cfg, schedule, rng):
    """Drive the settings ports: segment j's values when its first pixel is on offer, random
    values (also out of range) on every other pixel: only the first pixel's may count."""
    starts = {}
    frame = cfg.width * cfg.height
    word = 0
    for entry in schedule:
        starts[word] = entry
        word += entry.segment_frames * frame
    ports = (dut.segment_frames, dut.candidate_count, dut.histogram_shift)

    def drive(ctx, index):
        entry = starts.get(index)
        for port, name in zip(ports, ("segment_frames", "candidate_count", "histogram_shift")):
            value = getattr(entry, name) if entry else int(rng.integers(0, 1 << len(port)))
            ctx.set(port, value)
    return drive


def ref_scheduled(cfg, frames, schedule):
    """Lists and event counts of the golden model for a run-time schedule."""
    segments = run_fixed(frames, cfg, schedule)
    lists = segment_sequence(segments.energy.astype(np.int64), segments.direction, cfg, schedule)
    events = {"frame_done": len(frames), "segment_done": len(lists), "list_done": len(lists),
              "saturated": int(saturation_counts(frames, cfg, schedule).sum())}
    return lists, events


def rtl_scheduled(cfg, frames, schedule, lists, seed):
    dut = DPSegmenter(cfg)
    counts = {}
    run_lists(cfg, dut, dut.pixels, dut.candidates, pack_frames(cfg, frames), lists,
              valid_probability=0.8, ready_probability=0.6, seed=seed,
              on_cycle=schedule_driver(dut, cfg, schedule, np.random.default_rng(seed)),
              extra=[event_counter(dut.events, counts)])
    return counts


def test_run_time_k_n_s_and_events():
    """K, n and s changed between segments (written at a segment's first pixel, garbage on
    the others); every word and every event count equals the model's. B_E = 10 saturates
    at K = 5."""
    S = SegmentSettings
    cfg = make_config(width=8, height=6, segment_frames=2, max_segment_frames=5,
                      energy_bits=10, candidate_count=3, candidate_capacity=8,
                      histogram_bits=5)
    schedule = [S(2, 3, 0), S(3, 6, 4), S(1, 2, 5), S(5, 8, 5), S(2, 0, 3), S(4, 4, 5),
                S(1, 5, 2)]
    frames = make_frames("random", cfg, sum(e.segment_frames for e in schedule), seed=7)
    lists, events = ref_scheduled(cfg, frames, schedule)
    counts = rtl_scheduled(cfg, frames, schedule, lists, seed=7)
    assert counts == events
    assert events["saturated"] > 0 and len(lists) == len(schedule)
    assert sum(lst.count for lst in lists) >= 7


def test_one_pixel_per_clock_and_latency():
    """K >= 2, valid and ready high: no bubble; a record comes out L + 3 cycles after its
    pixel was accepted, the trailer one cycle after the frame's last pixel's record slot."""
    cfg = make_config(width=8, height=6, segment_frames=2, candidate_count=5,
                      histogram_bits=5, histogram_shift=4)
    frames = make_frames("random", cfg, 6, seed=3)
    lists = expected_lists(cfg, frames)
    dut = DPSegmenter(cfg)
    assert dut.latency == 14 + 3
    result = run_lists(cfg, dut, dut.pixels, dut.candidates, pack_frames(cfg, frames), lists)
    accepts = result.accept_cycles
    assert accepts == list(range(1, 1 + frames.size))
    frame = cfg.width * cfg.height
    expected_cycles = []
    for s, lst in enumerate(lists):
        base = (s * cfg.segment_frames + cfg.segment_frames - 1) * frame
        expected_cycles += [accepts[base + int(r["row"]) * cfg.width + int(r["col"])]
                            + dut.latency for r in lst.records]
        expected_cycles.append(accepts[base + frame - 1] + dut.latency + 1)
    assert sum(lst.count for lst in lists) >= 5
    assert result.output_cycles == expected_cycles


@pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")
def test_the_segmenter_top_refuses_a_family_configuration():
    cfg = make_config(width=8, height=8, recursive=True)
    with refused(Exception, match=(
            r"^the segmenter top \(dptbd\.hw\.dp_segmenter_top\) implements paper 001's "
            r"datapath only \(docs/arithmetic\.md §4-§5\), but this configuration sets paper "
            r"000's family field\(s\) recursive \(§8\): use "
            r"dptbd\.model\.family\.run_family_fixed$")):
        DPSegmenter(cfg)
    DPCore(cfg)._MustUse__silence = True   # the DP core itself builds it


class _WithStore(Elaboratable):
    """``DPSegmenter(external_state_store=True)`` with a :class:`StateStore` on its port."""

    def __init__(self, dut):
        self.dut = dut

    def elaborate(self, platform):
        m = Module()
        m.submodules.dut = self.dut
        m.submodules.store = store = StateStore(self.dut.config)
        wiring.connect(m, self.dut.state_store, store.bus)
        return m


@pytest.mark.parametrize("core_options", [None, {"line_buffer_style": "lutram",
                                                 "sideband_delay": "memory",
                                                 "max_tree": "split",
                                                 "state_store_style": "memory",
                                                 "histogram_style": "memory",
                                                 "control_style": "registered",
                                                 "output_queue_style": "one_hot",
                                                 "register_read": "two_level",
                                                 "credit_ready": "per_load",
                                                 "lut_write": "predecoded"}])
def test_external_state_store_and_core_options_keep_the_bits(core_options):
    """The store outside (the ``state_store`` member, here a StateStore on it) and DPCore's
    implementation options build the same lists; ``split`` adds its cycles to the latency."""
    kw, scenario, n_frames, seed, (valid, ready) = CASES["8x6-k3-random"]
    cfg = make_config(**kw)
    frames = make_frames(scenario, cfg, n_frames, seed=seed)
    lists = expected_lists(cfg, frames)
    dut = DPSegmenter(cfg, external_state_store=True, core_options=core_options)
    plain = DPSegmenter(cfg)
    Fragment.get(plain, None)                  # elaborated: no UnusedElaboratable warning
    assert dut.external_state_store and not plain.external_state_store
    assert dut.latency == plain.latency + (4 if core_options else 0)
    assert dut.core_options == (core_options or {"line_buffer_style": "bram",
                                                 "sideband_delay": "registers",
                                                 "max_tree": "compact",
                                                 "state_store_style": "memory",
                                                 "histogram_style": "memory",
                                                 "control_style": "generic",
                                                 "output_queue_style": "binary",
                                                 "register_read": "one_level",
                                                 "credit_ready": "one", "lut_write": "case"})
    run_lists(cfg, _WithStore(dut), dut.pixels, dut.candidates, pack_frames(cfg, frames),
              lists, valid_probability=valid, ready_probability=ready, seed=n_frames)
    assert sum(lst.count for lst in lists) >= 7
