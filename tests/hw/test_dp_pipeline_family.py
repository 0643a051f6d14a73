"""Paper 000's DP family on the gateware against its golden model, bit for bit (§8).

Every variant of ``docs/arithmetic.md`` §8.9 streams whole small scenes through
``DPPipeline`` in the Amaranth simulator with random input gaps and output back-pressure;
every output word is compared with ``dptbd.model.family`` (``family_harness``) by the one
in-order checker ``assert_states_equal`` (first mismatching frame, row, column, field).
"""

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.model.family import run_family_fixed
from helpers.family_harness import (VARIANTS, family_reference_states, family_writes, likelihood_merit,
                            variant)
from helpers.hw_harness import assert_states_equal, frames_to_stream, run_stream

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


def make_config(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def random_frames(cfg, n_frames, seed):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                size=(n_frames, cfg.height, cfg.width))


def test_reference_is_the_golden_model():
    """The scoreboard's reference is ``run_family_fixed`` (no LUT writes)."""
    for name in ("likelihood-penalty-r1", "recursive-r1"):
        kw, n_frames = variant(name)
        cfg = make_config(**kw)
        frames = random_frames(cfg, n_frames, seed=3)
        out = run_family_fixed(frames, cfg)
        ref = family_reference_states(cfg, frames)
        ends = out.end_frames
        np.testing.assert_array_equal(ref[ends, ..., 0], out.energy)
        np.testing.assert_array_equal(ref[ends, ..., 1], out.direction)


@pytest.mark.parametrize("name", VARIANTS)
def test_matches_family_golden_model(name):
    kw, n_frames = variant(name)
    cfg = make_config(**kw)
    assert not cfg.is_paper001_datapath
    frames = random_frames(cfg, n_frames, seed=len(name))
    run = run_stream(DPPipeline(cfg), cfg, frames_to_stream(frames), valid_probability=0.75,
                     ready_probability=0.6, seed=n_frames)
    expected = family_reference_states(cfg, frames)
    assert_states_equal(run.outputs, expected)
    if "saturating" in name:
        assert (expected[..., 0] == cfg.e_max).any(), "the test must reach saturation"
    if cfg.merit_codes is not None and cfg.merit_code_array.min() < 0:
        assert (expected[..., 0] == 0).any(), "the test must reach the clamp at 0"


@pytest.mark.parametrize("family", ["ice40", "ecp5"])
@pytest.mark.parametrize("name", ["likelihood-penalty-r1", "forgetting-truncate-penalty",
                                  "recursive-r1"])
def test_family_core_options_are_bit_exact(name, family):
    """Every variant with the implementation options the flow builds for each FPGA family
    (``Family.core_options``: split max tree, side band in a block RAM ring buffer, line
    buffer in LUT RAM; the state store in an Amaranth memory): the same words."""
    from dptbd.hw.flow.family import get_family

    kw, n_frames = variant(name)
    cfg = make_config(**kw)
    frames = random_frames(cfg, n_frames, seed=7)
    # the DP16KD store (ECP5) has no simulation model: tests/hw/test_read_ahead_store.py
    options = {**get_family(family).core_options, "state_store_style": "memory"}
    run = run_stream(DPPipeline(cfg, **options), cfg, frames_to_stream(frames),
                     valid_probability=0.75, ready_probability=0.6, seed=11)
    assert_states_equal(run.outputs, family_reference_states(cfg, frames))


@pytest.mark.parametrize("radius", [1, 2])
def test_merit_and_penalty_luts_written_at_run_time(radius):
    """New merit and penalty codes through their write ports between frames and inside a
    frame; the pixels from the write on use them, the earlier ones do not."""
    kw, _ = variant("likelihood-penalty-r1" if radius == 1 else "amplitude-penalty-r2")
    cfg = make_config(**{**kw, "segment_frames": 3, "merit_codes": likelihood_merit(),
                         "merit_bits": 8, "penalty_bits": 5, "forgetting": 0.85})
    rng = np.random.default_rng(radius)
    merit = cfg.merit_code_array.copy()
    changed = rng.choice(256, size=48, replace=False)
    merit[changed] = rng.integers(-128, 128, size=48)
    penalty = cfg.penalty_code_array.copy()
    penalty[:, : cfg.n_moves // 2] = rng.integers(0, 32, size=(cfg.n_moves + 1, cfg.n_moves // 2))
    between = cfg.replace(merit_codes=merit)
    inside = between.replace(penalty_codes=penalty)
    pixels = cfg.width * cfg.height
    switch_between, switch_inside = pixels, 2 * pixels + 11
    frames = random_frames(cfg, 4, seed=radius + 20)
    run = run_stream(DPPipeline(cfg), cfg, frames_to_stream(frames), valid_probability=0.8,
                     ready_probability=0.7, seed=radius,
                     lut_writes={switch_between: family_writes(cfg, between),
                                 switch_inside: family_writes(between, inside)})
    expected = family_reference_states(cfg, frames, [(switch_between, between),
                                                     (switch_inside, inside)])
    assert_states_equal(run.outputs, expected)
    assert not np.array_equal(expected, family_reference_states(cfg, frames))


@pytest.mark.parametrize("name", ["amplitude-penalty-r1", "forgetting-truncate-penalty",
                                  "recursive-r2-truncate", "likelihood-r2"])
def test_latency_without_back_pressure(name):
    """Each result leaves exactly ``latency`` cycles after its pixel is accepted."""
    kw, _ = variant(name)
    cfg = make_config(**kw)
    dut = DPPipeline(cfg)
    frames = random_frames(cfg, 2, seed=1)
    run = run_stream(dut, cfg, frames_to_stream(frames))
    delays = {out - acc for acc, out in zip(run.accept_cycles, run.output_cycles)}
    assert delays == {dut.latency}
    assert run.cycles <= len(run.accept_cycles) + dut.latency + 2


def test_recursive_restarts_only_on_a_resync():
    """Recursive mode (§8.6): frames continue the recursion until an unexpected ``first``;
    the interrupted frame's pixels come out as recursion steps without end flags, and the
    frame that begins at the resync is a start frame again."""
    cfg = make_config(**variant("recursive-r1")[0])
    pixels = cfg.width * cfg.height
    before = random_frames(cfg, 3, seed=30)       # frames 0, 1 and an interrupted frame 2
    after = random_frames(cfg, 3, seed=31)
    cut = 7
    stream = frames_to_stream(before)[: 2 * pixels + cut] + frames_to_stream(after)
    run = run_stream(DPPipeline(cfg), cfg, stream, valid_probability=0.8,
                     ready_probability=0.7, seed=3)
    first = family_reference_states(cfg, before)
    second = family_reference_states(cfg, after)
    assert_states_equal(run.outputs[: 2 * pixels], first[:2])
    partial = first[2].reshape(-1, first.shape[-1])[:cut]
    assert [list(o.values()) for o in run.outputs[2 * pixels: 2 * pixels + cut]] == \
        partial.tolist()
    assert_states_equal(run.outputs[2 * pixels + cut:], second)
    assert second[0, ..., 1].max() == cfg.start_code       # a start frame after the resync
