"""The family's float counterpart and paper 000's float variants against the integer model
(``docs/arithmetic.md`` §8.9): equal wherever nothing rounds and nothing clamps."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.evaluation.detectors import merits, transitions, unified, unified_fixed
from dptbd.model.family import run_family_fixed
from dptbd.model.family.floating import run_family_float
from dptbd.scenes.synthetic import paper000_scenario
from helpers.model_strategies import SETTINGS

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


def lut_merit(table):
    """A :class:`merits.Merit` reading a table at the measurement (the pixel code itself)."""
    table = np.asarray(table, dtype=np.float64)
    return merits.Merit("lut", lambda z: table[z.astype(np.int64)], {})


@SETTINGS
@given(data=st.data(), radius=st.sampled_from([1, 2]), n_frames=st.integers(1, 5))
def test_integer_codes_equal_unified_datapath(data, radius, n_frames):
    """Eqs (24)-(25) with integer P and Q: run_unified (float, datapath form) = the model."""
    n_moves = (2 * radius + 1) ** 2
    penalty = data.draw(arrays(np.int64, (n_moves + 1, n_moves), elements=st.integers(0, 15)))
    merit = data.draw(arrays(np.int64, (16,), elements=st.integers(15, 200)))  # >= max penalty
    cfg = DPConfig(width=5, height=4, radius=radius, input_bits=4, energy_bits=12,
                   weights=plain_weights(radius), merit_codes=merit, penalty_codes=penalty,
                   segment_frames=n_frames)
    frames = data.draw(arrays(np.int64, (n_frames, 4, 5), elements=st.integers(0, 15)))
    ref = unified.run_unified(frames, lut_merit(merit), -penalty.astype(np.float64),
                              radius=radius, mode="datapath")
    got = run_family_fixed(frames, cfg)
    np.testing.assert_array_equal(got.energy[0], ref.value)
    np.testing.assert_array_equal(got.direction[0], ref.direction)
    flt = run_family_float(frames, cfg)
    np.testing.assert_array_equal(flt.energy[0], ref.value)


def test_likelihood_dp_on_paper000_scene_equals_unified_fixed():
    """000 §5.2 (6 dB, eqs (19)-(23)) quantised by ``quantise_unified``: the model with its
    LUTs is ``run_unified_fixed`` bit for bit over the 20 frames."""
    luts = unified_fixed.quantise_unified(merits.likelihood_difference_merit(2.0, 0.85, 1.0),
                                    transitions.velocity_log_penalty(2, 1.0), input_bits=8,
                                    gain=16, offset=128, scale=256)
    codes = paper000_scenario(6.0, seed=3).quantised(8, gain=16, offset=128)
    cfg = DPConfig(width=64, height=64, radius=2, weights=plain_weights(2), segment_frames=20,
                   merit_codes=luts.merit_codes, penalty_codes=luts.penalty_codes)
    want_e, want_d = unified_fixed.run_unified_fixed(codes, luts)
    got = run_family_fixed(codes, cfg)
    np.testing.assert_array_equal(got.energy[0], want_e)
    np.testing.assert_array_equal(got.direction[0], want_d)
    assert (cfg.merit_width, cfg.penalty_width) == (11, 8)


def test_float_merit_and_penalty_equal_unified_exactly():
    """Real (unquantised) S(z) and eq (22): ``run_family_float`` with alpha = 1 is
    ``run_unified(mode="datapath")`` exactly, on the codes' measurements z = (x - 128)/16."""
    merit = merits.likelihood_difference_merit(2.0, 0.85, 1.0)
    q = transitions.velocity_log_penalty(2, 1.0)
    codes = paper000_scenario(6.0, seed=1).quantised(8, gain=16, offset=128).astype(np.int64)
    z = (codes - 128) / 16.0
    cfg = DPConfig(width=64, height=64, radius=2, weights=plain_weights(2), segment_frames=20)
    table = merit((np.arange(256) - 128) / 16.0)
    got = run_family_float(codes, cfg, merit=table, penalty=-q)
    ref = unified.run_unified(z, merit, q, radius=2, mode="datapath")
    np.testing.assert_array_equal(got.energy[0], ref.value)
    np.testing.assert_array_equal(got.direction[0], ref.direction)


@SETTINGS
@given(data=st.data(), n_frames=st.integers(1, 5), recursive=st.booleans())
def test_integer_equals_float_when_alpha_is_exact_and_nothing_rounds(data, n_frames, recursive):
    """alpha = 1/2 (G = 1), merits and penalties multiples of 2**T, merit >= penalty: every
    product a * V is even, nothing clamps, so E equals the float recursion exactly."""
    scale = 1 << n_frames
    penalty = data.draw(arrays(np.int64, (10, 9), elements=st.integers(0, 7))) * scale
    merit = data.draw(arrays(np.int64, (4,), elements=st.integers(7, 60))) * scale
    cfg = DPConfig(width=4, height=3, input_bits=2, energy_bits=14, weights=plain_weights(1),
                   merit_codes=merit, penalty_codes=penalty, forgetting=0.5, forgetting_bits=1,
                   rounding=data.draw(st.sampled_from(["truncate", "half_up"])),
                   segment_frames=n_frames, recursive=recursive)
    frames = data.draw(arrays(np.int64, (n_frames, 3, 4), elements=st.integers(0, 3)))
    got, flt = run_family_fixed(frames, cfg), run_family_float(frames, cfg)
    np.testing.assert_array_equal(got.energy, flt.energy)
    np.testing.assert_array_equal(got.direction, flt.direction)


def test_float_refuses_a_bad_merit_table():
    cfg = DPConfig(width=3, height=3, input_bits=2)
    with pytest.raises(ValueError, match=r"^merit must be 4 finite reals \(one per 2-bit pixel "
                                         r"code\), got shape \(3,\)$"):
        run_family_float(np.zeros((4, 3, 3), dtype=np.int64), cfg, merit=[0.0, 1.0, 2.0])
