"""DPCore with an external state store: a Python model of a one-cycle synchronous SRAM."""

import itertools
import random

import numpy as np
import pytest
from amaranth.back import rtlil

from dptbd.config import DPConfig
from dptbd.hw.dp_core import CORE_OPTIONS, DPCore
from dptbd.hw.dp_pipeline import DPPipeline
from helpers.dp16kd_model import model_dp16kd_cells
from helpers.option_sets import option_params
from helpers.hw_harness import (assert_states_equal, frames_to_stream, reference_states, refused,
                        run_stream)
from helpers.refusals import whole

#: Every combination of DPCore's implementation options (the iCE40 and ECP5 flows' among
#: them); the default suite every pair of their values (``helpers.option_sets``).
# The on-chip store's DP16KD build is checked in tests/hw/test_read_ahead_store.py and the
# histogram, the control style and the register read are not in these blocks (the
# segmenter's and the AXI top's tests; the core builds the same netlist with each,
# `test_the_register_read_and_credit_options_build_the_same_core`); every other option is
# simulated, the DP16KD line buffer's block RAMs by a behavioural DP16KD: every combination,
# but the weight LUT's write decode (local to the LUT, `tests/hw/test_weight_lut.py` cycle for
# cycle against the case decode) only in the set of every last value.
SIMULATED = {**CORE_OPTIONS, "state_store_style": ("memory",), "histogram_style": ("memory",),
             "control_style": ("generic",), "register_read": ("one_level",),
             "credit_ready": ("one",)}
OPTION_SETS = option_params(
    {name: values for name, values in SIMULATED.items() if len(values) > 1 and name != "lut_write"},
    base={name: values[0] for name, values in SIMULATED.items()},
    last={name: values[-1] for name, values in SIMULATED.items()})


def sram_model(bus, words, seed):
    """Testbench process: read ``read_addr`` at each edge with ``read_en``, write likewise.

    ``read_data`` is garbage except in the cycle after a read, and the memory starts with
    random contents: the core must use neither.
    """
    rng = random.Random(seed)
    width = len(bus.read_data.as_value())
    contents = [rng.randrange(1 << width) for _ in range(words)]
    collisions = []

    async def process(ctx):
        async for _clk, _rst, read_en, read_addr, write_en, write_addr, write_data in ctx.tick().sample(
                bus.read_en, bus.read_addr, bus.write_en, bus.write_addr,
                bus.write_data.as_value()):
            if read_en and write_en and read_addr == write_addr:
                collisions.append(read_addr)
            data = contents[read_addr] if read_en else rng.randrange(1 << width)
            ctx.set(bus.read_data.as_value(), data)
            if write_en:
                contents[write_addr] = write_data

    return process, collisions


@pytest.mark.parametrize("style", ["bram", "logic"])
def test_external_store_matches_golden_model(style):
    cfg = DPConfig(width=6, height=5, segment_frames=3)
    dut = DPCore(cfg, lut_style=style)
    assert dut.lut_style == style
    frames = np.random.default_rng(21).integers(0, 256, size=(7, cfg.height, cfg.width))
    process, collisions = sram_model(dut.state_store, cfg.width * cfg.height, seed=3)
    run = run_stream(dut, cfg, frames_to_stream(frames), valid_probability=0.8,
                     ready_probability=0.7, seed=11, processes=[process])
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    assert collisions == []   # no read and write of one address in one cycle


@pytest.mark.parametrize("options", OPTION_SETS)
@pytest.mark.parametrize("kw, n_frames", [
    (dict(width=6, height=5, segment_frames=3), 5),
    (dict(width=7, height=6, segment_frames=2, radius=2, rounding="half_up"), 3),
])
def test_storage_options_are_bit_exact(monkeypatch, options, kw, n_frames):
    """Every storage option computes the golden model's bits with random gaps and stalls."""
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(**kw)
    dut = DPCore(cfg, **options)
    assert dut.core_options == options
    frames = np.random.default_rng(5).integers(0, 256, size=(n_frames, cfg.height, cfg.width))
    process, collisions = sram_model(dut.state_store, cfg.width * cfg.height, seed=4)
    run = run_stream(dut, cfg, frames_to_stream(frames), valid_probability=0.8,
                     ready_probability=0.7, seed=9, processes=[process])
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    assert collisions == []


def test_the_default_suite_holds_every_pair_of_option_values():
    """The option sets are every combination (with the set of every last value); those the
    default suite runs (not marked slow) hold every pair of values of every two options."""
    varied = [name for name, values in SIMULATED.items()
              if len(values) > 1 and name != "lut_write"]
    runs = [param.values[0] for param in OPTION_SETS]
    default = [options for options, param in zip(runs, OPTION_SETS) if not param.marks]
    combos = {tuple(options[name] for name in varied) for options in runs[:-1]}
    assert len(combos) == len(runs) - 1 == 24
    assert runs[-1] == {name: values[-1] for name, values in SIMULATED.items()}
    assert len(default) == 8 and not OPTION_SETS[-1].marks
    for a, b in itertools.combinations(varied, 2):
        assert {(o[a], o[b]) for o in default} == set(itertools.product(SIMULATED[a],
                                                                        SIMULATED[b]))


@pytest.mark.parametrize("options", OPTION_SETS)
def test_storage_options_keep_the_cycle_count(monkeypatch, options):
    """Valid and ready always high: no bubble; latency 14, or 14 + 4 with the split max
    tree (two stages for each of the ceil(log2 9) = 4 levels), whatever the line buffer."""
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(width=6, height=5, segment_frames=3)
    dut = DPPipeline(cfg, **options)
    latency = {"compact": 14, "split": 18}[options["max_tree"]]
    assert dut.core_options == options and dut.latency == latency
    assert dut.schedule.tree_levels == latency - 10
    frames = np.random.default_rng(3).integers(0, 256, size=(3, cfg.height, cfg.width))
    run = run_stream(dut, cfg, frames_to_stream(frames))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    total = 3 * cfg.width * cfg.height
    assert run.accept_cycles == list(range(1, 1 + total))
    assert run.output_cycles == list(range(1 + latency, 1 + latency + total))



@pytest.mark.parametrize("option", [dict(register_read="two_level"),
                                    dict(credit_ready="per_load")])
def test_the_register_read_and_credit_options_build_the_same_core(option):
    cfg = DPConfig(width=6, height=5, segment_frames=3)
    assert rtlil.convert(DPCore(cfg, **option)) == rtlil.convert(DPCore(cfg))

@pytest.mark.parametrize("option, bad, allowed", [
    ("line_buffer_style", "distributed", "('bram', 'lutram', 'dp16kd')"),
    ("sideband_delay", "bram", "('registers', 'memory')"),
    ("max_tree", "fast", "('compact', 'split')"),
    ("state_store_style", "lutram", "('memory', 'dp16kd')"),
    ("histogram_style", "distributed", "('memory', 'dp16kd')"),
    ("control_style", "fast", "('generic', 'registered')"),
    ("output_queue_style", "shift", "('binary', 'one_hot')"),
    ("register_read", "late", "('one_level', 'two_level')"),
    ("credit_ready", "many", "('one', 'per_load')"),
    ("lut_write", "table", "('case', 'predecoded')"),
])
def test_refuses_an_unknown_storage_option(option, bad, allowed):
    with refused(ValueError, whole(f"{option} must be one of {allowed}, got '{bad}'")):
        DPCore(DPConfig(width=6, height=5), **{option: bad})
