"""The P-pixel pipeline's implementation options (``DPPipelineWide``): each combination
of the structure's options bit for bit against the golden model in the Amaranth simulator,
the credit's copies cycle for cycle, the options it ignores netlist for netlist, and the
line buffer each style chooses."""

import functools

import numpy as np
import pytest
from amaranth.back import rtlil

from dptbd.hw.dp_core import CORE_OPTIONS
from dptbd.hw.wide import DPPipelineWide
from helpers.dp16kd_model import model_dp16kd_cells
from helpers.option_sets import option_params
from helpers.hw_harness import assert_states_equal, reference_states
from helpers.wide_harness import frames_to_beats, make_config, random_frames, run_beats


#: The implementation options the P-pixel pipeline builds: its structure's (every
#: combination simulated; the default suite every pair of values), the credit's copies and
#: the LUT's write decode (their blocks' own tests; here only in the set of every last
#: value). The others are the on-chip store's, the segmenter's, the P = 1 flags queue's and
#: the AXI top's, which it accepts and ignores
#: (``test_ignored_core_options_build_the_same_netlist``).
STRUCTURE_OPTIONS = ("line_buffer_style", "sideband_delay", "max_tree")
WIDE_OPTIONS = STRUCTURE_OPTIONS + ("credit_ready", "lut_write")
IGNORED_OPTIONS = tuple(name for name in CORE_OPTIONS if name not in WIDE_OPTIONS)
WIDE_OPTION_SETS = option_params(
    {name: CORE_OPTIONS[name] for name in STRUCTURE_OPTIONS},
    base={name: values[0] for name, values in CORE_OPTIONS.items()},
    last={name: values[-1] for name, values in CORE_OPTIONS.items()})


@pytest.mark.parametrize("options", WIDE_OPTION_SETS)
def test_core_options_change_nothing(monkeypatch, options):
    model_dp16kd_cells(monkeypatch)          # the DP16KD line buffer's block RAMs, modelled
    cfg = make_config(width=8, height=6, segment_frames=3, pixels_per_clock=2)
    dut = DPPipelineWide(cfg, **options)
    assert dut.core_options == options
    frames = random_frames(cfg, 5, seed=1)
    run = run_beats(dut, cfg, frames_to_beats(cfg, frames), valid_probability=0.8,
                    ready_probability=0.7, seed=2)
    assert_states_equal(run.outputs, reference_states(cfg, frames))



@pytest.mark.parametrize("p", [2, 4])
def test_ready_copied_per_load_keeps_every_cycle(p):
    """``credit_ready="per_load"``: the same handshakes in the same cycles as one register,
    under random input gaps and output back-pressure (the credit closing and opening)."""
    cfg = make_config(width=4 * p, height=6, segment_frames=2, pixels_per_clock=p)
    frames = random_frames(cfg, 4, seed=p)
    runs = [run_beats(DPPipelineWide(cfg, credit_ready=style), cfg, frames_to_beats(cfg, frames),
                      valid_probability=0.8, ready_probability=0.4, seed=3)
            for style in ("one", "per_load")]
    for run in runs:
        assert_states_equal(run.outputs, reference_states(cfg, frames))
    assert runs[1].accept_cycles == runs[0].accept_cycles
    assert runs[1].output_cycles == runs[0].output_cycles
    gaps = np.diff(runs[0].accept_cycles)
    assert gaps.max() > 1 and gaps.min() == 1


@pytest.mark.parametrize("name, value", [(name, value) for name in IGNORED_OPTIONS
                                         for value in CORE_OPTIONS[name][1:]])
def test_ignored_core_options_build_the_same_netlist(name, value):
    cfg = make_config(width=8, height=6, segment_frames=3, pixels_per_clock=2)
    assert rtlil.convert(DPPipelineWide(cfg, **{name: value})) == _default_netlist(cfg)


@functools.lru_cache(maxsize=None)
def _default_netlist(cfg) -> str:
    """The options' default build, converted once for every option above."""
    return rtlil.convert(DPPipelineWide(cfg))


@pytest.mark.parametrize("width, style, chosen", [
    (16, "lutram", ("distributed", True)), (12, "lutram", ("distributed", False)),
    (24, "bram", (None, False)), (12, "dp16kd", ("dp16kd", False))],
    ids=["4-beats", "3-beats", "6-beats-bram", "3-beats-dp16kd"])
def test_line_buffer_of_each_style(monkeypatch, width, style, chosen):
    """At P = 4 the LUT-RAM line buffer reads interleaved (as DPCore's) when a row has an
    even number of beats >= 4; the DP16KD one at 3 beats (the fewest a row has); bit for bit
    either way."""
    import dptbd.hw.dp_core.options as options

    model_dp16kd_cells(monkeypatch)
    made = []
    real = options.LineBuffer
    monkeypatch.setattr(options, "LineBuffer",
                        lambda *a, **k: made.append(k) or real(*a, **k))
    cfg = make_config(width=width, height=6, segment_frames=3, pixels_per_clock=4)
    dut = DPPipelineWide(cfg, line_buffer_style=style)
    frames = random_frames(cfg, 4, seed=width)
    run = run_beats(dut, cfg, frames_to_beats(cfg, frames), valid_probability=0.8,
                    ready_probability=0.7, seed=3)
    assert [(k["ram_style"], k["interleaved_read"]) for k in made] == [chosen]
    assert_states_equal(run.outputs, reference_states(cfg, frames))
