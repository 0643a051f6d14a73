"""The campaign's runs of ``dptbd_dp --state-store axi`` (:mod:`dptbd.sim.campaign.store`):
whole scenes bit-exact on Verilator at every latency class with random AXI4 ready / valid,
error responses on the Amaranth simulator flagged and recovered from, the ``store`` bins."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
from helpers.refusals import whole
from helpers.verilator_harness import needs_verilator

from dptbd.sim import campaign
from dptbd.sim.campaign.store import (STORE_FAULTS, axi_store_cases, boundary_bursts,
                                      check_store_run, draw_error_window, draw_memory,
                                      draw_store_run, store_cases)
from dptbd.sim.coverage.bins import declared_store
from dptbd.sim.coverage.bins.store import (ERROR_BINS, LATENCY_CLASSES, OBSERVED,
                                           STALLED_CHANNELS, latency_class, store_bins)


def _short(case, frames, runs=1):
    """``case`` with fewer frames: the same parameter set, so the same build."""
    return dataclasses.replace(case, name=case.name + "-short", frames=frames, runs=runs)


def test_the_cases_are_two_verilator_builds_and_an_error_case():
    cases = store_cases()
    assert {c.design for c in cases} == {"dp_axi"}
    stores = [c.cfg.axi_store(**c.store) for c in cases]
    assert any(s.frame_bytes > 4096 for s in stores)          # bursts at 4 KB boundaries
    assert {s.data_bits for s in stores} == {32, 64} and 1 in {s.outstanding for s in stores}
    assert [c.faults for c in cases] == [(), (), ("read_error", "write_error")]


def test_consecutive_seeds_draw_every_latency_class_and_error():
    verilator, errors = store_cases()[0], store_cases()[2]
    plans = [draw_store_run(verilator, s) for s in range(4)]
    assert [latency_class(*p.latency) for p in plans] == [c[0] for c in LATENCY_CLASSES]
    assert max(p.latency[1] for p in plans) >= 500
    assert all(p.base % 32 == 0 and not p.errors for p in plans)
    assert draw_store_run(verilator, 7).notes == draw_store_run(verilator, 7).notes
    firsts = [draw_store_run(errors, s).errors[0] for s in range(4)]
    assert firsts == [("SLVERR", "read"), ("DECERR", "read"), ("SLVERR", "write"),
                      ("DECERR", "write")]


def test_a_latency_range_across_classes_is_refused():
    with pytest.raises(ValueError, match=whole(
            "latency range (50, 120) is not inside one class of [(0, 0), (1, 99), (100, 499), "
            "(500, 1000000000)]")):
        latency_class(50, 120)


def test_bursts_ending_at_a_4_kb_boundary():
    store = store_cases()[0].cfg.axi_store(**store_cases()[0].store)
    assert store.frame_bytes == 64 * 48 * 4                  # 32-bit slots: 3 pages
    assert boundary_bursts(store, 0, 2) == 2 * 3              # 4096, 8192, 12288 (the end)
    assert boundary_bursts(store, 32, 1) == 3                 # 4096, 8192, 12288
    small = store_cases()[1].cfg.axi_store(**store_cases()[1].store)
    assert small.frame_bytes == 40 * 24 * 4
    assert boundary_bursts(small, 0, 5) == 0
    assert boundary_bursts(small, 4096 - 32, 5) == 5          # 4096
    assert boundary_bursts(small, 4096 - 3840, 1) == 1        # the region ends at 4096


@needs_verilator
def test_whole_scenes_at_each_latency_class_are_bit_exact():
    """Seeds 0 … 3: read latency 0, 1 … 99, 100 … 499, 500 … 700 cycles; every run's bins."""
    case = _short(store_cases()[1], 4)
    outcomes = [check_store_run(case, seed) for seed in range(4)]
    assert [(o.passed, o.report) for o in outcomes] == [(True, "")] * 4
    assert all(o.words_out == 4 * 40 * 24 for o in outcomes)
    bins = campaign.CampaignResult((), tuple(outcomes), 0.0, 1).bins
    assert all(bins[f"store: {c[0]}"] > 0 for c in LATENCY_CLASSES)
    assert set(bins) == set(declared_store())


@needs_verilator
def test_a_wrong_word_is_reported_by_frame_row_column_and_field(monkeypatch):
    import dptbd.sim.scoreboard as scoreboard

    true_words = scoreboard.expected_words

    def off(cfg, frames):
        words = true_words(cfg, frames).copy()
        words[1, 2, 3] ^= np.uint64(1)                     # frame 1, row 2, col 3: E's bit 0
        return words

    monkeypatch.setattr(scoreboard, "expected_words", off)
    case = _short(store_cases()[1], 2)
    outcome = check_store_run(case, 0)
    assert not outcome.passed and sum(outcome.bins.values()) == 0
    assert re.fullmatch(r"first mismatch at output 1043: frame 1, row 2, col 3, field energy.*",
                        outcome.report), outcome.report


def test_error_responses_are_flagged_once_and_the_later_segments_are_exact():
    """Seeds 0 … 3 of the error case: SLVERR and DECERR on a read and on a write."""
    case = store_cases()[2]
    outcomes = [check_store_run(case, seed) for seed in range(4)]
    assert [(o.passed, o.report) for o in outcomes] == [(True, "")] * 4
    bins = campaign.CampaignResult((), tuple(outcomes), 0.0, 1).bins
    assert all(bins[f"store: {label}"] >= 1 for label in ERROR_BINS)


def test_an_error_that_is_not_flagged_fails_the_run(monkeypatch):
    """A memory that answers OKAY where the run injected an error: the run fails."""
    from dptbd.sim.axi4_memory import Axi4Memory

    monkeypatch.setattr(Axi4Memory, "resp", lambda self, addr, beats, direction="": 0)
    outcome = check_store_run(store_cases()[2], 0)              # SLVERR on a read
    assert not outcome.passed
    assert outcome.report == "read_error pulsed 0 times, expected 1"


def test_a_failed_run_fills_no_bin_and_a_passed_one_what_was_observed():
    plan = draw_store_run(store_cases()[0], 3)
    seen = dict(zip(OBSERVED, (5, 4, 1, 2, 3, 6, 7, 1, 2)))
    assert store_bins(plan, passed=False, observed=seen) == declared_store()
    hit = store_bins(plan, passed=True, observed=seen)
    assert hit["store: read latency 500 cycles or more"] == 5
    assert [hit[f"store: {label}"] for label in STALLED_CHANNELS] == [1, 2, 3, 6, 7]
    assert hit["store: read burst ending at a 4 KB boundary"] == 1
    assert hit["store: write burst ending at a 4 KB boundary"] == 2
    assert sum(hit.values()) == 5 + 1 + 2 + 3 + 6 + 7 + 1 + 2
    # nothing observed: only nothing
    assert sum(store_bins(plan, passed=True).values()) == 0


@needs_verilator
def test_the_memory_model_observes_stalls_and_4_kb_boundaries():
    """Case 0 (6 KB of state on a 32-bit bus): seed 1 draws random AXI ready and valid; its
    run's stalls on every channel and its bursts ending at 4 KB boundaries are counted by the
    memory model, the boundary bursts as many as the layout gives."""
    case = _short(store_cases()[0], 4)
    seed = next(s for s in range(40) if draw_store_run(case, s).axi_ready < 1
                and draw_store_run(case, s).axi_valid < 1 and draw_store_run(case, s).latency[1] < 100)
    plan = draw_store_run(case, seed)
    outcome = check_store_run(case, seed)
    assert (outcome.passed, outcome.report) == (True, "")
    want = boundary_bursts(case.cfg.axi_store(**case.store), plan.base, 4)
    assert want >= 4
    assert outcome.bins["store: read burst ending at a 4 KB boundary"] == want
    assert outcome.bins["store: write burst ending at a 4 KB boundary"] == want
    assert all(outcome.bins[f"store: {label}"] > 0 for label in STALLED_CHANNELS)


@needs_verilator
def test_a_boundary_count_other_than_the_layout_fails_the_run(monkeypatch):
    from dptbd.sim.campaign.store import dp_axi as store_module

    monkeypatch.setattr(store_module, "boundary_bursts", lambda store, base, frames: 99)
    case = _short(store_cases()[0], 2)
    outcome = check_store_run(case, 0)
    assert not outcome.passed and sum(outcome.bins.values()) == 0
    want = boundary_bursts(case.cfg.axi_store(**case.store), draw_store_run(case, 0).base, 2)
    assert outcome.report == (f"{want} read bursts ended at a 4 KB boundary, the layout gives "
                              f"99 … 198")


def test_the_axi_store_case_draws_the_axi_runs_resets_and_every_latency_class():
    from dptbd.sim.axi.runs import AXI_FAULTS, draw_run

    case = axi_store_cases()[0]
    assert case.design == "axi_store" and case in campaign.default_cases()
    assert set(case.faults) == set(AXI_FAULTS)
    assert {"aresetn", "soft_reset"} <= set(case.faults)
    memories = [draw_memory(s) for s in range(4)]
    assert [latency_class(*m.latency) for m in memories] == [c[0] for c in LATENCY_CLASSES]
    assert all(not m.errors for m in memories) and draw_memory(5) == draw_memory(5)
    assert memories[0].memory() == dict(latency=(0, 0), write_latency=(0, 0),
                                        axi_ready=memories[0].axi_ready,
                                        axi_valid=memories[0].axi_valid)
    # seed 0: aresetn with words and bursts in flight, and soft resets with words in flight
    assert draw_run(case, 0).drawn["aresetn_now"] >= 1
    assert draw_run(case, 0).drawn["soft_reset_now"] >= 1


def test_the_axi_store_runs_draw_refused_accesses_on_the_store_builds_map():
    """The refused bus accesses use the store build's register map: a STATE_BASE write not
    a multiple of the burst size and one above the highest base, refused (SLVERR); no
    access of the store's registers taken for unmapped; the checks read the store's
    registers (STATE_BASE_ACTIVE: the build's base, its error counters 0)."""
    from dptbd.hw.register_map import register_map
    from dptbd.sim.axi.actions import Drawer
    from dptbd.sim.axi.runs import draw_run
    from dptbd.sim.verilator.axi import SLVERR

    case = axi_store_cases()[0]
    store = case.cfg.axi_store(**case.store)
    regs = register_map(case.cfg, store)
    base, align = regs["STATE_BASE"], store.burst_bytes
    plans = [draw_run(case, s) for s in range(4)]
    drawn = {k: sum(p.drawn.get(k, 0) for p in plans)
             for k in ("state_base_unaligned", "state_base_range", "unmapped_read",
                       "unmapped_write")}
    assert all(drawn.values()), drawn
    ops = [op for p in plans for step in p.steps for op in step.get("bus", [])]
    writes = [op for op in ops if op[0] == "w" and op[1] == base.address]
    assert len(writes) == drawn["state_base_unaligned"] + drawn["state_base_range"]
    assert all(op[3] == 0xF and op[4] == SLVERR for op in writes)
    assert sum(op[2] % align != 0 and op[2] <= base.fields[0].limits[1]
               for op in writes) == drawn["state_base_unaligned"]
    store_addresses = {r.address for r in regs.registers if "STATE" in r.name}
    rng = np.random.default_rng(0)
    assert not store_addresses & set(Drawer(case.cfg, rng, {}, store=store).unmapped)
    assert store_addresses <= set(Drawer(case.cfg, rng, {}).unmapped)
    checks = [step["check"] for p in plans for step in p.steps if step.get("check")]
    assert all(c["STATE_BASE_ACTIVE"] == c["STATE_BASE"] == store.base_address
               and c["STATE_READ_ERRORS"] == 0 for c in checks if "STATE_BASE" in c)
    assert sum("STATE_BASE" in c for c in checks) > 0


@needs_verilator
def test_axi_store_runs_with_resets_pass_at_each_latency_class():
    """Seeds 0 … 3 of the dptbd_axi --state-store axi case: every candidate word, flag,
    response and counter as the model's, no AXI4 rule broken, across aresetn pulses with
    bursts in flight; the axi and store bins filled."""
    case = axi_store_cases()[0]
    outcomes = [campaign.check_run(case, seed) for seed in range(4)]
    assert [(o.passed, o.report) for o in outcomes] == [(True, "")] * 4
    bins = campaign.CampaignResult((), tuple(outcomes), 0.0, 1).bins
    assert all(bins[f"store: {c[0]}"] > 0 for c in LATENCY_CLASSES)
    assert all(bins[f"store: {label}"] > 0 for label in STALLED_CHANNELS)
    assert set(declared_store()) <= set(bins)
    assert any(k.startswith("soft reset:") and v for k, v in bins.items())
    # the refused accesses, judged on the store build's map
    assert bins["register: STATE_BASE value not aligned"] > 0
    assert bins["register: STATE_BASE value out of range"] > 0
    assert bins["register: unmapped read"] > 0


def test_the_error_window_opens_at_a_burst_of_its_direction():
    from dptbd.sim.campaign.store import ErrorWindow, window_cycles

    bursts = np.array([[10, 0, 0], [12, 1, 0], [30, 0, 32], [31, 1, 32], [50, 0, 64]])
    accepted = np.arange(0, 100, 2)                       # 50 pixels, one every 2 cycles
    write = ErrorWindow(("write",), 0.2, 2, 0.0, 0.0)     # after pixel 10: cycle 20
    assert window_cycles(write, bursts, accepted) == (31, 51)
    both = ErrorWindow(("read", "write"), 0.1, 1, 0.0, 0.0)   # after cycle 10
    assert window_cycles(both, bursts, accepted) == (10, 11)
    late = ErrorWindow(("read",), 0.6, 9, 0.0, 0.0)        # after cycle 60: none
    with pytest.raises(ValueError, match=whole("no read burst after cycle 60")):
        window_cycles(late, bursts, accepted)
    windows = [draw_error_window(axi_store_cases()[1], s) for s in range(6)]
    assert [(w.directions, w.response) for w in windows] == [
        (("read",), "SLVERR"), (("write",), "DECERR"), (("read", "write"), "SLVERR"),
        (("read",), "DECERR"), (("write",), "SLVERR"), (("read", "write"), "DECERR")]


@needs_verilator
def test_axi_store_slverr_and_decerr_windows_are_counted_flagged_and_recovered_from():
    """Seeds 0 … 2 of the error case (SLVERR on reads, DECERR on writes, SLVERR on both):
    every beat taken, every list sent, the counters equal to the errors the memory sent,
    the ERROR bits, and every list clear of the window the model's."""
    case = axi_store_cases()[1]
    assert case.design == "axi_store" and set(case.faults) == set(STORE_FAULTS)
    outcomes = [campaign.check_run(case, seed) for seed in range(3)]
    assert [(o.passed, o.report) for o in outcomes] == [(True, "")] * 3
    bins = campaign.CampaignResult((), tuple(outcomes), 0.0, 1).bins
    assert bins["store: SLVERR on a read, flagged, recovered"] == 2
    assert bins["store: SLVERR on a write, flagged, recovered"] == 1
    assert bins["store: DECERR on a write, flagged, recovered"] == 1
    assert bins["store: DECERR on a read, flagged, recovered"] == 0
    assert outcomes[1].notes[0].startswith("DECERR on write bursts taken in cycles")


@needs_verilator
def test_an_error_run_compares_the_lists_clear_of_the_window(monkeypatch):
    """With no margin around the window every list is compared: in seed 1 (DECERR on
    writes) list 3 is one the failed writes changed, and the run fails. (Most windows change
    no list: three candidates of 384 pixels rarely move; seeds 0 … 11 change one.)"""
    from dptbd.sim.campaign.store import axi_store as store_module

    case = axi_store_cases()[1]
    assert campaign.check_run(case, 1).passed
    monkeypatch.setattr(store_module, "error_margin", lambda store, latency: -10**9)
    outcome = campaign.check_run(case, 1)
    assert not outcome.passed and sum(outcome.bins.values()) == 0
    assert outcome.report == "seed 1: list 3 (a segment clear of the window) differs from " \
        "the model's"
